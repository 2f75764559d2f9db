"""Read, interpret and check one model file: what ``validate``, ``inspect`` and ``build`` share."""

from __future__ import annotations

from dataclasses import dataclass, field

from acordcs.diagnostics import Diagnostic, Severity
from acordcs.model.architecture import Architecture, interpret
from acordcs.model.causes import settled
from acordcs.model.checks import Context, run_checks
from acordcs.model.lost_references import explain_lost_references
from acordcs.notation import is_notation, read_text_model
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
    """Read ``path`` (any supported XMI, or the text notation when its name ends in ``.acord``:
    :mod:`acordcs.notation`), interpret it and, with ``check``, run every model check.

    The findings come causes first, and a finding another one explains (a rule naming an element
    whose stereotype was not read, a component whose deployment refers to an id the file lacks)
    is counted by its cause instead of printed (:mod:`acordcs.model.causes`)."""
    uml = read_text_model(path) if is_notation(path) else read_uml(path)
    if uml.dialect == "unreadable":
        return ModelReading(path, uml, None, list(uml.diagnostics))
    arch = interpret(uml)
    explain_lost_references(arch)
    found = list(uml.diagnostics)
    if check:
        found += run_checks(Context(uml, arch))
    return ModelReading(path, uml, arch, settled(found))
