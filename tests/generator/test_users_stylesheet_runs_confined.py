"""A stylesheet given with ``-t`` runs confined: it reads the descriptor and the files under its own
directory (with ``unparsed-text``, ``doc``, ``xsl:import``), not a file elsewhere (a mode-600
secret, ``/etc/passwd``, an imported module outside), not a URL (a server on 127.0.0.1 gets no
request), and sees no environment variable; what is refused fails the build with the URI and the
stylesheet's line. ``--trust-stylesheet`` gives it the user's rights again. Where Linux Landlock is
missing, a user's stylesheet is refused rather than run unconfined."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from acordcs.generator import sandbox
from tests.support.generator import build
from tests.support.toolchain import WEBLAB, no_crash

SECRET = "acordcs-test-secret-7f3a"

needs_landlock = pytest.mark.skipif(
    sandbox.abi() < 1, reason="Linux Landlock is not available: a user's stylesheet is refused"
)


def _sheet(directory: Path, body: str, name: str = "sheet.xsl", top: str = "") -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / name
    path.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<xsl:stylesheet version="3.0" xmlns:xsl="http://www.w3.org/1999/XSL/Transform">\n'
        f"{top}"
        '  <xsl:template match="/">\n'
        '    <xsl:result-document href="out.txt" method="text">\n'
        f"      {body}\n"
        "    </xsl:result-document>\n"
        "  </xsl:template>\n"
        "</xsl:stylesheet>\n",
        encoding="utf-8",
    )
    return path


@pytest.fixture
def secret(tmp_path: Path) -> Path:
    path = tmp_path / "private" / "secret.txt"
    path.parent.mkdir()
    path.write_text(SECRET, encoding="utf-8")
    path.chmod(0o600)
    return path


@needs_landlock
def test_it_reads_a_file_beside_it_and_not_one_elsewhere(tmp_path: Path, secret: Path):
    beside = _sheet(tmp_path / "sheet", "<xsl:value-of select=\"unparsed-text('data/in.txt')\"/>")
    (beside.parent / "data").mkdir()
    (beside.parent / "data" / "in.txt").write_text("from beside", encoding="utf-8")
    done = build(WEBLAB, tmp_path / "ok", "-t", str(beside))
    assert done.code == 0, done.both
    assert (tmp_path / "ok" / "out.txt").read_text(encoding="utf-8") == "from beside"

    for uri in (secret.as_uri(), "../private/secret.txt", "file:///etc/passwd"):
        sheet = _sheet(tmp_path / "sheet", f"<xsl:value-of select=\"unparsed-text('{uri}')\"/>")
        refused = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
        no_crash(refused)
        assert refused.code == 1, refused.both
        assert SECRET not in refused.both and "root:x:" not in refused.both
        assert not (tmp_path / "out").exists()
        assert f"{sheet}:5: error: target sheet.xsl:" in refused.err  # the stylesheet's line
        assert "is confined and may not read" in refused.err
        shown = "/etc/passwd" if uri.startswith("file:///etc") else str(secret)
        assert shown in refused.err
        assert "--trust-stylesheet" in refused.err


@needs_landlock
def test_a_link_beside_it_to_a_file_elsewhere_is_refused(tmp_path: Path, secret: Path):
    sheet = _sheet(tmp_path / "sheet", "<xsl:value-of select=\"unparsed-text('link.txt')\"/>")
    (sheet.parent / "link.txt").symlink_to(secret)
    refused = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
    assert refused.code == 1 and SECRET not in refused.both, refused.both
    assert "is confined and may not read" in refused.err


@needs_landlock
def test_it_imports_a_module_beside_it_and_not_one_elsewhere(tmp_path: Path):
    helper = (
        '<xsl:stylesheet version="3.0" xmlns:xsl="http://www.w3.org/1999/XSL/Transform"'
        ' xmlns:h="urn:h" xmlns:xs="http://www.w3.org/2001/XMLSchema">\n'
        '<xsl:function name="h:word" as="xs:string"><xsl:sequence select="\'imported\'"/>'
        "</xsl:function></xsl:stylesheet>\n"
    )
    (tmp_path / "sheet" / "lib").mkdir(parents=True)
    (tmp_path / "sheet" / "lib" / "helper.xsl").write_text(helper, encoding="utf-8")
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "helper.xsl").write_text(helper, encoding="utf-8")
    call = '<xsl:value-of select="h:word()" xmlns:h="urn:h"/>'
    sheet = _sheet(tmp_path / "sheet", call, top='  <xsl:import href="lib/helper.xsl"/>\n')
    done = build(WEBLAB, tmp_path / "ok", "-t", str(sheet))
    assert done.code == 0, done.both
    assert (tmp_path / "ok" / "out.txt").read_text(encoding="utf-8") == "imported"
    sheet = _sheet(tmp_path / "sheet", call, top='  <xsl:import href="../elsewhere/helper.xsl"/>\n')
    refused = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
    no_crash(refused)
    assert refused.code == 1, refused.both
    assert "is confined and may not read" in refused.err
    assert str(tmp_path / "elsewhere" / "helper.xsl") in refused.err


@needs_landlock
def test_it_sees_no_environment_variable(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("ACORDCS_TEST_SECRET", SECRET)
    body = (
        "<xsl:value-of select=\"'[' || environment-variable('ACORDCS_TEST_SECRET') || ']', "
        "count(available-environment-variables()), empty(environment-variable('HOME'))\"/>"
    )
    sheet = _sheet(tmp_path / "sheet", body)
    done = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
    assert done.code == 0, done.both
    assert (tmp_path / "out" / "out.txt").read_text(encoding="utf-8") == "[] 0 true"
    trusted = build(WEBLAB, tmp_path / "trusted", "-t", str(sheet), "--trust-stylesheet")
    assert trusted.code == 0, trusted.both
    said = (tmp_path / "trusted" / "out.txt").read_text(encoding="utf-8")
    assert said.startswith(f"[{SECRET}] ") and not said.startswith(f"[{SECRET}] 0 ")


# A server on 127.0.0.1 in a process of its own (a trusted stylesheet runs in the test's process,
# holding it while it waits for the answer), noting each request's path in a file; it stops by
# itself after a minute.
_SERVER = """
import http.server, sys, threading
log = open(sys.argv[1], "a", buffering=1)
class Recorder(http.server.BaseHTTPRequestHandler):
    def do_GET(self):
        log.write(self.path + "\\n")
        self.send_response(200)
        self.send_header("Content-Type", "text/plain")
        self.end_headers()
        self.wfile.write(b"served")
    def log_message(self, *args):
        pass
