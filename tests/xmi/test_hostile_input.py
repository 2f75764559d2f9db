"""Broken and hostile input through ``acordcs-gen validate``: a clear diagnostic with the right code and
exit code, never a Python traceback, never the content of a file an entity names."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.support.toolchain import (
    WEBLAB,
    codes_in,
    no_crash,
    replace,
    run_main,
    run_process,
    write_model,
)

SECRET = "S3CR3T-acordcs-xxe-canary-7f3a"
HEAD = (
    '<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" '
    'xmlns:xmi="http://schema.omg.org/spec/XMI/2.1">'
)
PAD = "<!--" + "x" * 70_000 + "-->\n"  # pushes a DOCTYPE past a prefix scan


def _xxe(tmp: Path, pad: str = "") -> bytes:
    secret = tmp / "secret.txt"
    secret.write_text(SECRET)
    return (
        f'<?xml version="1.0"?>\n{pad}<!DOCTYPE x [<!ENTITY e SYSTEM "file://{secret}">]>\n'
        f'{HEAD}<uml:Model xmi:type="uml:Model" xmi:id="m" name="&e;"/></xmi:XMI>\n'
    ).encode()


def _bomb(pad: str = "") -> bytes:
    entities = '<!ENTITY a0 "aaaaaaaaaa">' + "".join(
        f'<!ENTITY a{i} "{f"&a{i - 1};" * 10}">' for i in range(1, 10)
    )
    return (
        f'<?xml version="1.0"?>\n{pad}<!DOCTYPE bomb [{entities}]>\n'
        f'{HEAD}<uml:Model xmi:type="uml:Model" xmi:id="m" name="&a9;"/></xmi:XMI>\n'
    ).encode()


def _weblab(edit=None) -> bytes:
    text = WEBLAB.read_text(encoding="utf-8")
    return (edit(text) if edit else text).encode("utf-8")


WEBLAB_BYTES = WEBLAB.read_bytes()


@dataclass
class Case:
    id: str
    make: object  # (tmp_path) -> bytes | None (None: the case makes its own path)
    code: str
    exit: int
    fail_on: str = "error"
    message: str = ""


CASES = [
    Case("xxe", lambda tmp: _xxe(tmp), "X102", 2, message="XXE"),
    Case("xxe-after-64k-prefix", lambda tmp: _xxe(tmp, PAD), "X102", 2),
    Case("entity-bomb", lambda tmp: _bomb(), "X102", 2),
    Case(
        "deep-nesting",
        lambda tmp: (
            f'<?xml version="1.0"?>\n{HEAD}<uml:Model xmi:type="uml:Model" xmi:id="m" name="m">'
            + "<ownedComment>" * 300
            + "</ownedComment>" * 300
            + "</uml:Model></xmi:XMI>\n"
        ).encode(),
        "X103",
        2,
        message="256",
    ),
    Case(
        "truncated-after-a-tag",
        lambda tmp: WEBLAB_BYTES[: WEBLAB_BYTES.index(b"</packagedElement>", 30_000) + 18],
        "X104",
        2,
    ),
    Case(
        "undeclared-prefix",
        lambda tmp: _weblab(
            lambda t: replace(  # a self-closing element: only its start tag carries the prefix
                t,
                '<ownedComment xmi:type="uml:Comment" xmi:id="COMMENT_1"',
                '<foo:ownedComment xmi:type="uml:Comment" xmi:id="COMMENT_1"',
            )
        ),
        "X106",
        2,
        message="foo",
    ),
    Case(
        "latin1-bytes-declared-utf8",
        lambda tmp: _weblab(lambda t: replace(t, 'name="Image"', 'name="Imagé"')).replace(
            "Imagé".encode(), "Imagé".encode("iso-8859-1")
        ),
        "X105",
        2,
    ),
    Case(
        "unknown-encoding-name",
        lambda tmp: WEBLAB_BYTES.replace(b'encoding="UTF-8"', b'encoding="no-such-encoding"', 1),
        "X105",
        2,
    ),
    Case(
        "dangling-id",
        lambda tmp: WEBLAB_BYTES.replace(
            b'xmi:idref="BOUML_0x1f402_4"/>', b'xmi:idref="BOUML_0xdead_4"/>'
        ),
        "R202",
        1,
        message="BOUML_0xdead_4",
    ),
    Case(
        "duplicate-id",
        lambda tmp: WEBLAB_BYTES.replace(b'xmi:id="BOUML_0x1f482_1"', b'xmi:id="BOUML_0x1f402_1"'),
        "R203",
        1,
        message="BOUML_0x1f402_1",
    ),
    Case(  # a component: what ACORD-CS reads of it is lost, an error
        "unknown-xmi-type",
        lambda tmp: WEBLAB_BYTES.replace(
            b'xmi:type="uml:Class" name="Locomotion"', b'xmi:type="uml:Clas" name="Locomotion"'
        ),
        "R201",
        1,
        message="did you mean uml:Class?) on 'Locomotion'; the element is skipped, and it holds "
        "<<CtxComponent>> 'Locomotion'",
    ),
    Case(  # a class no ACORD-CS element is: a warning (its name, a parameter's type, is kept)
        "unknown-xmi-type-of-a-plain-class",
        lambda tmp: WEBLAB_BYTES.replace(
            b'xmi:type="uml:Class" name="Image"', b'xmi:type="uml:Clas" name="Image"'
        ),
        "R201",
        1,
        fail_on="warning",
        message="did you mean uml:Class?) on 'Image'; the element is skipped: it holds no ACORD-CS",
    ),
    Case(
        "unescaped-lt-in-name",
        lambda tmp: WEBLAB_BYTES.replace(b'name="Image"', b'name="Image<T>"'),
        "X107",
        1,
        message="recovery mode",
    ),
    Case(
        "tag-of-wrong-type",
        lambda tmp: _weblab(
            lambda t: replace(
                replace(t, 'frequency="1" base_Element', 'frequency="fast" base_Element'),
                'CtxMonitor:frequency" value="1"',
                'CtxMonitor:frequency" value="fast"',
            )
        ),
        "T304",
        1,
        message="'fast'",
    ),
    Case("empty-file", lambda tmp: b"", "X104", 2, message="empty"),
    Case("blank-file", lambda tmp: b"  \n\t\n", "X104", 2, message="empty"),
    Case("directory", lambda tmp: None, "X101", 2),
    Case("nonexistent", lambda tmp: None, "X101", 2),
    Case(
        "not-xmi",
        lambda tmp: b'<?xml version="1.0"?>\n<project><module name="x"/></project>\n',
        "X109",
        2,
        message="not XMI",
    ),
    Case(
        "huge-attribute",
        lambda tmp: (
            f'<?xml version="1.0"?>\n{HEAD}<uml:Model xmi:type="uml:Model" xmi:id="m" name="'
            + "A" * (11 * 2**20)
            + '"/></xmi:XMI>\n'
        ).encode(),
        "X103",
        2,
    ),
]


def path_for(case: Case, tmp_path: Path) -> Path:
    if case.id == "directory":
        target = tmp_path / "model.xmi"
        target.mkdir()
        return target
    if case.id == "nonexistent":
        return tmp_path / "missing.xmi"
    target = tmp_path / "model.xmi"
    target.write_bytes(case.make(tmp_path))
    return target


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_hostile_input_gives_a_clear_diagnostic(case: Case, tmp_path: Path) -> None:
    path = path_for(case, tmp_path)
    result = run_main(["validate", "--fail-on", case.fail_on, str(path)])
    no_crash(result)
    assert result.code == case.exit, result.both
    lines = [ln for ln in result.out.splitlines() if f": {case.code} " in ln]
    assert lines, result.both
    assert all(ln.startswith(str(path)) for ln in lines)
    assert any(case.message in ln for ln in lines), (case.message, lines)
    assert SECRET not in result.both
    if case.fail_on == "warning":  # a warning alone does not fail the default --fail-on error
        assert run_main(["validate", str(path)]).code == 0


def test_hostile_files_in_one_process_run(tmp_path: Path) -> None:
    """The real entry point, every case at once: exit 2, no traceback, the secret never printed."""
    paths = []
    for n, case in enumerate(c for c in CASES if c.id != "huge-attribute"):
        sub = tmp_path / f"{n:02d}-{case.id}"
        sub.mkdir()
        paths.append(str(path_for(case, sub)))
    result = run_process(["validate", "--format", "json", *paths])
    no_crash(result)
    assert result.code == 2
    assert SECRET not in result.both
    result = run_process(["inspect", paths[0]])  # the XXE file
    no_crash(result)
    assert result.code == 2 and "X102" in result.err and SECRET not in result.both


TRUNCATIONS = {
    # name: (marker to cut just after, offset from the marker's end)
    "mid-start-tag": (b'<ownedAttribute xmi:type="uml:Property" name="fps" xmi:id=', -8),
    "mid-attribute-value": (b"crawl := trape 0 0 20 50; slow", 0),
    "mid-text-of-tag-value": (b"smallNarrow: if cycleRate is small", 0),
    "mid-end-tag": (b"</ownedAttribute>", -5),
    "after-a-tag": (b"</packagedElement>", 0),
}


@pytest.mark.parametrize("where", list(TRUNCATIONS))
def test_truncated_file_is_refused(where: str, tmp_path: Path) -> None:
    marker, shift = TRUNCATIONS[where]
    cut = WEBLAB_BYTES.index(marker) + len(marker) + shift
    target = tmp_path / "truncated.xmi"
    target.write_bytes(WEBLAB_BYTES[:cut])
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert result.code == 2, result.both
    assert " X104 " in result.out, result.out


def test_a_missing_end_tag_is_refused_not_recovered(weblab_text, tmp_path):
    text = weblab_text.replace("</packagedElement>", "", 1)
    result = run_main(["validate", str(write_model(tmp_path, text))])
    no_crash(result)
    assert codes_in(result.out) == {"X108"} and result.code == 2, result.out


def test_a_control_character_is_not_called_an_encoding_problem(weblab_text, tmp_path):
    text = weblab_text.replace('name="Locomotion"', 'name="Loco\x01motion"', 1)
    result = run_main(["validate", str(write_model(tmp_path, text))])
    assert codes_in(result.out) == {"X108"} and "control character" in result.out


def test_utf16_declaration_on_utf8_bytes_is_an_encoding_error(tmp_path: Path) -> None:
    target = tmp_path / "utf16.xmi"
    target.write_bytes(WEBLAB_BYTES.replace(b'encoding="UTF-8"', b'encoding="UTF-16"', 1))
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert result.code == 2
    assert " X105 " in result.out, result.out


def test_binary_garbage_is_not_called_empty(tmp_path: Path) -> None:
    target = tmp_path / "garbage.xmi"
    target.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 8)
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert result.code == 2
    assert " X108 " in result.out or " X109 " in result.out, result.out
    assert "empty" not in result.out


def test_binary_garbage_exit_code(tmp_path: Path) -> None:
    """Whatever the code, garbage is unreadable input: exit 2 and a reading diagnostic."""
    target = tmp_path / "garbage.xmi"
    target.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 8)
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert result.code == 2
    assert " error: X1" in result.out


def test_huge_attribute_message_does_not_talk_of_nesting(tmp_path: Path) -> None:
    case = next(c for c in CASES if c.id == "huge-attribute")
    target = tmp_path / "huge.xmi"
    target.write_bytes(case.make(tmp_path))
    result = run_main(["validate", str(target)])
    assert " X103 " in result.out
    assert "nest this deep" not in result.out  # the file nests nothing


def test_recovered_file_with_unbound_prefix_does_not_crash(tmp_path: Path) -> None:
    data = WEBLAB_BYTES.replace(b'name="Image"', b'name="Image<T>"').replace(
        b'<ACORDCS:CtxComponent xmi:id="BOUML_STELT_0x1f702_4"',
        b'<ACORDX:CtxComponent xmi:id="BOUML_STELT_0x1f702_4"',
    )
    target = tmp_path / "recovered.xmi"
    target.write_bytes(data)
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert " X107 " in result.out
    assert result.code in (0, 1)


def test_recovered_name_keeps_its_text(tmp_path: Path) -> None:
    """The unescaped ``<`` is read, not dropped: the class is still called ``Image<T>``."""
    import json

    target = tmp_path / "lt.xmi"
    target.write_bytes(WEBLAB_BYTES.replace(b'name="Image"', b'name="Image<T>"'))
    result = run_main(["inspect", "--format", "json", str(target)])
    assert result.code == 0
    data = json.loads(result.out)
    assert data["classifiers"] == {"Class": 36, "DataType": 1, "Stereotype": 8}
    assert data["diagnostics"] == 1


# --------------------------------------------------------------------------------------- fuzzing
_PAYLOADS = [
    b"<",
    b">",
    b"&",
    b'"',
    b"\x00",
    b"\xff\xfe",
    b"]]>",
    b"<!--",
    b"&#0;",
    b"xmi:",
    b" is ",
]


@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@st.composite
def mutated_weblab(draw) -> bytes:
    data = bytearray(WEBLAB_BYTES)
    for _ in range(draw(st.integers(1, 6))):
        pos = draw(st.integers(0, len(data) - 1))
        op = draw(st.sampled_from(["flip", "delete", "insert", "truncate"]))
        if op == "flip":
            data[pos] = draw(st.integers(0, 255))
        elif op == "delete":
            del data[pos : pos + draw(st.integers(1, 64))]
        elif op == "insert":
            data[pos:pos] = draw(st.sampled_from(_PAYLOADS) | st.binary(min_size=1, max_size=8))
        else:
            del data[pos:]
        if not data:
            break
    return bytes(data)


@settings(
    max_examples=100,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(data=mutated_weblab())
def test_fuzzed_weblab_never_raises(fuzz_dir: Path, data: bytes) -> None:
    target = fuzz_dir / "fuzz.xmi"
    target.write_bytes(data)
    result = run_main(["validate", "--format", "json", str(target)])  # must not raise
    assert result.code in (0, 1, 2)
    assert "Traceback" not in result.both
    assert "internal error" not in result.err, result.err


@pytest.mark.parametrize(
    ("old", "new"),
    [
        (  # an association's ownedEnd
            b'type="BOUML_0x1f502_4" aggregation="composite"',
            b'type=" " aggregation="composite"',
        ),
        (  # an operation parameter typed by attribute (Eclipse style)
            b'<ownedParameter xmi:type="uml:Parameter" name="frame" xmi:id="BOUML_op_param_1" direction="in">',
            b'<ownedParameter xmi:type="uml:Parameter" name="frame" xmi:id="BOUML_op_param_1" direction="in" type="  ">',
        ),
    ],
    ids=["owned-end", "parameter"],
)
def test_blank_type_reference_does_not_crash(old: bytes, new: bytes, tmp_path: Path) -> None:
    target = tmp_path / "blank-type.xmi"
    assert WEBLAB_BYTES.count(old) == 1
    target.write_bytes(WEBLAB_BYTES.replace(old, new))
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert result.code in (0, 1)
