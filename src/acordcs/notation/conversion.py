"""A model converted between its forms: any model the readers read to the text notation, and any
to the XMI Papyrus opens or the XMI BOUML reads, all through its outline
(:mod:`acordcs.notation.outline`), so that each form says the same model."""

from __future__ import annotations

from acordcs.model.architecture import Architecture
from acordcs.notation.from_uml import outline_of
from acordcs.notation.text_form import text_of
from acordcs.notation.text_model import uml_of
from acordcs.notation.xmi_forms import bouml_form, papyrus_form

FORMS = ("text", "papyrus", "bouml")
SUFFIXES = {".acord": "text", ".uml": "papyrus", ".xmi": "bouml"}


def to_form(arch: Architecture, form: str) -> bytes:
    """The model ``arch`` interprets, in ``form`` (one of :data:`FORMS`)."""
    outline = outline_of(arch)
    if form == "text":
        return text_of(outline).encode("utf-8")
    uml = uml_of(outline, arch.uml.file)
    return papyrus_form(uml) if form == "papyrus" else bouml_form(uml)