httpd = http.server.HTTPServer(("127.0.0.1", 0), Recorder)
print(httpd.server_address[1], flush=True)
threading.Timer(60, httpd.shutdown).start()
httpd.serve_forever(poll_interval=0.1)
"""


@pytest.fixture
def server(tmp_path: Path) -> Iterator[tuple[str, Path]]:
    log = tmp_path / "requests.log"
    log.touch()
    process = subprocess.Popen(
        [sys.executable, "-c", _SERVER, str(log)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert process.stdout is not None
        port = int(process.stdout.readline())
        yield f"http://127.0.0.1:{port}", log
    finally:
        process.kill()
        process.wait(timeout=10)


def test_it_reaches_no_url(tmp_path: Path, server: tuple[str, Path], monkeypatch):
    monkeypatch.setenv("ACORDCS_TEST_SECRET", SECRET)
    server, log = server
    for select in (
        f"unparsed-text('{server}/page')",
        f"doc('{server}/page.xml')",
        f"unparsed-text('{server}/leak?' || environment-variable('ACORDCS_TEST_SECRET'))",
    ):
        sheet = _sheet(tmp_path / "sheet", f'<xsl:value-of select="{select}"/>')
        refused = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
        no_crash(refused)
        assert refused.code == 1, refused.both
        assert "is confined and may not read" in refused.err and server in refused.err
    assert log.read_text(encoding="utf-8") == ""  # not one request reached the server
    trusted = build(WEBLAB, tmp_path / "trusted", "-t", str(sheet), "--trust-stylesheet")
    assert trusted.code == 0, trusted.both
    assert log.read_text(encoding="utf-8") == f"/leak?{SECRET}\n"  # the server sees requests


def test_a_trusted_stylesheet_reads_what_the_user_can(tmp_path: Path, secret: Path):
    sheet = _sheet(
        tmp_path / "sheet", f"<xsl:value-of select=\"unparsed-text('{secret.as_uri()}')\"/>"
    )
    done = build(WEBLAB, tmp_path / "out", "-t", str(sheet), "--trust-stylesheet")
    assert done.code == 0, done.both
    assert (tmp_path / "out" / "out.txt").read_text(encoding="utf-8") == SECRET


def test_without_landlock_a_users_stylesheet_is_refused_not_run(tmp_path: Path, monkeypatch):
    from acordcs.generator import stylesheet_worker

    monkeypatch.setattr(sandbox, "abi", lambda: 0)
    monkeypatch.setattr(stylesheet_worker, "_WORKERS", {})  # no confined child already running
    sheet = _sheet(tmp_path / "sheet", "<xsl:value-of select=\"'x'\"/>")
    refused = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
    no_crash(refused)
    assert refused.code == 2, refused.both
    assert "cannot be run confined here" in refused.err and "Landlock" in refused.err
    assert not (tmp_path / "out").exists()
    assert build(WEBLAB, tmp_path / "out", "-t", str(sheet), "--trust-stylesheet").code == 0


@needs_landlock
def test_an_entity_of_a_document_beside_it_or_a_collection_elsewhere_reads_nothing(
    tmp_path: Path, secret: Path
):
    sheet = _sheet(tmp_path / "sheet", "<xsl:value-of select=\"string(doc('data.xml'))\"/>")
    (sheet.parent / "data.xml").write_text(
        f'<!DOCTYPE d [<!ENTITY e SYSTEM "{secret.as_uri()}">]>\n<d>&e;</d>\n', encoding="utf-8"
    )
    refused = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
    assert refused.code == 1 and SECRET not in refused.both, refused.both
    assert "is confined and may not read" in refused.err and str(secret) in refused.err
    listing = f"string-join(collection('{secret.parent.as_uri()}/?select=*;unparsed=yes'))"
    sheet = _sheet(tmp_path / "sheet", f'<xsl:value-of select="{listing}"/>')
    refused = build(WEBLAB, tmp_path / "out", "-t", str(sheet))
    no_crash(refused)
    assert refused.code == 1 and SECRET not in refused.both, refused.both
    assert not (tmp_path / "out").exists()
