"""The component provider: descriptions, XPath search, and installing factories fetched over HTTP."""

from __future__ import annotations

import hashlib
import sys
import zipfile
from pathlib import Path

import pytest

from acordcs.runtime.repository import (
    ComponentRepository,
    FactoryHost,
    FactoryInstaller,
    FactoryServer,
    RepositoryError,
    parse_description,
)
from acordcs.vocabularies import PORT_KINDS, PORT_ROLES
from tests.support.services import free_port

PLAIN_PACKAGE = {
    "linefollower/__init__.py": "from .factory import make_factory\n",
    "linefollower/factory.py": (
        "from .steer import turn\n\n"
        "class Factory:\n"
        "    type_name = 'weblab.LineFollower'\n"
        "    def create(self, **config):\n"
        "        return {'turn': turn(config.get('offset', 0))}\n\n"
        "def make_factory():\n"
        "    return Factory()\n"
    ),
    "linefollower/steer.py": "VERSION = '{version}'\n\ndef turn(offset):\n    return -offset * 0.5\n",
}


def build_package(
    directory: Path, filename: str, files: dict[str, str], version: str = "1.0.0"
) -> Path:
    path = directory / filename
    with zipfile.ZipFile(path, "w") as archive:
        for name, text in files.items():
            archive.writestr(name, text.replace("{version}", version))
    return path


def describe(
    name: str, type_name: str, version: str, url: str, package: Path | None, entry: str, ports=()
) -> str:
    sha = hashlib.sha256(package.read_bytes()).hexdigest() if package else "0" * 64
    port_xml = "".join(f'<port name="{p}" kind="asynchronous" role="required"/>' for p in ports)
    return (
        f'<component name="{name}" type="{type_name}" version="{version}">{port_xml}'
        f'<factory location="{url}" sha256="{sha}" entry="{entry}"/></component>'
    )


class Registry:
    """The smallest real factory host: a dict of factories by type name."""

    def __init__(self) -> None:
        self.factories: dict[str, object] = {}

    def install_factory(self, factory: object) -> None:
        if factory.type_name in self.factories:
            raise ValueError(f"{factory.type_name} already installed")
        self.factories[factory.type_name] = factory

    def remove_factory(self, type_name: str) -> None:
        del self.factories[type_name]


@pytest.fixture
def packages(tmp_path: Path) -> Path:
    directory = tmp_path / "packages"
    directory.mkdir()
    return directory


@pytest.fixture
def server(packages: Path):
    with FactoryServer(packages) as srv:
        yield srv


@pytest.fixture
def workdir(tmp_path: Path) -> Path:
    return tmp_path / "installed"


def _nothing_installed(registry: Registry, workdir: Path, installer: FactoryInstaller) -> bool:
    leftovers = list(workdir.iterdir()) if workdir.exists() else []
    modules = [
        m for m in sys.modules if m.startswith("_acordcs_factory_") or m.startswith("linefollower")
    ]
    return not registry.factories and not leftovers and not installer.installed() and not modules


# -- descriptions and search ------------------------------------------------------------------------------
def test_search_by_xpath_returns_descriptions() -> None:
    repo = ComponentRepository()
    repo.add(
        describe(
            "LineFollower", "weblab.LineFollower", "1.9", "http://h/a.zip", None, "a:f", ["image"]
        )
    )
    repo.add(
        describe(
            "LineFollower", "weblab.LineFollower", "1.10", "http://h/b.zip", None, "a:f", ["image"]
        )
    )
    repo.add(
        describe("Locomotion", "weblab.Locomotion", "2.0", "http://h/c.zip", None, "c:f", ["speed"])
    )
    found = repo.search("//component[port/@name='image']")
    assert [(d.name, d.version) for d in found] == [
        ("LineFollower", "1.9"),
        ("LineFollower", "1.10"),
    ]
    # selecting nodes inside a description returns the description
    assert [d.name for d in repo.search("//port[@name='speed']/@kind")] == ["Locomotion"]
    assert repo.get("LineFollower").version == "1.10"  # numeric version order
    assert repo.search("//component[@type='nothing']") == []
    with pytest.raises(RepositoryError, match="yields a float"):
        repo.search("count(//component)")
    with pytest.raises(RepositoryError, match="syntax error"):
        repo.search("//component[")
    with pytest.raises(RepositoryError, match="already stored"):
        repo.add(describe("Locomotion", "weblab.Locomotion", "2.0", "http://h/c.zip", None, "c:f"))
    with pytest.raises(RepositoryError, match="known components: LineFollower, Locomotion"):
        repo.get("Vision")
    assert repo.remove("LineFollower") == 2 and len(repo) == 1


