"""What a reader does not read, said once per type: a UML metaclass it does not need (info R211), or a
type that is not UML at all (R201: a warning, an error only when the element holds or relates an
ACORD-CS element).

A reader reads packages, classifiers with their attributes, ports, operations and literals,
associations, generalizations, dependencies, comments and stereotype applications. Real exports hold
more: BOUML 1.13 writes the events of its sequence diagrams (``uml:ExecutionEvent``, a UML 2.0 to
2.3 metaclass), ArgoUML the actions of its collaborations (``UML:CreateAction``), Enterprise Architect
and Poseidon their diagrams in the UML namespace (``UML:DiagramElement``, OMG Diagram Interchange).
Those are legitimate UML that the toolchain has no use for: each metaclass is named once, with a
count and the first place, never as an error. Whether a name is a UML metaclass is decided by the
list in ``uml_metaclasses.txt`` (UML 1.3, 1.4, 2.0 to 2.5 and Diagram Interchange 1.0, with its
sources). A name no UML version defines is a typo or another tool's extension (UML 1.4 exports of
the NetBeans MDR writer also write the metamodel's associations as elements,
``UML:A_context_raisedSignal``): R201, with the closest metaclass, unless a known tool wrote the file
and no metaclass resembles it (then it is that tool's own element type, R211). R201 is a warning,
one per type with the count and the first place, when nothing ACORD-CS reads is lost with the
element; it is an error, one per element, when the element (or one inside it) has an ACORD-CS
stereotype applied, or it names two such elements, as a relation ACORD-CS reads would (a misspelt
``uml:Dependancy`` between a container and a component): the reader says what it holds.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from importlib import resources

from lxml import etree

from acordcs.diagnostics import Severity, diagnostic
from acordcs.xmi.uml import UmlModel

METACLASS_FILE = "uml_metaclasses.txt"


@cache
def uml_metaclasses() -> dict[str, str]:
    """Every UML metaclass name -> the first metamodel that defines it (``UML 2.5``, ``UML 1.4``,
    ...), from the package's ``uml_metaclasses.txt``."""
    text = resources.files(__package__).joinpath(METACLASS_FILE).read_text(encoding="utf-8")
    names: dict[str, str] = {}
    section = ""
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        if line.startswith("["):
            section = line.strip("[]")
            continue
        names.setdefault(line, section)
    return names


def metamodel_of(name: str) -> str | None:
    """The metamodel that defines metaclass ``name``, or None when no UML version does."""
    return uml_metaclasses().get(name)


def closest_metaclass(name: str) -> str | None:
    """The metaclass ``name`` looks like a misspelling of (``Clas``: ``Class``), or None. The bar
    is high: at difflib's default, Visual Paradigm's ``activitySwimlane2`` would be taken for a
    misspelt ``SubactivityState``."""
    import difflib  # only for a name that is not UML: it costs start-up time

    close = difflib.get_close_matches(name, list(uml_metaclasses()), n=1, cutoff=0.8)
    return close[0] if close else None


def qualified_name(el: etree._Element | None) -> str | None:
    """``Package::Element`` for an element the reader skipped (so has no object in the view): the
    names of it and its named ancestors below the model, as :meth:`Element.qualified_name` says
    them; None when it has no name."""
    if el is None or not el.get("name"):
        return None
    parts = []
    node: etree._Element | None = el
    while node is not None:
        local = node.tag.rpartition("}")[2] if isinstance(node.tag, str) else ""
        typed = next((v for k, v in node.items() if k.endswith("}type")), "")
        if local in ("Model", "XMI") or typed.endswith(":Model"):
            break
        if node.get("name"):
            parts.append(node.get("name"))
        node = node.getparent()
    return "::".join(reversed(parts))


@dataclass
class _Seen:
    count: int = 0
    line: int = 0
    ident: str | None = None
    # for R201, one each: line, id, the element (to look for what ACORD-CS reads in it)
    places: list[tuple[int, str | None, etree._Element | None]] = field(default_factory=list)


