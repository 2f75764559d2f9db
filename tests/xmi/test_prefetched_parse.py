"""The parse of a model file ahead on a thread (acordcs.xmi.source.prefetch): its result is used once,
and only for a file unchanged since; a file changed or gone is read, and reported, as usual."""

from __future__ import annotations

import os
import time
from pathlib import Path

from acordcs.xmi import source as xmlsafe
from tests.support.toolchain import WEBLAB


def _wait(path: str) -> None:
    slot = xmlsafe._prefetched[path]
    assert slot.done.wait(30)


def test_a_prefetched_parse_is_used_once(tmp_path: Path) -> None:
    path = str(tmp_path / "m.xmi")
    Path(path).write_bytes(WEBLAB.read_bytes())
    xmlsafe.prefetch([path])
    _wait(path)
    prefetched = xmlsafe._prefetched[path].result
    first = xmlsafe.read_xml(path)
    assert first is prefetched and first.root is not None
    second = xmlsafe.read_xml(path)  # not prefetched any more: parsed again
    assert second is not first and second.root is not None


def test_a_file_changed_after_the_prefetch_is_read_again(tmp_path: Path) -> None:
    path = str(tmp_path / "m.xmi")
    Path(path).write_bytes(WEBLAB.read_bytes())
    xmlsafe.prefetch([path])
    _wait(path)
    time.sleep(0.01)
    Path(path).write_text("<broken", encoding="utf-8")
    reading = xmlsafe.read_xml(path)
    assert reading.root is None and reading.diagnostics[0].code == "X104"


def test_a_prefetch_of_a_file_that_vanished_reports_it_as_usual(tmp_path: Path) -> None:
    path = str(tmp_path / "m.xmi")
    Path(path).write_bytes(WEBLAB.read_bytes())
    xmlsafe.prefetch([path])
    _wait(path)
    os.remove(path)
    reading = xmlsafe.read_xml(path)
    assert reading.root is None and reading.diagnostics[0].code == "X101"
