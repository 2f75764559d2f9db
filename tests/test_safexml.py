"""The one hardened XML parser (acordcs.safexml) and its three callers: model files, context documents
and component descriptions each refuse hostile documents through it, and share its configuration."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from pathlib import Path

import pytest
from lxml import etree

from acordcs import safexml
from acordcs.runtime.context.errors import PublishError
from acordcs.runtime.context.xmlparse import Limits, parse_document
from acordcs.runtime.repository.description import parse_description
from acordcs.runtime.repository.errors import RepositoryError
from acordcs.xmi import source

SECRET = "S3CR3T-acordcs-safexml-canary-91c4"
LAUGHS = '<!ENTITY a0 "lol">' + "".join(
    f'<!ENTITY a{i} "{f"&a{i - 1};" * 10}">' for i in range(1, 10)
)
DESCRIPTION = (
    '<component name="X" type="a.X" version="1.0"><factory location="http://h/x.zip" '
    'sha256="' + "0" * 64 + '" entry="x:f"/></component>'
)


def billion_laughs() -> str:
    return f'<?xml version="1.0"?><!DOCTYPE component [{LAUGHS}]><component name="&a9;"/>'


def xxe(tmp_path: Path) -> str:
    secret = tmp_path / "secret.txt"
    secret.write_text(SECRET)
    return (
        f'<?xml version="1.0"?><!DOCTYPE component [<!ENTITY e SYSTEM "file://{secret}">]>'
        "<component>&e;</component>"
    )


def too_deep() -> str:
    return "<component>" + "<a>" * 300 + "</a>" * 300 + "</component>"


def encoded(text: str, encoding: str) -> bytes:
    if encoding == "utf-16":  # the declaration must match the bytes
        text = text.replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="UTF-16"?>')
    return text.encode(encoding)


# Each caller's refusal as text (what its user reads), asserting that it is a refusal.


def model_file(data: bytes) -> str:
    result = source.parse_bytes(data, "model.xmi")
    assert result.root is None
    return " ".join(f"{d.code} {d.message}" for d in result.diagnostics)


def context_document(data: bytes) -> str:
    with pytest.raises(PublishError) as info:
        parse_document("p", data, Limits())
    return str(info.value)


def component_description(data: bytes) -> str:
    with pytest.raises(RepositoryError) as info:
        parse_description(data)
    return str(info.value)


CALLERS = {
    "model file": model_file,
    "context document": context_document,
    "component description": component_description,
}


@pytest.fixture
def shared_parse(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """What each call of safexml.parse ended with: 'Refused', 'XMLSyntaxError' or 'parsed'."""
    outcomes: list[str] = []
    real = safexml.parse

    def spy(*args, **kwargs):
        try:
            root = real(*args, **kwargs)
        except (safexml.Refused, etree.XMLSyntaxError) as err:
            outcomes.append(type(err).__name__)
            raise
        outcomes.append("parsed")
        return root

    monkeypatch.setattr(safexml, "parse", spy)
    return outcomes


@pytest.mark.parametrize("caller", CALLERS)
@pytest.mark.parametrize("encoding", ["utf-8", "utf-16"])
def test_billion_laughs_is_refused(caller: str, encoding: str, shared_parse: list[str]) -> None:
    said = CALLERS[caller](encoded(billion_laughs(), encoding))
    assert shared_parse == ["Refused"]  # seen by the byte scan, which reads UTF-16 too
    assert "DOCTYPE" in said or "X102 document type declaration refused" in said
    assert "lollollol" not in said


@pytest.mark.parametrize("caller", CALLERS)
@pytest.mark.parametrize("encoding", ["utf-8", "utf-16"])
def test_external_entity_is_never_read(
    caller: str, encoding: str, tmp_path: Path, shared_parse: list[str]
) -> None:
    said = CALLERS[caller](encoded(xxe(tmp_path), encoding))
    assert shared_parse == ["Refused"]  # by the byte scan, in UTF-8 and UTF-16 alike
    assert "DOCTYPE" in said or "X102 document type declaration refused" in said
    assert SECRET not in said


@pytest.mark.parametrize("caller", CALLERS)
def test_nesting_deeper_than_libxml2_allows_is_refused(
    caller: str, shared_parse: list[str]
) -> None:
    said = CALLERS[caller](too_deep().encode())
    assert shared_parse == ["XMLSyntaxError"]
    assert "Excessive depth" in said or "X103 elements nested deeper than 256 levels" in said


def test_a_late_doctype_is_refused_in_recover_mode_too(tmp_path: Path) -> None:
    # Past the scanned prefix, and with an unescaped '<' in a name: the strict parse fails before its
    # tree could be checked, and the recovering parse is checked as well.
    pad = "<!--" + "x" * 70_000 + "-->"
    text = (
        xxe(tmp_path)
        .replace("<!DOCTYPE", pad + "<!DOCTYPE")
        .replace("<component>", '<component name="a<b">')
    )
    said = model_file(text.encode())
    assert said.startswith("X102 document type") and "refused" in said and SECRET not in said


def _on_a_new_thread(work: Callable[[], object]) -> None:
    """Run ``work`` on a thread of its own: a thread's parser is made on its first parse."""
    failures: list[BaseException] = []

    def run() -> None:
        try:
            work()
        except BaseException as err:
            failures.append(err)

    thread = threading.Thread(target=run)
    thread.start()
    thread.join(30)
    assert not failures, failures


