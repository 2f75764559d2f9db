"""rule_warmup: rules parsed from a model's raw bytes while libxml2 parses the file.

It may only save time: the checks must find the rules the warm-up parsed (else it is useless), its
mistakes cost nothing but a wasted parse, it never changes a result, and hostile bytes do not make
it slow.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from gen_helpers import SMARTROOM, WEBLAB, no_crash, replace, run_main, run_process

from acordcs.generator.architecture import POLICY_SET
from acordcs.generator.checks.rules import policy_rules
from acordcs.generator.pipeline import read_model
from acordcs.generator.rule_warmup import warm
from acordcs.metamodel import rules


def _rules_checked(path: Path) -> set[tuple[str, str]]:
    """The (text, kind) pairs the rules check parses for ``path``."""
    arch = read_model(str(path)).architecture
    found = set()
    for policy_set in arch.of_kind(POLICY_SET):
        kind = "crisp" if policy_set.tag("engine") == "clips" else "fuzzy"
        for policy in arch.policies(policy_set):
            found |= {(p.text, kind) for p in policy_rules(policy)}
    return found


@pytest.mark.parametrize("path", [WEBLAB, SMARTROOM], ids=lambda p: p.name)
def test_warm_up_parses_what_the_rules_check_parses(path: Path) -> None:
    checked = _rules_checked(path)
    assert any(kind == "crisp" for _, kind in checked) or path == SMARTROOM
    rules._PARSED.clear()
    assert warm(path.read_bytes()) == len({text for text, _ in checked})
    assert checked <= set(rules._PARSED)  # every one is a memo hit for the check


def test_warm_up_stops_when_asked() -> None:
    rules._PARSED.clear()
    assert warm(WEBLAB.read_bytes(), stop=lambda: True) == 0
    assert not rules._PARSED


def test_a_text_read_wrongly_only_misses(tmp_path: Path) -> None:
    """The memo is keyed by the text: a rule the warm-up reads differently from lxml (here bytes
    of an ISO-8859-1 file, which it decodes as UTF-8) is parsed again by the check."""
    text = WEBLAB.read_text(encoding="utf-8").replace(
        'encoding="UTF-8"', 'encoding="ISO-8859-1"', 1
    )
    text = replace(
        text, "if cycleRate is small and angle is narrow", "if cycleRate is smäll and", 2
    )
    path = tmp_path / "latin1.xmi"
    path.write_bytes(text.encode("iso-8859-1"))
    rules._PARSED.clear()
    cold = read_model(str(path)).diagnostics
    rules._PARSED.clear()
    warm(path.read_bytes())
    assert read_model(str(path)).diagnostics == cold
    assert any(d.code == "L401" for d in cold)


def test_validate_reports_the_same_with_and_without_the_warm_up(tmp_path: Path) -> None:
    """``acordcs-gen`` warms up; ``main()`` (library use) does not: same output, broken rules too."""
    text = WEBLAB.read_text(encoding="utf-8")
    text = replace(text, "if cycleRate is small and angle is narrow", "if cycleRat is smal and", 2)
    path = tmp_path / "broken-rules.xmi"
    path.write_text(text, encoding="utf-8")
    for model in (WEBLAB, path):
        warmed = run_process(["validate", str(model)])
        cold = run_main(["validate", str(model)])
        no_crash(warmed)
        assert (warmed.code, warmed.out) == (cold.code, cold.out)
    assert "L401" in run_process(["validate", str(path)]).out


def test_hostile_bytes_do_not_make_it_slow() -> None:
    """'RuleRuleRule...' once made each 'Rule' start a scan to the end of the run: 80 KB took
    19 s. Run in a subprocess with a bound far above what it takes now (milliseconds)."""
    code = (
        "from acordcs.generator.rule_warmup import warm\n"
        "data = b'<!-- ' + b'Rule' * 200_000 + b' -->' + b' Rule=\"' * 50_000 + b'<'\n"
        "print(warm(data))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "0"
