"""Read, interpret and check one model file: what ``validate``, ``inspect`` and ``build`` share."""

from __future__ import annotations

from dataclasses import dataclass, field

from acordcs.diagnostics import Diagnostic, Severity
from acordcs.model.architecture import Architecture, interpret
from acordcs.model.checks import Context, run_checks
from acordcs.xmi.readers import read_uml
from acordcs.xmi.uml import UmlModel


@dataclass
class ModelReading:
    file: str
    uml: UmlModel
    architecture: Architecture | None
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def unreadable(self) -> bool:
        return any(d.unreadable for d in self.diagnostics)

    def worst(self) -> Severity | None:
        return max((d.severity for d in self.diagnostics), default=None)


def read_model(path: str, *, check: bool = True) -> ModelReading:
    """Read ``path`` (any supported XMI), interpret it and, with ``check``, run every model check."""
    uml = read_uml(path)
    if uml.dialect == "unreadable":
        return ModelReading(path, uml, None, list(uml.diagnostics))
    arch = interpret(uml)
    found = list(uml.diagnostics)
    if check:
        found += run_checks(Context(uml, arch))
    return ModelReading(path, uml, arch, in_reading_order(found))


# What a finding's code is about, from reading the file to generating code: a finding of an
# earlier stage about an element can cause findings of later stages about it, never the reverse.
_STAGES = {letter: n for n, letter in enumerate("XRTNLAGZ")}


def in_reading_order(found: list[Diagnostic]) -> list[Diagnostic]:
    """``found`` by source position, causes before consequences: the findings about one element
    together, where its first one is in the file, in the order of their stages (a misspelt tag
    of a monitor, at the stereotype application near the file's end, before what the monitor
    then lacks, at the monitor itself), then by line and column."""
    first: dict[str, int] = {}
    for d in found:
        if d.xmi_id:
            first[d.xmi_id] = min(first.get(d.xmi_id, d.line), d.line)

    def key(d: Diagnostic) -> tuple:
        where = first.get(d.xmi_id, d.line) if d.xmi_id else d.line
        return (where, d.xmi_id or "", _STAGES.get(d.code[:1], 9), d.line, d.column, d.code)

    return sorted(found, key=key)