GOOD = '<component name="X" type="a.X" version="1.0"><factory location="http://h/x.zip" sha256="{sha}" entry="x:f"/></component>'


@pytest.mark.parametrize(
    ("document", "expected"),
    [
        ("<component", "not well-formed"),
        ('<thing name="X"/>', "not <component>"),
        (GOOD.replace(' name="X"', ""), "lacks the 'name' attribute"),
        (GOOD.replace('version="1.0"', 'version="one"'), "is not a version"),
        (GOOD.replace("{sha}", "abc"), "64 lowercase hex digits"),
        (GOOD.replace("http://h/x.zip", "file:///etc/passwd"), r"not an http\(s\) URL"),
        (GOOD.replace('entry="x:f"', 'entry="x"'), "module.path:attribute"),
        (GOOD.replace("<factory", "<extra/><factory"), "unexpected element <extra>"),
        ('<component name="X" type="a.X" version="1.0"/>', "no <factory> element"),
        (GOOD.replace("<factory", '<port name="p"/><port name="p"/><factory'), "described twice"),
        (GOOD.replace("<factory", '<port name="p" kind="telepathy"/><factory'), "unknown"),
        ('<!DOCTYPE component [<!ENTITY e SYSTEM "file:///etc/passwd">]>' + GOOD, "DOCTYPE"),
    ],
)
def test_malformed_description_is_a_clear_error_and_nothing_is_added(
    document: str, expected: str
) -> None:
    repo = ComponentRepository()
    with pytest.raises(RepositoryError, match=expected) as info:
        repo.add(document.replace("{sha}", "a" * 64), source="x.xml")
    assert info.value.file == "x.xml" and info.value.hint
    assert len(repo) == 0


def test_port_kinds_and_roles_are_the_metamodels() -> None:
    # "notification" is the paper's (RM-ODP's) name of the asynchronous kind, not a kind of its
    # own: no port of the runtime, the schema or the metamodel has it.
    for kind in PORT_KINDS:
        for role in PORT_ROLES:
            port = f'<port name="p" kind="{kind}" role="{role}"/>'
            text = GOOD.replace("{sha}", "a" * 64).replace("<factory", port + "<factory")
            assert parse_description(text).ports[0].kind == kind
    text = GOOD.replace("{sha}", "a" * 64).replace(
        "<factory", '<port name="p" kind="notification"/><factory'
    )
    with pytest.raises(
        RepositoryError, match="kind 'notification' / role 'provided' unknown"
    ) as info:
        parse_description(text, "d.xml")
    assert info.value.hint == (
        "kind is one of synchronous, asynchronous, stream (RM-ODP's request-reply, notification "
        "and flow), role one of provided, required"
    )


def test_description_error_names_the_line() -> None:
    text = GOOD.replace("{sha}", "a" * 64).replace(
        "<factory", '\n\n<port name="p" role="boss"/><factory'
    )
    with pytest.raises(RepositoryError) as info:
        parse_description(text, "lf.xml")
    assert info.value.line == 3 and str(info.value).startswith("lf.xml:3: error:")