class Skipped:
    """The elements one reading skipped, by type; :meth:`report` adds the diagnostics.

    ``prefix`` is how the file's dialect writes a metaclass (``uml:`` in XMI 2, ``UML:`` in XMI 1).
    A type written without ``xmi:type`` is recorded by its tag, ``<region>``."""

    def __init__(self, model: UmlModel, prefix: str) -> None:
        self.model = model
        self.prefix = prefix
        # R201's words as each dialect has always said them
        xmi1 = prefix == "UML:"
        self._unknown = "unknown element" if xmi1 else "unknown xmi:type"
        self._skipped = "it is skipped" if xmi1 else "the element is skipped"
        self._seen: dict[str, _Seen] = {}

    def __bool__(self) -> bool:
        return bool(self._seen)

    def add(
        self, kind: str, line: int | None, ident: str | None, el: etree._Element | None = None
    ) -> None:
        seen = self._seen.get(kind)
        if seen is None:
            seen = self._seen[kind] = _Seen(line=line or 0, ident=ident)
        seen.count += 1
        if kind[0] != "<" and metamodel_of(kind) is None:
            seen.places.append((line or 0, ident, el))

    def report(
        self,
        tool: str | None,
        acordcs: Callable[[etree._Element], str | None] | None = None,
    ) -> None:
        """One R211 per UML metaclass, and per type of a known ``tool``'s own (a name no UML
        version defines and no metaclass resembles); for a type that looks like a misspelt
        metaclass, or that no known tool wrote, R201: an error per element of it that
        ``acordcs`` says holds or relates an ACORD-CS element (what it says is named), one
        warning for the others."""
        model = self.model
        for kind, seen in self._seen.items():
            written = kind if kind[0] == "<" else f"{self.prefix}{kind}"
            metamodel = None if kind[0] == "<" else metamodel_of(kind)
            close = closest_metaclass(kind) if kind[0] != "<" and metamodel is None else None
            if kind[0] != "<" and metamodel is None and (tool is None or close is not None):
                self._unknown_type(kind, written, close, seen, acordcs)
                continue
            if kind[0] == "<":
                why = "written without xmi:type"
            elif metamodel is not None:
                why = f"a {metamodel} metaclass this reader does not read"
            else:
                why = "no UML version defines it (the exporting tool's own type)"
            first = ", the first at this line" if seen.count > 1 else ""
            plural = "s" if seen.count > 1 else ""
            model.diagnostics.append(
                diagnostic(
                    "R211",
                    f"{seen.count} {written} element{plural} skipped{first}: {why}; what "
                    f"{'they hold' if plural else 'it holds'} is not checked",
                    file=model.file,
                    line=seen.line,
                    xmi_id=seen.ident,
                )
            )

    def _unknown_type(
        self,
        kind: str,
        written: str,
        close: str | None,
        seen: _Seen,
        acordcs: Callable[[etree._Element], str | None] | None,
    ) -> None:
        model = self.model
        hint = f" (did you mean {self.prefix}{close}?)" if close else ""
        if kind.startswith("A_") and self.prefix == "UML:" and close is None:
            hint = " (a UML 1.4 metamodel association written as links between its ends)"
        quiet = []
        for line, ident, el in seen.places:
            held = acordcs(el) if acordcs is not None and el is not None else None
            if held is None:
                quiet.append((line, ident, el))
                continue
            name = el.get("name", "") if el is not None else ""
            named = f" on {name!r}" if name else ""
            model.diagnostics.append(
                diagnostic(
                    "R201",
                    f"{self._unknown} {written}{hint}{named}; {self._skipped}, and it {held}, "
                    "which ACORD-CS reads: correct the type (or export the model again)",
                    file=model.file,
                    line=line,
                    element=qualified_name(el),
                    xmi_id=ident,
                    severity=Severity.ERROR,
                )
            )
        if not quiet:
            return
        line, ident, el = quiet[0]
        name = el.get("name", "") if el is not None else ""
        if len(quiet) == 1:
            what = f" on {name!r}" if name else ""
            said = f"{self._skipped}: it holds no ACORD-CS element and relates none"
        else:
            first = f", the first ({name!r})" if name else ", the first"
            said = f"{len(quiet)} elements skipped{first} at this line: they hold no ACORD-CS element and relate none"
            what = ""
        model.diagnostics.append(
            diagnostic(
                "R201",
                f"{self._unknown} {written}{hint}{what}; {said}, so nothing ACORD-CS reads is "
                "lost: correct the type if it matters to you",
                file=model.file,
                line=line,
                element=qualified_name(el),
                xmi_id=ident,
            )
        )
