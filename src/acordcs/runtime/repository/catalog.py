"""The component provider's repository of descriptions, searched with XPath."""

from __future__ import annotations

import threading

from lxml import etree

from acordcs.runtime.context.errors import SubscriptionError
from acordcs.runtime.context.xpathexpr import compile_expression
from acordcs.runtime.repository.description import ComponentDescription, parse_description
from acordcs.runtime.repository.errors import RepositoryError


class ComponentRepository:
    """Descriptions keyed by (name, version). ``search`` evaluates XPath over
    ``<components><component .../>...</components>`` and returns the components it selects or
    selects nodes within."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._items: dict[tuple[str, str], ComponentDescription] = {}
        self._catalog: etree._ElementTree | None = None
        self._owners: dict[etree._Element, ComponentDescription] = {}

    def __len__(self) -> int:
        with self._lock:
            return len(self._items)

    def add(
        self,
        description: ComponentDescription | str | bytes,
        *,
        source: str | None = None,
        replace: bool = False,
    ) -> ComponentDescription:
        """Store a description (XML or parsed). Raises :class:`RepositoryError` if malformed or present."""
        if not isinstance(description, ComponentDescription):
            description = parse_description(description, source or "<description>")
        key = (description.name, description.version)
        with self._lock:
            if key in self._items and not replace:
                raise RepositoryError(
                    f"component {description.name!r} version {description.version} is already stored",
                    file=description.source,
                    hint="bump the version, or add(..., replace=True)",
                )
            self._items[key] = description
            self._catalog = None
        return description

    def remove(self, name: str, version: str | None = None) -> int:
        """Remove a description (every version if ``version`` is None). Returns how many."""
        with self._lock:
            keys = [k for k in self._items if k[0] == name and (version is None or k[1] == version)]
            for key in keys:
                del self._items[key]
            self._catalog = None
        return len(keys)

    def get(self, name: str, version: str | None = None) -> ComponentDescription:
        """The description of ``name`` (its highest version unless ``version`` is given)."""
        with self._lock:
            found = [
                d
                for (n, v), d in self._items.items()
                if n == name and (version is None or v == version)
            ]
            known = sorted({n for n, _ in self._items})
        if not found:
            wanted = f"{name!r}" + (f" version {version}" if version else "")
            raise RepositoryError(
                f"no component {wanted} in the repository",
                element="component provider",
                hint=f"known components: {', '.join(known) or 'none'}",
            )
        return max(found, key=lambda d: d.version_key)

    def all(self) -> list[ComponentDescription]:
        with self._lock:
            return sorted(self._items.values(), key=lambda d: (d.name, d.version_key))

    def catalog(self) -> etree._ElementTree:
        """The document searches run on (rebuilt after each change)."""
        return self._snapshot()[0]

    def _snapshot(self) -> tuple[etree._ElementTree, dict]:
        with self._lock:
            if self._catalog is None:
                root = etree.Element("components")
                owners = {}
                for desc in sorted(self._items.values(), key=lambda d: (d.name, d.version_key)):
                    elem = desc.to_element()
                    root.append(elem)
                    owners[elem] = desc
                self._catalog, self._owners = etree.ElementTree(root), owners
            return self._catalog, self._owners

    def search(self, xpath: str) -> list[ComponentDescription]:
        """Descriptions selected by ``xpath`` (e.g. ``//component[port/@name='image']``), in catalog order."""
        try:
            compiled = compile_expression(xpath, 4096, what="component search")
        except SubscriptionError as err:
            raise RepositoryError(
                err.message, column=err.column, element=err.element, hint=err.hint
            ) from None
        tree, owners = self._snapshot()
        result = compiled(tree)
        if not isinstance(result, list):
            raise RepositoryError(
                f"search {xpath!r} yields a {type(result).__name__}, not components",
                element="component provider",
                hint="select component elements or nodes within them, e.g. //component[@type='x']",
            )
        found: dict[int, ComponentDescription] = {}
        order = {id(d): i for i, d in enumerate(owners.values())}
        for node in result:
            elem = node.getparent() if isinstance(node, str) else node
            while elem is not None and elem not in owners:
                elem = elem.getparent()
            if elem is not None:
                found[id(owners[elem])] = owners[elem]
        return sorted(found.values(), key=lambda d: order[id(d)])