# -- installing -----------------------------------------------------------------------------------------
def test_install_and_remove_with_isolated_import(
    packages: Path, server: FactoryServer, workdir: Path
) -> None:
    package = build_package(packages, "linefollower-1.0.0.zip", PLAIN_PACKAGE)
    repo = ComponentRepository()
    repo.add(
        describe(
            "LineFollower",
            "weblab.LineFollower",
            "1.0.0",
            server.url(package.name),
            package,
            "linefollower.factory:make_factory",
        )
    )
    installer = FactoryInstaller(repo, workdir=workdir, timeout=5)
    registry = Registry()
    assert isinstance(registry, FactoryHost)
    path_before = list(sys.path)
    installed = installer.install(registry, "LineFollower")
    factory = registry.factories["weblab.LineFollower"]
    assert factory is installed.factory and factory.create(offset=4) == {"turn": -2.0}
    assert sys.path == path_before and "linefollower" not in sys.modules
    assert installed.directory.is_dir() and installed.directory.parent == workdir
    assert installed.module_name in sys.modules
    installer.remove(registry, "weblab.LineFollower")
    assert _nothing_installed(registry, workdir, installer)
    with pytest.raises(RepositoryError, match="was not installed"):
        installer.remove(registry, "weblab.LineFollower")


def test_two_versions_side_by_side_do_not_share_modules(
    packages: Path, server: FactoryServer, workdir: Path
) -> None:
    repo = ComponentRepository()
    for version in ("1.0.0", "2.0.0"):
        package = build_package(packages, f"lf-{version}.zip", PLAIN_PACKAGE, version)
        repo.add(
            describe(
                "LineFollower",
                "weblab.LineFollower",
                version,
                server.url(package.name),
                package,
                "linefollower:make_factory",
            )
        )
    installer = FactoryInstaller(repo, workdir=workdir)
    old, new = Registry(), Registry()
    a = installer.install(old, "LineFollower", "1.0.0")
    b = installer.install(new, "LineFollower")
    assert sys.modules[a.module_name + ".steer"].VERSION == "1.0.0"
    assert sys.modules[b.module_name + ".steer"].VERSION == "2.0.0"
    installer.remove(old, "weblab.LineFollower")
    installer.remove(new, "weblab.LineFollower")
    assert _nothing_installed(old, workdir, installer) and not new.factories


def test_hash_mismatch_installs_nothing(
    packages: Path, server: FactoryServer, workdir: Path
) -> None:
    package = build_package(packages, "lf.zip", PLAIN_PACKAGE)
    repo = ComponentRepository()
    repo.add(
        describe(
            "LineFollower",
            "weblab.LineFollower",
            "1.0.0",
            server.url("lf.zip"),
            package,
            "linefollower:make_factory",
        )
    )
    build_package(
        packages, "lf.zip", {**PLAIN_PACKAGE, "linefollower/steer.py": "import os\n"}
    )  # tampered
    installer, registry = FactoryInstaller(repo, workdir=workdir), Registry()
    with pytest.raises(RepositoryError, match=r"has sha256 .* but the description says") as info:
        installer.install(registry, "LineFollower")
    assert "not installed" in info.value.hint
    assert _nothing_installed(registry, workdir, installer)


def test_unreachable_server_installs_nothing(tmp_path: Path, workdir: Path) -> None:
    package = build_package(tmp_path, "lf.zip", PLAIN_PACKAGE)
    url = f"http://127.0.0.1:{free_port()}/lf.zip"  # nothing listens there
    repo = ComponentRepository()
    repo.add(
        describe(
            "LineFollower",
            "weblab.LineFollower",
            "1.0.0",
            url,
            package,
            "linefollower:make_factory",
        )
    )
    installer, registry = FactoryInstaller(repo, workdir=workdir, timeout=2), Registry()
    with pytest.raises(RepositoryError, match="cannot download") as info:
        installer.install(registry, "LineFollower")
    assert "HTTP server is running" in info.value.hint
    assert _nothing_installed(registry, workdir, installer)


def test_missing_package_is_an_http_error(
    server: FactoryServer, workdir: Path, tmp_path: Path
) -> None:
    package = build_package(tmp_path, "lf.zip", PLAIN_PACKAGE)
    repo = ComponentRepository()
    repo.add(
        describe(
            "LineFollower",
            "weblab.LineFollower",
            "1.0.0",
            server.url("gone.zip"),
            package,
            "linefollower:make_factory",
        )
    )
    installer, registry = FactoryInstaller(repo, workdir=workdir), Registry()
    with pytest.raises(RepositoryError, match="HTTP 404"):
        installer.install(registry, "LineFollower")
    assert _nothing_installed(registry, workdir, installer)