def test_the_three_callers_get_their_parsers_from_the_one_factory(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    made: list[dict] = []
    real = safexml.parser

    def factory(**variant):
        made.append(variant)
        return real(**variant)

    monkeypatch.setattr(safexml, "parser", factory)
    assert source.parse_bytes(b"<model>\n  <a/>\n</model>").root is not None
    assert made == [{"remove_blank_text": True}]
    made.clear()
    _on_a_new_thread(lambda: parse_document("p", b"<robot><battery>5</battery></robot>", Limits()))
    assert made == [{}]
    made.clear()
    _on_a_new_thread(lambda: parse_description(DESCRIPTION))
    assert made == [{}]
    made.clear()
    recovered = source.parse_bytes(b'<model><a name="x<y"/></model>')  # BOUML's unescaped names
    assert recovered.recovered and recovered.root is not None
    assert made == [{"remove_blank_text": True}, {"recover": True, "remove_blank_text": True}]


def test_changing_the_shared_options_changes_all_three(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(safexml.OPTIONS, "huge_tree", True)  # never do this outside a test
    deep = too_deep().encode()
    assert source.parse_bytes(deep).root is not None
    _on_a_new_thread(lambda: parse_document("p", deep, Limits()))

    def description() -> None:
        with pytest.raises(RepositoryError) as info:  # parsed: refused by validation instead
            parse_description(deep)
        assert "not well-formed" not in str(info.value)

    _on_a_new_thread(description)


@pytest.mark.parametrize(
    "declaration", ["<!DOCTYPE r>", '<!ENTITY e "x">', "<!doctype r>", "<!Entity e 'x'>"]
)
def test_the_scan_gives_where_the_declaration_is(declaration: str) -> None:
    data = f'<?xml version="1.0"?>\n<!-- a comment -->\n  {declaration}<r/>'.encode()
    with pytest.raises(safexml.Refused) as info:
        safexml.parse(data)
    assert (info.value.line, info.value.column) == (3, 3)
    assert data[info.value.offset :].startswith(declaration.encode())


def test_past_scan_end_the_tree_check_refuses() -> None:
    data = b"<!-- padding -->\n<!DOCTYPE r><r/>"
    with pytest.raises(safexml.Refused) as info:
        safexml.parse(data, scan_end=10)
    assert (info.value.offset, info.value.line, info.value.column) == (None, None, None)


def test_comments_and_cdata_are_not_declarations() -> None:
    root = safexml.parse(b"<r><!-- <!x --><![CDATA[ DOCTYPE ]]></r>")
    assert root.tag == "r" and root.xpath("string()") == " DOCTYPE "


def test_each_thread_has_its_own_parser() -> None:
    assert safexml.thread_parser() is safexml.thread_parser()
    other: list[etree.XMLParser] = []
    _on_a_new_thread(lambda: other.append(safexml.thread_parser()))
    assert other[0] is not safexml.thread_parser()


def test_limits_in_words() -> None:
    with pytest.raises(etree.XMLSyntaxError) as info:
        safexml.parse(too_deep().encode())
    assert safexml.exceeded_limit(str(info.value)) == "elements nested deeper than 256 levels"
    assert safexml.exceeded_limit("Opening and ending tag mismatch") is None


def test_past_the_scan_libxml2_never_opens_an_external_entity(tmp_path: Path) -> None:
    # scan_end=0: the declaration gets past the byte scan, as one past a caller's prefix would; the
    # target is a FIFO, so opening it would block until a writer appears
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    doc = f'<!DOCTYPE r [<!ENTITY x SYSTEM "file://{fifo}">]><r>&x;</r>'.encode("utf-16")
    outcome: list[object] = []

    def attempt() -> None:
        try:
            outcome.append(safexml.parse(doc, safexml.parser(), scan_end=0))
        except BaseException as err:
            outcome.append(err)

    worker = threading.Thread(target=attempt)
    worker.start()
    worker.join(10)
    if worker.is_alive():
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        worker.join(5)
        pytest.fail("libxml2 opened the external entity's target")
    assert isinstance(
        outcome[0], safexml.Refused
    )  # the tree check, after a parse that read nothing
