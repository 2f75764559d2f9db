"""The hostile-input shapes of ``test_hostile_input`` over the other tools' dialect paths (XMI 1.x of
Umbrello and Rose, XMI 2.5 of MagicDraw, EA's XMI 2.1 with applications inside the model, Eclipse UML2
of Modelio, Visual Paradigm's XMI 2.1): exit 1 or 2, a located message with the right code, no traceback, no file content leaked."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.xmi.readers import read_uml
from tests.support.toolchain import codes_in, no_crash, run_main
from tests.xmi.test_dialects import XMI10_LONG_NAMES

MODELS = Path(__file__).parent / "tool_models"
SECRET = "S3CR3T-acordcs-dialect-canary-41c9"


def _umbrello(classes: int = 3, duplicate_ids: bool = False) -> str:
    """An XMI 1.2 file in Umbrello's form: UML 1.3 namespace, attribute references, diagram widgets
    in XMI.extension restating the classes' ids."""
    members = "".join(
        f'<UML:Class xmi.id="{"dup" if duplicate_ids else f"c{n}"}" name="C{n}">'
        f'<UML:Classifier.feature><UML:Operation xmi.id="o{n}" name="op{n}"/></UML:Classifier.feature>'
        f"</UML:Class>\n"
        for n in range(classes)
    )
    widgets = "".join(f'<classwidget xmi.id="c{n}"/>' for n in range(classes))
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<XMI xmi.version="1.2" xmlns:UML="http://schema.omg.org/spec/UML/1.3">\n'
        "<XMI.header><XMI.documentation><XMI.exporter>umbrello uml modeller http://umbrello.kde.org"
        "</XMI.exporter><XMI.exporterVersion>1.6.1</XMI.exporterVersion></XMI.documentation>"
        "</XMI.header>\n<XMI.content>\n"
        '<UML:Model xmi.id="m1" name="UML Model"><UML:Namespace.ownedElement>\n'
        f"{members}</UML:Namespace.ownedElement>\n"
        f'<XMI.extension xmi.extender="umbrello"><diagrams><diagram><widgets>{widgets}'
        "</widgets></diagram></diagrams></XMI.extension>\n"
        "</UML:Model>\n</XMI.content>\n</XMI>\n"
    )


BASES = {
    "umbrello-xmi12": _umbrello(),
    "novosoft-xmi10": XMI10_LONG_NAMES,
    "magicdraw-xmi25": (MODELS / "acordcs_magicdraw.xmi").read_text(encoding="utf-8"),
    "ea-xmi21": (MODELS / "acordcs_enterprise_architect.xmi").read_text(encoding="cp1252"),
    "modelio-uml2": (MODELS / "acordcs_modelio.xmi").read_text(encoding="utf-8"),
    "vp-xmi21": (MODELS / "acordcs_visual_paradigm.xmi").read_text(encoding="utf-8"),
    "rose-xmi11": (
        "<?xml version = '1.0' encoding = 'ISO-8859-1'?>\n<!DOCTYPE XMI SYSTEM 'UML1311.dtd' >\n"
        "<XMI xmi.version = '1.1' xmlns:UML='href://org.omg/UML/1.3'>\n<XMI.header><XMI.documentation>"
        "<XMI.exporter>Unisys.JCR.1</XMI.exporter></XMI.documentation></XMI.header>\n<XMI.content>\n"
        "<Model xmi.id = 'G.0' name = 'm'><Namespace.ownedElement>\n"
        "<Class xmi.id = 'c' name = 'C'/>\n</Namespace.ownedElement></Model>\n"
        "<TaggedValue xmi.id = 't' tag = 'documentation' value = 'x' modelElement = 'G.0' />\n"
        "</XMI.content>\n</XMI>\n"
    ),
}


def _body_start(text: str) -> int:
    """Offset of the root element's start tag (after the declaration, comments and DOCTYPE)."""
    pos = 0
    while True:
        pos = text.index("<", pos)
        if text.startswith(("<?", "<!"), pos):
            pos = text.index(">", pos) + 1
            continue
        return pos


def _with_doctype(text: str, doctype: str) -> str:
    text = text.replace("<!DOCTYPE XMI SYSTEM 'UML1311.dtd' >\n", "")
    start = _body_start(text)
    return text[:start] + doctype + "\n" + text[start:]


def _xxe(text: str, tmp: Path) -> str:
    secret = tmp / "secret.txt"
    secret.write_text(SECRET)
    doctype = f'<!DOCTYPE XMI SYSTEM "UML13.dtd" [<!ENTITY e SYSTEM "file://{secret}">]>'
    text = _with_doctype(text, doctype)
    return text.replace('name="', 'name="&e;', 1).replace("name = '", "name = '&e;", 1)


def _bomb(text: str, tmp: Path) -> str:
    entities = '<!ENTITY a0 "aaaaaaaaaa">' + "".join(
        f'<!ENTITY a{i} "{f"&a{i - 1};" * 10}">' for i in range(1, 10)
    )
    return _with_doctype(text, f"<!DOCTYPE XMI [{entities}]>")


def _deep(text: str, tmp: Path) -> str:
    start = text.index(">", _body_start(text)) + 1
    return text[:start] + "<x>" * 300 + "</x>" * 300 + text[start:]