@pytest.mark.parametrize(
    ("files", "entry", "expected"),
    [
        ({"../evil.py": "x = 1\n", **PLAIN_PACKAGE}, "linefollower:make_factory", "unsafe entry"),
        ({"/abs.py": "x = 1\n"}, "abs:f", "unsafe entry"),
        (
            {"linefollower/__init__.py": "raise ImportError('broken package')\n"},
            "linefollower:f",
            "broken package",
        ),
        (
            {"linefollower/__init__.py": "import linefollower.steer\n"},
            "linefollower:f",
            "relative imports",
        ),
        ({"other/__init__.py": ""}, "linefollower:make_factory", "has no module 'linefollower'"),
        ({"lf.py": "make = 42\n"}, "lf:make", "neither a factory"),
        (
            {"lf.py": "class F:\n    type_name = 'weblab.Other'\n\ndef make():\n    return F()\n"},
            "lf:make",
            "builds type 'weblab.Other'",
        ),
        (
            {"lf.py": "def make():\n    raise RuntimeError('no')\n"},
            "lf:make",
            "raised RuntimeError",
        ),
    ],
)
def test_bad_packages_install_nothing(
    packages: Path, server: FactoryServer, workdir: Path, files: dict, entry: str, expected: str
) -> None:
    package = build_package(packages, "bad.zip", files)
    repo = ComponentRepository()
    repo.add(describe("Bad", "weblab.LineFollower", "1.0", server.url("bad.zip"), package, entry))
    installer, registry = FactoryInstaller(repo, workdir=workdir), Registry()
    with pytest.raises(RepositoryError, match=expected):
        installer.install(registry, "Bad")
    assert _nothing_installed(registry, workdir, installer)
    assert not (packages.parent / "evil.py").exists() and not (workdir.parent / "evil.py").exists()


def test_not_a_zip_installs_nothing(packages: Path, server: FactoryServer, workdir: Path) -> None:
    junk = packages / "junk.zip"
    junk.write_bytes(b"this is not a zip archive")
    repo = ComponentRepository()
    repo.add(describe("Junk", "weblab.Junk", "1.0", server.url("junk.zip"), junk, "j:f"))
    installer, registry = FactoryInstaller(repo, workdir=workdir), Registry()
    with pytest.raises(RepositoryError, match="not a wheel or zip"):
        installer.install(registry, "Junk")
    assert _nothing_installed(registry, workdir, installer)


def test_host_refusing_the_factory_leaves_nothing(
    packages: Path, server: FactoryServer, workdir: Path
) -> None:
    package = build_package(packages, "lf.zip", PLAIN_PACKAGE)
    repo = ComponentRepository()
    repo.add(
        describe(
            "LineFollower",
            "weblab.LineFollower",
            "1.0.0",
            server.url("lf.zip"),
            package,
            "linefollower:make_factory",
        )
    )
    registry = Registry()
    registry.factories["weblab.LineFollower"] = object()  # installed by someone else
    installer = FactoryInstaller(repo, workdir=workdir)
    with pytest.raises(ValueError, match="already installed"):
        installer.install(registry, "LineFollower")
    del registry.factories["weblab.LineFollower"]
    assert _nothing_installed(registry, workdir, installer)
    with pytest.raises(RepositoryError, match="cannot host factories"):
        installer.install(object(), "LineFollower")


