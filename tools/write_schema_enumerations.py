"""Write the descriptor's schema from the descriptor's declaration.

The schema (``src/acordcs/descriptor/acordcs-descriptor.xsd``) is the contract users' own
stylesheets read, so the package ships it as a file; its text is what
:func:`acordcs.descriptor.xsd.schema_text` makes of the declaration in
:mod:`acordcs.descriptor.application` (the dataclasses' fields, annotated), its enumerations the
literals of the EEnums of ``acordcs.ecore`` (through :mod:`acordcs.vocabularies`). To change the
schema, change the declaration (or, for what only the schema says, :mod:`acordcs.descriptor.xsd`)
and run this. ``tests/descriptor/test_schema_is_the_declarations.py`` fails when the shipped file
is not what this writes.

Run from the repository: ``.venv/bin/python tools/write_schema_enumerations.py`` (``--check``:
write nothing, exit 1 when the schema is not current). The name is the one of the tool that
wrote only the enumerations into a schema written by hand; :data:`SCHEMA`, :data:`SIMPLE_TYPES`,
:func:`enumeration_values` and :func:`schema_text` keep their meaning for the tests that use them.
"""

from __future__ import annotations

import sys
from pathlib import Path

from acordcs.descriptor import xsd

SCHEMA = Path(__file__).resolve().parents[1] / "src/acordcs/descriptor/acordcs-descriptor.xsd"
COMMAND = "python tools/write_schema_enumerations.py"

SIMPLE_TYPES: dict[str, tuple[str, tuple[str, ...], str]] = {
    # simple type of the schema: (EEnum of acordcs.ecore, literals left out, why)
    name: (simple.eenum, simple.left_out, simple.why)
    for name, simple in xsd.enumerations().items()
    if simple.eenum
}


def enumeration_values(simple_type: str) -> tuple[str, ...]:
    """The values the schema's ``simple_type`` enumerates: its EEnum's literals, less those left out."""
    return xsd.enumeration_values(xsd.enumerations()[simple_type])


def schema_text(current: str | None = None) -> str:
    """The schema as the declaration writes it (``current``, the shipped text, is not needed: the
    whole file is written)."""
    return xsd.schema_text()


def main(argv: list[str]) -> int:
    current = SCHEMA.read_text(encoding="utf-8")
    wanted = schema_text()
    if "--check" in argv:
        if wanted != current:
            print(f"{SCHEMA}: not current; run {COMMAND}")
            return 1
        print(f"{SCHEMA}: current")
        return 0
    if wanted == current:
        print(f"{SCHEMA}: up to date")
    else:
        SCHEMA.write_text(wanted, encoding="utf-8")
        print(f"wrote {SCHEMA}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