def _truncated(text: str, tmp: Path) -> str:
    return text[: len(text) * 2 // 3]


SHAPES = {
    "xxe": (_xxe, "X102", 2),
    "entity-bomb": (_bomb, "X102", 2),
    "deep-nesting": (_deep, "X103", 2),
    "truncated": (_truncated, "X104", 2),
}


def encoding_of(text: str) -> str:
    return "cp1252" if "windows-1252" in text[:60] else "utf-8"


@pytest.mark.parametrize("base", sorted(BASES))
@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_hostile_shape_on_dialect(base: str, shape: str, tmp_path: Path) -> None:
    make, code, exit_code = SHAPES[shape]
    text = BASES[base]
    path = tmp_path / "model.xmi"
    path.write_bytes(make(text, tmp_path).encode(encoding_of(text), errors="replace"))
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == exit_code, result.out
    lines = [ln for ln in result.out.splitlines() if f": {code} " in ln]
    assert lines and all(ln.startswith(f"{path}:") for ln in lines), result.out
    assert SECRET not in result.both


@pytest.mark.parametrize("base", sorted(BASES))
def test_windows_1252_bytes_declared_utf8_are_refused_where_they_are(
    base: str, tmp_path: Path
) -> None:
    text = BASES[base]
    model = re.search(r"<([\w.]+[:.])?Model\s", text).start()  # the first name in the model
    found = re.compile(r"""name\s*=\s*['"]|ModelElement\.name>""").search(text, model)
    text = text[: found.end()] + "Régulateur" + text[found.end() :]
    declared = text.replace("windows-1252", "UTF-8").replace("ISO-8859-1", "UTF-8")
    path = tmp_path / "model.xmi"
    path.write_bytes(declared.encode("cp1252"))
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == 2 and codes_in(result.out) == {"X105"}, result.out
    line = next(ln for ln in result.out.splitlines() if ": X105 " in ln)
    assert line.startswith(f"{path}:{text[: found.end()].count(chr(10)) + 1}:")
    # declared as what it is, the same bytes read with the accent intact
    path.write_bytes(declared.replace("UTF-8", "windows-1252", 1).encode("cp1252"))
    uml = read_uml(str(path))
    assert not [d for d in uml.diagnostics if d.code.startswith("X")], uml.diagnostics
    assert any(e.name.startswith("Régulateur") for e in uml.elements.values())


def test_thousands_of_ids_restated_in_extensions_are_not_duplicates(tmp_path: Path) -> None:
    """Umbrello restates every class id in its diagram widgets: 3,000 classes, no R203."""
    path = tmp_path / "umbrello.xmi"
    path.write_text(_umbrello(3000), encoding="utf-8")
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == 0 and ": R203 " not in result.out, result.out[:2000]
    assert "3000 Class" in run_main(["inspect", str(path)]).out


def test_thousands_of_real_duplicate_ids_are_one_located_error(tmp_path: Path) -> None:
    path = tmp_path / "umbrello.xmi"
    path.write_text(_umbrello(3000, duplicate_ids=True), encoding="utf-8")
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == 1
    lines = [ln for ln in result.out.splitlines() if ": R203 " in ln]
    assert len(lines) == 1 and "3000 times" in lines[0] and lines[0].startswith(f"{path}:6:")


@pytest.mark.parametrize(
    "tag",
    [
        "Foundation.Core.Class.-x",
        "Foundation.",
        "Foundation.Core.ModelElement.1name",
        "Foundation.Core..",
    ],
)
def test_xmi10_names_that_shorten_to_no_xml_name_are_skipped_and_said(
    tag: str, tmp_path: Path
) -> None:
    text = XMI10_LONG_NAMES.replace(
        '<Foundation.Core.ModelElement.visibility xmi.value="public"/>', f"<{tag}>x</{tag}>"
    )
    assert tag in text
    path = tmp_path / "model.xmi"
    path.write_text(text, encoding="utf-8")
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code in (0, 1), result.out
    uml = read_uml(str(path))
    assert [c.name for c in uml.classifiers] == ["Camera", "Device", "int"]


_PAYLOADS = [
    b"<",
    b">",
    b"&",
    b'"',
    b"\x00",
    b"]]>",
    b"<!--",
    b"<!DOCTYPE x [",
    b"xmi.idref=",
    b"\xff",
]


@st.composite
def mutated(draw) -> bytes:
    base = draw(st.sampled_from(sorted(BASES)))
    text = BASES[base]
    data = bytearray(text.encode(encoding_of(text)))
    for _ in range(draw(st.integers(1, 4))):
        pos = draw(st.integers(0, len(data) - 1))
        op = draw(st.sampled_from(["flip", "delete", "insert", "truncate"]))
        if op == "flip":
            data[pos] = draw(st.integers(0, 255))
        elif op == "delete":
            del data[pos : pos + draw(st.integers(1, 64))]
        elif op == "insert":
            data[pos:pos] = draw(st.sampled_from(_PAYLOADS))
        else:
            del data[pos:]
        if not data:
            break
    return bytes(data)


@settings(
    max_examples=60,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(data=mutated())
def test_fuzzed_dialects_never_raise(tmp_path: Path, data: bytes) -> None:
    target = tmp_path / "fuzz.xmi"
    target.write_bytes(data)
    result = run_main(["validate", "--format", "json", str(target)])
    assert result.code in (0, 1, 2)
    assert "Traceback" not in result.both and "internal error" not in result.err, result.err
