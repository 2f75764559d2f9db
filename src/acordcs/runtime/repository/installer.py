"""Installing component factories found through the component provider into a container.

``install``: download the package (urllib, with a per-read timeout, an overall deadline and a size
limit: :mod:`.fetch`), verify its sha256
against the description, unpack it (wheel or zip; no absolute paths, no ``..``, no links, bounded
size) into a private directory, import it under a unique module name without touching ``sys.path``,
resolve the entry to a factory and hand it to the container. Any failure leaves nothing behind.
``remove`` takes the factory out of the container, forgets the modules and deletes the directory.

The sha256 is checked before any package code runs; the import is first tried in a child process
with a deadline (:mod:`.vetting`), so a package that exits, hangs or fails there is refused without
touching this process; directories still installed are deleted when the process exits.

Packages are imported by path, so they must refer to their own modules with relative imports
(``from .component import LineFollower``): their top-level name is not importable.
"""

from __future__ import annotations

import atexit
import hashlib
import importlib
import importlib.util
import io
import itertools
import logging
import re
import shutil
import stat
import sys
import tempfile
import threading
import urllib.error
import zipfile
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Any, Protocol, runtime_checkable

from acordcs.runtime.repository.catalog import ComponentRepository
from acordcs.runtime.repository.description import ComponentDescription
from acordcs.runtime.repository.errors import RepositoryError
from acordcs.runtime.repository.fetch import DeadlineExceeded, fetch
from acordcs.runtime.repository.vetting import vet_import

log = logging.getLogger("acordcs.runtime.repository")

_unique = itertools.count(1)
# Bound now: a package imported later cannot change what verifies the next one.
_sha256 = hashlib.sha256
_directories: set[Path] = set()  # unpacked and not yet removed: deleted at exit


@atexit.register
def _clean_up_at_exit() -> None:
    for directory in list(_directories):
        shutil.rmtree(directory, ignore_errors=True)


@runtime_checkable
class FactoryHost(Protocol):
    """What the installer needs from a container (``acordcs.runtime.container.Container`` is one)."""

    def install_factory(self, factory: Any) -> None: ...

    def remove_factory(self, type_name: str) -> None: ...


@dataclass
class InstalledFactory:
    description: ComponentDescription
    factory: Any
    host: FactoryHost
    directory: Path
    module_name: str