def test_a_trickling_server_cannot_hold_an_install_past_its_deadline(
    tmp_path: Path, workdir: Path
) -> None:
    """A server sending one byte every 0.5 s (each read within the timeout) for at most 30 s."""
    import socket
    import threading

    listener = socket.create_server(("127.0.0.1", 0))
    listener.settimeout(10)
    stop = threading.Event()

    def trickle() -> None:
        try:
            conn, _ = listener.accept()
        except OSError:
            return
        with conn:
            conn.recv(4096)
            body = b"HTTP/1.0 200 OK\r\nContent-Length: 100000\r\n\r\n" + b"x" * 100000
            for byte in body[:60]:
                if stop.wait(0.5):
                    return
                try:
                    conn.sendall(bytes([byte]))
                except OSError:
                    return

    thread = threading.Thread(target=trickle, daemon=True)
    thread.start()
    package = build_package(tmp_path, "lf.zip", PLAIN_PACKAGE)
    url = f"http://127.0.0.1:{listener.getsockname()[1]}/lf.zip"
    repo = ComponentRepository()
    repo.add(describe("LineFollower", "weblab.LineFollower", "1.0.0", url, package,
                      "linefollower:make_factory"))  # fmt: skip
    installer = FactoryInstaller(repo, workdir=workdir, timeout=2, deadline=3)
    registry = Registry()
    try:
        with pytest.raises(RepositoryError, match="deadline of 3 s") as info:
            installer.install(registry, "LineFollower")
        assert "deadline" in info.value.hint
        assert _nothing_installed(registry, workdir, installer)
    finally:
        stop.set()
        listener.close()
        thread.join(timeout=5)


@pytest.mark.parametrize(
    ("init", "expected"),
    [
        ("import sys\nsys.exit(3)\n", "ended the process with exit 3"),
        ("import sys\nsys.exit(0)\n", "ended the process"),
        ("while True:\n    pass\n", "did not finish within 3 s"),
        (
            "import hashlib\n"
            "hashlib.sha256 = lambda data=b'': type('H', (), {'hexdigest': lambda s: '0' * 64})()\n"
            "raise ImportError('half-installed')\n",
            "half-installed",
        ),
    ],
)
def test_a_hostile_import_is_tried_in_a_child_and_leaves_this_process_alone(
    packages: Path, server: FactoryServer, workdir: Path, init: str, expected: str
) -> None:
    sha256 = hashlib.sha256
    package = build_package(packages, "bad.zip", {"lf/__init__.py": init})
    repo = ComponentRepository()
    repo.add(describe("Bad", "weblab.LineFollower", "1.0", server.url("bad.zip"), package, "lf:f"))
    installer, registry = FactoryInstaller(repo, workdir=workdir, import_deadline=3), Registry()
    with pytest.raises(RepositoryError, match=expected):
        installer.install(registry, "Bad")
    assert hashlib.sha256 is sha256  # the patch never ran here
    assert _nothing_installed(registry, workdir, installer)
    # and the next, tampered, package is still refused
    tampered = build_package(packages, "lf.zip", PLAIN_PACKAGE)
    repo.add(describe("LF", "weblab.LineFollower", "1.0", server.url("lf.zip"), tampered, "lf:f"))
    tampered.write_bytes(tampered.read_bytes() + b"tampered")
    with pytest.raises(RepositoryError, match="has sha256"):
        installer.install(registry, "LF")


def test_installed_directories_are_deleted_when_the_process_exits(tmp_path: Path) -> None:
    package = build_package(tmp_path, "lf.zip", PLAIN_PACKAGE)
    workdir = tmp_path / "installed"
    script = f"""
import sys
sys.path[:0] = {[str(Path(__file__).parents[2] / "src"), str(Path(__file__).parents[2])]!r}
from pathlib import Path
from acordcs.runtime.repository import ComponentRepository, FactoryInstaller, FactoryServer
from tests.runtime.test_repository_provider import Registry, describe
with FactoryServer(Path({str(tmp_path)!r})) as server:
    repo = ComponentRepository()
    package = Path({str(package)!r})
    repo.add(describe("LF", "weblab.LineFollower", "1.0", server.url("lf.zip"), package,
                      "linefollower:make_factory"))
    installed = FactoryInstaller(repo, workdir={str(workdir)!r}).install(Registry(), "LF")
    print(installed.directory.is_dir())
"""
    import subprocess

    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60
    )
    assert done.stdout.strip() == "True", done.stderr
    assert workdir.is_dir() and list(workdir.iterdir()) == []
