"""Component descriptions: the XML documents a component provider stores and searches.

    <component name="LineFollower" type="weblab.LineFollower" version="1.2.0">
      <port name="image" kind="asynchronous" role="required"/>
      <factory location="http://host:8000/linefollower-1.2.0.zip"
               sha256="<64 hex digits>" entry="linefollower.factory:make_factory"/>
    </component>

``entry`` names, inside the package, either a component factory (anything with ``type_name``), a
component class (wrapped in ``acordcs.runtime.component.ComponentFactory``), or a function without
arguments returning a factory. A port's ``kind`` and ``role`` are the metamodel's (PortKind,
PortRole): the paper's notification ports are of kind ``asynchronous``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from urllib.parse import urlsplit

from lxml import etree

from acordcs import safexml
from acordcs.runtime.repository.errors import RepositoryError
from acordcs.vocabularies import PORT_KINDS, PORT_ROLES

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*")
_TYPE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*")
_VERSION = re.compile(r"[0-9]+(?:\.[0-9]+)*(?:[-+._]?[A-Za-z0-9.]+)?")
_SHA256 = re.compile(r"[0-9a-f]{64}")
_ENTRY = re.compile(
    r"([A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*):([A-Za-z_][A-Za-z0-9_]*)"
)
_MAX_BYTES = 64 * 1024


@dataclass(frozen=True)
class PortDescription:
    name: str
    kind: str = "synchronous"
    role: str = "provided"


@dataclass(frozen=True)
class ComponentDescription:
    name: str
    type: str
    version: str
    ports: tuple[PortDescription, ...]
    location: str
    sha256: str
    entry: str
    source: str = "<description>"

    @property
    def version_key(self) -> tuple:
        """Sort key: numeric release parts first, so 1.10 > 1.9."""
        release = re.match(r"[0-9]+(?:\.[0-9]+)*", self.version)
        parts = tuple(int(p) for p in release.group().split(".")) if release else ()
        return (parts, self.version)

    def to_element(self) -> etree._Element:
        elem = etree.Element("component", name=self.name, type=self.type, version=self.version)
        for port in self.ports:
            etree.SubElement(elem, "port", name=port.name, kind=port.kind, role=port.role)
        etree.SubElement(
            elem, "factory", location=self.location, sha256=self.sha256, entry=self.entry
        )
        return elem

    def to_xml(self) -> str:
        return etree.tostring(self.to_element(), pretty_print=True, encoding="unicode")


def _fail(
    source: str, message: str, hint: str, elem: etree._Element | None = None
) -> RepositoryError:
    line = elem.sourceline if elem is not None else None
    return RepositoryError(
        message, file=source, line=line, element="component description", hint=hint
    )


def _attribute(source: str, elem: etree._Element, name: str, pattern: re.Pattern, what: str) -> str:
    value = elem.get(name)
    if value is None:
        raise _fail(
            source, f"<{elem.tag}> lacks the {name!r} attribute", f'add {name}="..." ({what})', elem
        )
    value = value.strip()
    if not pattern.fullmatch(value):
        raise _fail(
            source, f"<{elem.tag}> {name}={value!r} is not {what}", f"write {name} as {what}", elem
        )
    return value


def parse_description(document: str | bytes, source: str = "<description>") -> ComponentDescription:
    """Parse and validate one ``<component>`` description, or raise :class:`RepositoryError`."""
    data = document.encode("utf-8") if isinstance(document, str) else document
    if not isinstance(data, bytes):
        raise _fail(
            source, f"a description is XML text, not {type(document).__name__}", "pass str or bytes"
        )
    if len(data) > _MAX_BYTES:
        raise _fail(
            source,
            f"description of {len(data)} bytes exceeds {_MAX_BYTES}",
            "describe one component",
        )
    try:
        root = safexml.parse(data)
    except safexml.Refused:
        raise _fail(
            source, "descriptions with a DOCTYPE are refused", "remove the DOCTYPE"
        ) from None
    except etree.XMLSyntaxError as err:
        line, column = err.position if err.position else (None, None)
        raise RepositoryError(
            f"not well-formed XML: {err.msg.split(', line ')[0]}",
            file=source,
            line=line,
            column=column,
            element="component description",
            hint="fix the description; nothing was added",
        ) from None
    if root.tag != "component":
        raise _fail(
            source,
            f"the root element is <{root.tag}>, not <component>",
            "see the format above",
            root,
        )
    name = _attribute(source, root, "name", _NAME, "a name (letters, digits, _ . -)")
    type_name = _attribute(
        source, root, "type", _TYPE, "a dotted type name, e.g. weblab.LineFollower"
    )
    version = _attribute(source, root, "version", _VERSION, "a version such as 1.2.0")
    ports: list[PortDescription] = []
    factory = None
    for child in root:
        if not isinstance(child.tag, str):
            continue
        if child.tag == "port":
            port = PortDescription(
                _attribute(source, child, "name", _NAME, "a port name"),
                child.get("kind", "synchronous"),
                child.get("role", "provided"),
            )
            if port.kind not in PORT_KINDS or port.role not in PORT_ROLES:
                raise _fail(
                    source,
                    f"port {port.name!r}: kind {port.kind!r} / role {port.role!r} unknown",
                    f"kind is one of {', '.join(PORT_KINDS)} (RM-ODP's request-reply, "
                    f"notification and flow), role one of {', '.join(PORT_ROLES)}",
                    child,
                )
            if any(p.name == port.name for p in ports):
                raise _fail(
                    source, f"port {port.name!r} is described twice", "name each port once", child
                )
            ports.append(port)
        elif child.tag == "factory":
            if factory is not None:
                raise _fail(
                    source, "more than one <factory>", "describe one factory package", child
                )
            factory = child
        else:
            raise _fail(
                source,
                f"unexpected element <{child.tag}>",
                "only <port> and <factory> are allowed",
                child,
            )
    if factory is None:
        raise _fail(
            source, "no <factory> element", "add <factory location=... sha256=... entry=.../>", root
        )
    location = factory.get("location", "").strip()
    parts = urlsplit(location)
    if parts.scheme not in ("http", "https") or not parts.netloc:
        raise _fail(
            source,
            f"factory location {location!r} is not an http(s) URL",
            'factories are fetched from HTTP servers: location="http://host:port/package.zip"',
            factory,
        )
    sha = _attribute(
        source, factory, "sha256", _SHA256, "64 lowercase hex digits (sha256sum of the package)"
    )
    entry = _attribute(source, factory, "entry", _ENTRY, "module.path:attribute")
    return ComponentDescription(
        name, type_name, version, tuple(ports), location, sha, entry, source
    )
