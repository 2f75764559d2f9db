"""Write the metamodel's enumerations into the descriptor's schema.

The descriptor's schema (``src/acordcs/descriptor/acordcs-descriptor.xsd``) is the contract users'
own stylesheets read, so it carries its enumerations itself; they are the literals of the EEnums
of ``acordcs.ecore`` (through :mod:`acordcs.vocabularies`), written here into the simple types of
:data:`SIMPLE_TYPES`, each with a documentation line naming its EEnum. The rest of the file is
left byte for byte. ``tests/test_vocabularies_agree.py`` fails when the shipped schema is not
what this writes.

Run from the repository: ``.venv/bin/python tools/write_schema_enumerations.py`` (``--check``:
write nothing, exit 1 when the schema is not current).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from acordcs.vocabularies import literals

SCHEMA = Path(__file__).resolve().parents[1] / "src/acordcs/descriptor/acordcs-descriptor.xsd"

SIMPLE_TYPES: dict[str, tuple[str, tuple[str, ...], str]] = {
    # simple type of the schema: (EEnum of acordcs.ecore, literals left out, why)
    "language": ("ImplementationLanguage", (), ""),
    "portKind": ("PortKind", (), ""),
    "portRole": ("PortRole", (), ""),
    "connector": ("ConnectorKind", (), ""),
    "acquisition": ("MonitorAcquisition", (), ""),
    "engine": ("EngineKind", (), ""),
    "semantics": ("FuzzySemantics", (), ""),
    "trigger": ("PolicyTrigger", (), ""),
    "direction": (
        "ParameterDirection",
        ("return",),
        "an operation's result is its returnType, not one of its parameters",
    ),
    "shape": ("MembershipShape", (), ""),
}


def enumeration_values(simple_type: str) -> tuple[str, ...]:
    """The values the schema's ``simple_type`` enumerates: its EEnum's literals, less those left out."""
    enum, left_out, _why = SIMPLE_TYPES[simple_type]
    return tuple(v for v in literals(enum) if v not in left_out)


def _block(simple_type: str) -> str:
    enum, left_out, why = SIMPLE_TYPES[simple_type]
    where = f"The literals of EEnum {enum} of the metamodel, acordcs.ecore"
    if left_out:
        where += f", but {', '.join(left_out)} ({why})"
    lines = [
        f'  <xs:simpleType name="{simple_type}">',
        f"    <xs:annotation><xs:documentation>{where}.</xs:documentation></xs:annotation>",
        '    <xs:restriction base="xs:string">',
        *(f'      <xs:enumeration value="{v}"/>' for v in enumeration_values(simple_type)),
        "    </xs:restriction>",
        "  </xs:simpleType>",
    ]
    return "\n".join(lines)


def schema_text(current: str) -> str:
    """``current`` (the schema's text) with every simple type of :data:`SIMPLE_TYPES` written from
    the metamodel; ``ValueError`` when one of them is not in it."""
    out = current
    for simple_type in SIMPLE_TYPES:
        pattern = re.compile(
            rf'^  <xs:simpleType name="{simple_type}">\n.*?^  </xs:simpleType>$', re.M | re.S
        )
        out, found = pattern.subn(lambda _m, t=simple_type: _block(t), out, count=1)
        if not found:
            raise ValueError(f'{SCHEMA.name} has no <xs:simpleType name="{simple_type}">')
    return out


def main(argv: list[str]) -> int:
    current = SCHEMA.read_text(encoding="utf-8")
    wanted = schema_text(current)
    if "--check" in argv:
        if wanted != current:
            print(f"{SCHEMA}: not current; run python tools/write_schema_enumerations.py")
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
