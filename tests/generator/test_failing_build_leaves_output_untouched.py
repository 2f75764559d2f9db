"""A build that fails (a model with errors, a target raising, a stylesheet that does not compile
or stops, two files where one is a directory of the other) leaves the output directory as it was:
every target runs in memory before a byte is written, and a new output directory appears whole or
not at all. Errors say what, where and what to do, without a traceback."""

from __future__ import annotations

from pathlib import Path

import pytest

from acordcs.generator import BuildError, GeneratedFile, target, writer, xslt_target
from acordcs.generator.manifest import Manifest
from tests.support.generator import build, registered, snapshot, weblab_variant
from tests.support.toolchain import WEBLAB, no_crash, run_main

STYLESHEET = """<xsl:stylesheet version="3.0" xmlns:xsl="http://www.w3.org/1999/XSL/Transform"
    xmlns="http://acordcs.org/codegen/1.0">
  <xsl:param name="source-file"/><xsl:param name="generator"/><xsl:param name="target"/>
  <xsl:param name="descriptor-schema"/>
  <xsl:template match="/">{body}</xsl:template>
</xsl:stylesheet>"""


@pytest.fixture
def built(tmp_path: Path) -> Path:
    out = tmp_path / "out"
    assert build(WEBLAB, out).code == 0
    (out / "mine.txt").write_text("mine", encoding="utf-8")
    return out


def _stylesheet(tmp_path: Path, name: str, body: str) -> Path:
    path = tmp_path / f"{name}.xsl"
    path.write_text(STYLESHEET.format(body=body), encoding="utf-8")
    return path


def test_a_raising_python_target(built: Path, tmp_path: Path):
    @target("boom", description="raises")
    def boom(context) -> None:
        context.emit("boom.txt", "half")
        raise RuntimeError("disk on fire")

    before = snapshot(built)
    with registered(boom):
        result = build(weblab_variant(tmp_path, ('name="WebLab">', 'name="Other">')), built)
    no_crash(result)
    assert result.code == 1
    assert "target boom failed: RuntimeError: disk on fire" in result.err
    assert "nothing was written" in result.err and "--target" in result.err
    assert snapshot(built) == before


def test_a_stylesheet_that_stops(built: Path, tmp_path: Path, capfd):
    body = '<xsl:message terminate="yes">no way: <xsl:value-of select="*/@name"/></xsl:message>'
    stops = xslt_target("stops", _stylesheet(tmp_path, "stops", body))
    before = snapshot(built)
    with registered(stops):
        result = build(WEBLAB, built, "--force")
    no_crash(result)
    assert result.code == 1
    assert "target stops: the transformation failed" in result.err
    assert "xsl:message: no way: WebLab" in result.err
    assert snapshot(built) == before
    assert "XTMM9000" not in capfd.readouterr().err  # Saxon's own print was caught


def test_a_stylesheet_that_does_not_compile(built: Path, tmp_path: Path):
    broken = xslt_target("broken", _stylesheet(tmp_path, "broken", '<xsl:value-of select="1 +"/>'))
    before = snapshot(built)
    with registered(broken):
        result = build(WEBLAB, built, "--force")
    assert result.code == 1
    assert (
        "target broken: compiling the stylesheet failed" in result.err and "XPST0003" in result.err
    )
    assert snapshot(built) == before


def test_a_stylesheet_listing_a_file_it_does_not_write(built: Path, tmp_path: Path):
    body = (
        '<xsl:result-document href="x.txt" method="text">x</xsl:result-document>'
        '<files><file path="y.txt"/></files>'
    )
    sly = xslt_target("sly", _stylesheet(tmp_path, "sly", body))
    before = snapshot(built)
    with registered(sly):
        result = build(WEBLAB, built, "--force")
    assert result.code == 1
    assert "the stylesheet lists 'y.txt' but did not write it (it wrote: 'x.txt')" in result.err
    assert snapshot(built) == before


def test_messages_of_a_stylesheet_are_reported(tmp_path: Path):
    body = (
        '<xsl:message>note from <xsl:value-of select="$target"/></xsl:message>'
        '<xsl:result-document href="n.txt" method="text">n</xsl:result-document>'
        '<files><file path="n.txt" element="WebLab"/></files>'
    )
    noisy = xslt_target("noisy", _stylesheet(tmp_path, "noisy", body))
    with registered(noisy):
        result = build(WEBLAB, tmp_path / "out", "--target", "noisy")
    assert result.code == 0, result.both
    assert "acordcs-gen: target noisy: note from noisy" in result.err
    assert (tmp_path / "out" / "n.txt").read_text(encoding="utf-8") == "n"


def test_a_model_with_errors_is_reported_as_validate_reports_it(built: Path, tmp_path: Path):
    broken = weblab_variant(
        tmp_path,
        ("then Locomotion.maxSpeed is fast", "then Locomotion.maxSpeed is fastest", 2),
    )
    before = snapshot(built)
    result = build(broken, built)
    assert result.code == 1
    validate = run_main(["validate", str(broken)])
    assert result.out == validate.out  # the same diagnostics lines and summary
    assert "L404" in result.out
    assert "the model has errors; nothing was built" in result.err
    assert snapshot(built) == before


def test_an_unreadable_model_exits_2(tmp_path: Path):
    result = build(tmp_path / "absent.xmi", tmp_path / "out")
    no_crash(result)
    assert result.code == 2
    assert "X101" in result.out
    assert "the model could not be read; nothing was built" in result.err
    assert not (tmp_path / "out").exists()


def test_a_file_where_another_needs_a_directory_is_g702(tmp_path: Path):
    @target("clash", description="a file where another needs a directory")
    def clash(context) -> None:
        context.emit("x", "a file")
        context.emit("x/y", "under it")

    with registered(clash):
        result = build(WEBLAB, tmp_path / "out", "--target", "clash,config")
    no_crash(result)
    assert result.code == 1
    assert (
        "G702 target clash would write 'x/y' inside 'x', a file target clash writes" in result.out
    )
    assert list(tmp_path.iterdir()) == []


def test_a_new_output_directory_appears_whole_or_not_at_all(tmp_path: Path):
    out = tmp_path / "parent" / "out"
    files = [GeneratedFile("a/mine.txt", b"mine", "t"), GeneratedFile("b.txt", b"b", "t")]
    planned = writer.plan(out, files, None, Manifest("m.xmi"), {"t"})
    assert planned.fresh
    writer.apply(out, planned)
    assert [p.name for p in (tmp_path / "parent").iterdir()] == ["out"]  # nothing beside it
    assert snapshot(out).keys() == {".acordcs-manifest.json", "a/mine.txt", "b.txt"}

    # planned as new, and made by someone else before the build writes: nothing written
    other = tmp_path / "other"
    planned = writer.plan(other, files, None, Manifest("m.xmi"), {"t"})
    other.mkdir()
    (other / "theirs.txt").write_text("theirs", encoding="utf-8")
    with pytest.raises(BuildError, match="it exists") as caught:
        writer.apply(other, planned)
    assert caught.value.exit_code == 2 and "nothing was written" in caught.value.hint
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other", "parent"]
    assert [p.name for p in other.iterdir()] == ["theirs.txt"]
