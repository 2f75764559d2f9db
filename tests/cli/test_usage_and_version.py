"""``acordcs-gen`` usage: a wrong command line exits 2 with click's usage and reads no model;
``--version`` names the package's version."""

from __future__ import annotations

import re

import pytest

from acordcs import __version__
from tests.support.toolchain import WEBLAB, no_crash, run_main, run_process


@pytest.mark.parametrize(
    "args",
    [
        [],
        ["validate"],
        ["inspect"],
        ["validate", "--bogus", str(WEBLAB)],
        ["frobnicate"],
        ["validate", "--format", "xml", str(WEBLAB)],
        ["validate", "--fail-on", "info", str(WEBLAB)],
        ["inspect", "--format", "sarif", str(WEBLAB)],
    ],
    ids=[
        "no-args",
        "validate-no-file",
        "inspect-no-file",
        "bad-option",
        "bad-command",
        "bad-format",
        "bad-fail-on",
        "inspect-bad-format",
    ],
)
def test_usage_errors_exit_2(args: list[str]) -> None:
    result = run_main(args)
    no_crash(result)
    assert result.code == 2
    assert "Usage:" in result.both
    assert not re.search(r"\b[XRTLANZ]\d{3}\b", result.out)  # no model was read


def test_usage_error_from_the_real_entry_point() -> None:
    result = run_process(["validate"])
    no_crash(result)
    assert result.code == 2
    assert "Missing argument" in result.err


def test_version() -> None:
    result = run_main(["--version"])
    assert result.code == 0
    assert result.out.strip() == f"acordcs-gen, version {__version__}"
    assert run_process(["--version"]).out.strip() == f"acordcs-gen, version {__version__}"