class FactoryInstaller:
    """Installs factories described in ``repository`` into containers, and removes them."""

    def __init__(
        self,
        repository: ComponentRepository,
        *,
        workdir: str | Path | None = None,
        timeout: float = 10.0,
        deadline: float = 120.0,
        max_download_bytes: int = 50 * 1024 * 1024,
        max_unpacked_bytes: int = 200 * 1024 * 1024,
        max_files: int = 2000,
        import_deadline: float | None = 30.0,
    ) -> None:
        self.repository = repository
        self.workdir = Path(workdir) if workdir is not None else None
        self.timeout = timeout
        self.deadline = deadline  # seconds for a whole download, however the server paces it
        self.max_download_bytes = max_download_bytes
        self.max_unpacked_bytes = max_unpacked_bytes
        self.max_files = max_files
        # seconds for the trial import in a child process; None: no trial (trusted packages)
        self.import_deadline = import_deadline
        self._lock = threading.Lock()
        self._installed: dict[tuple[int, str], InstalledFactory] = {}

    # -- public API -----------------------------------------------------------------------------------
    def install(self, host: FactoryHost, name: str, version: str | None = None) -> InstalledFactory:
        """Install component ``name`` (its highest version unless given) into ``host``."""
        return self.install_description(host, self.repository.get(name, version))

    def install_description(
        self, host: FactoryHost, description: ComponentDescription
    ) -> InstalledFactory:
        if not isinstance(host, FactoryHost):
            raise RepositoryError(
                f"{type(host).__name__} cannot host factories",
                element="installer",
                hint="pass a container (an object with install_factory/remove_factory)",
            )
        key = (id(host), description.type)
        with self._lock:
            if key in self._installed:
                raise RepositoryError(
                    f"component type {description.type!r} is already installed in {host!r} by this installer",
                    file=description.source,
                    hint="remove() it first to install another version",
                )
        data = self.download(description)
        directory = self._unpack(description, data)
        module_name = (
            f"_acordcs_factory_{next(_unique)}_{re.sub(r'[^A-Za-z0-9_]', '_', description.name)}"
        )
        _directories.add(directory)
        try:
            factory = self._load(description, directory, module_name)
            host.install_factory(factory)
        except BaseException:
            _forget_modules(module_name)
            shutil.rmtree(directory, ignore_errors=True)
            _directories.discard(directory)
            raise
        installed = InstalledFactory(description, factory, host, directory, module_name)
        with self._lock:
            self._installed[key] = installed
        log.info(
            "installed %s %s (%s) from %s",
            description.name,
            description.version,
            description.type,
            description.location,
        )
        return installed

    def remove(self, host: FactoryHost, type_name: str) -> ComponentDescription:
        """Remove the factory of ``type_name`` from ``host`` and delete what ``install`` left on disk."""
        with self._lock:
            installed = self._installed.get((id(host), type_name))
        if installed is None:
            raise RepositoryError(
                f"component type {type_name!r} was not installed in {host!r} by this installer",
                element="installer",
                hint="remove factories you installed yourself with the container's remove_factory()",
            )
        host.remove_factory(type_name)
        with self._lock:
            del self._installed[(id(host), type_name)]
        _forget_modules(installed.module_name)
        shutil.rmtree(installed.directory, ignore_errors=True)
        _directories.discard(installed.directory)
        return installed.description

    def installed(self) -> list[InstalledFactory]:
        with self._lock:
            return list(self._installed.values())

    # -- steps ----------------------------------------------------------------------------------------
    def download(self, description: ComponentDescription) -> bytes:
        """The package bytes, verified against the description's sha256."""
        url = description.location
        where = f"{description.name} {description.version}"
        try:
            # http(s) only: checked when the description was parsed
            data = fetch(
                url,
                timeout=self.timeout,
                deadline=self.deadline,
                max_bytes=self.max_download_bytes,
            )
        except DeadlineExceeded as err:
            raise RepositoryError(
                f"factory package of {where}: download of {url} {err}",
                file=description.source,
                hint="the server is too slow (or stalling on purpose); raise the installer's "
                "deadline if the package is large and the link slow",
            ) from None
        except urllib.error.HTTPError as err:
            raise RepositoryError(
                f"factory package of {where}: HTTP {err.code} {err.reason} from {url}",
                file=description.source,
                hint="check the description's location and that the package is on the server",
            ) from None
        except (urllib.error.URLError, OSError, ValueError) as err:
            reason = getattr(err, "reason", err)
            raise RepositoryError(
                f"factory package of {where}: cannot download {url}: {reason}",
                file=description.source,
                hint="check that the HTTP server is running and reachable from this machine",
            ) from None
        if len(data) > self.max_download_bytes:
            raise RepositoryError(
                f"factory package of {where} at {url} is larger than {self.max_download_bytes} bytes",
                file=description.source,
                hint="raise max_download_bytes if the package really is that large",
            )
        digest = _sha256(data).hexdigest()
        if digest != description.sha256:
            raise RepositoryError(
                f"factory package of {where} at {url} has sha256 {digest}, "
                f"but the description says {description.sha256}",
                file=description.source,
                hint="the package was changed or corrupted: not installed; publish a matching description",
            )
        return data

    def _unpack(self, description: ComponentDescription, data: bytes) -> Path:
        fail_where = f"factory package of {description.name} {description.version}"
        try:
            archive = zipfile.ZipFile(io.BytesIO(data))
        except zipfile.BadZipFile:
            raise RepositoryError(
                f"{fail_where} is not a wheel or zip archive",
                file=description.source,
                hint="serve a .whl or .zip",
            ) from None
        members = archive.infolist()
        total = sum(m.file_size for m in members)
        if len(members) > self.max_files or total > self.max_unpacked_bytes:
            raise RepositoryError(
                f"{fail_where} unpacks to {len(members)} files / {total} bytes, over the limits",
                file=description.source,
                hint="raise max_files / max_unpacked_bytes if that is intended",
            )
        for member in members:
            path = PurePosixPath(member.filename)
            is_link = stat.S_ISLNK(member.external_attr >> 16)
            if (
                path.is_absolute()
                or ".." in path.parts
                or ":" in member.filename
                or "\\" in member.filename
                or is_link
            ):
                raise RepositoryError(
                    f"{fail_where} contains the unsafe entry {member.filename!r}",
                    file=description.source,
                    hint="packages may only contain relative paths inside the archive",
                )
        if self.workdir is not None:
            self.workdir.mkdir(parents=True, exist_ok=True)
        directory = Path(tempfile.mkdtemp(prefix=f"acordcs-{description.name}-", dir=self.workdir))
        try:
            archive.extractall(directory)
        except (OSError, zipfile.BadZipFile, RuntimeError) as err:
            shutil.rmtree(directory, ignore_errors=True)
            raise RepositoryError(
                f"{fail_where} cannot be unpacked: {err}",
                file=description.source,
                hint="rebuild the package",
            ) from None
        return directory

    def _load(self, description: ComponentDescription, directory: Path, alias: str) -> Any:
        module_path, attribute = description.entry.split(":")
        top, _, rest = module_path.partition(".")
        package_dir, module_file = directory / top, directory / f"{top}.py"
        fail = f"factory package of {description.name} {description.version}"
        if (package_dir / "__init__.py").is_file():
            spec = importlib.util.spec_from_file_location(
                alias, package_dir / "__init__.py", submodule_search_locations=[str(package_dir)]
            )
        elif module_file.is_file() and not rest:
            spec = importlib.util.spec_from_file_location(alias, module_file)
        else:
            raise RepositoryError(
                f"{fail} has no module {top!r} (entry {description.entry!r})",
                file=description.source,
                hint=f"the archive must contain {top}/__init__.py or {top}.py at its top level",
            )
        if self.import_deadline is not None:
            problem = vet_import(directory, description.entry, self.import_deadline)
            if problem is not None:
                raise RepositoryError(
                    f"{fail}: {problem}",
                    file=description.source,
                    hint="packages must use relative imports for their own modules; fix the "
                    "package (it was tried in a child process, not imported here)",
                )
        try:
            module = importlib.util.module_from_spec(spec)
            sys.modules[alias] = module
            spec.loader.exec_module(module)
            if rest:
                module = importlib.import_module(f"{alias}.{rest}")
            target = getattr(module, attribute)
        except (Exception, SystemExit) as err:  # SystemExit: sys.exit() at import
            raise RepositoryError(
                f"{fail}: importing entry {description.entry!r} failed: {type(err).__name__}: {err}",
                file=description.source,
                hint="packages must use relative imports for their own modules; fix the package",
            ) from None
        return self._factory(description, target)

    def _factory(self, description: ComponentDescription, target: Any) -> Any:
        fail = f"entry {description.entry!r} of {description.name} {description.version}"
        if isinstance(target, type) and not hasattr(target, "type_name"):
            from acordcs.runtime.component import ComponentFactory, CtxComponent

            if issubclass(target, CtxComponent):
                target = ComponentFactory(description.type, target)
        elif not hasattr(target, "type_name") and callable(target):
            try:
                target = target()
            except (Exception, SystemExit) as err:
                raise RepositoryError(
                    f"{fail} raised {type(err).__name__}: {err}",
                    file=description.source,
                    hint="fix the package",
                ) from None
        type_name = getattr(target, "type_name", None)
        if type_name is None:
            raise RepositoryError(
                f"{fail} is neither a factory, a component class, nor a function returning a factory",
                file=description.source,
                hint="point entry at e.g. a make_factory() returning ComponentFactory(type, cls)",
            )
        if type_name != description.type:
            raise RepositoryError(
                f"{fail} builds type {type_name!r}, but the description says {description.type!r}",
                file=description.source,
                hint="make the description's type and the factory's type_name agree",
            )
        declared = getattr(getattr(target, "cls", None), "ports", None)
        if declared and description.ports:
            actual = {getattr(p, "name", None) for p in declared}
            described = {p.name for p in description.ports}
            if actual != described:
                raise RepositoryError(
                    f"{fail}: the component's ports {sorted(actual)} differ from the described {sorted(described)}",
                    file=description.source,
                    hint="update the description's <port> elements",
                )
        return target


def _forget_modules(alias: str) -> None:
    for name in [n for n in sys.modules if n == alias or n.startswith(alias + ".")]:
        del sys.modules[name]
