"""The outcomes of a test run as JUnit XML (the form CI systems show test results in): one
``testsuite`` per scenario file, one ``testcase`` per scenario, a ``failure`` per expectation
that did not hold (its place, what was expected and seen, the rules in effect) and an ``error``
for faults the run recorded."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Iterable

from acordcs.scenarios.scenario_run import Failure, Outcome


def rules_text(failure: Failure) -> str:
    """The rules that had fired when the failure was seen, with their degrees, strongest first."""
    rules = ", ".join(f"{name} {degree:.2f}" for name, degree in failure.fired[:8])
    more = f" and {len(failure.fired) - 8} more" if len(failure.fired) > 8 else ""
    return f"rules in effect at t={failure.time:g} s: {rules or 'none'}{more}"


def failure_text(failure: Failure, separator: str = "\n  ") -> str:
    """The failure's message, and the rules that had fired then with their degrees."""
    return f"{failure.message}{separator}{rules_text(failure)}"


# What XML 1.0 cannot hold (a scenario's name may have any character YAML escapes allow)
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _xml_text(text: str) -> str:
    return _NOT_XML.sub(lambda m: f"\\u{ord(m[0]):04x}", text)


def junit_xml(model: str, outcomes: Iterable[Outcome]) -> bytes:
    by_file: dict[str, list[Outcome]] = {}
    for outcome in outcomes:
        by_file.setdefault(outcome.scenario.file, []).append(outcome)
    root = ET.Element("testsuites", name=f"acordcs-gen test {model}")
    for file, mine in by_file.items():
        suite = ET.SubElement(
            root,
            "testsuite",
            name=file,
            tests=str(len(mine)),
            failures=str(sum(1 for o in mine if o.failures)),
            errors=str(sum(1 for o in mine if (o.faults or o.refused) and not o.failures)),
            time=f"{sum(o.seconds for o in mine):.6f}",
        )
        for o in mine:
            case = ET.SubElement(
                suite, "testcase", classname=file, name=o.scenario.name, time=f"{o.seconds:.6f}"
            )
            for f in o.failures:
                node = ET.SubElement(
                    case, "failure", message=f"{f.expectation.at.where()}: {f.message}", type="S810"
                )
                node.text = f"{f.expectation.at.where()}: {failure_text(f)}"
            problems = [f"{at.where()}: {why}" for at, why in o.refused] + o.faults
            if problems:
                node = ET.SubElement(case, "error", message=problems[0], type="S811")
                node.text = "\n".join(problems)
    for node in root.iter():
        node.attrib = {k: _xml_text(v) for k, v in node.attrib.items()}
        if node.text:
            node.text = _xml_text(node.text)
    ET.indent(root)
    return ET.tostring(root, encoding="utf-8", xml_declaration=True) + b"\n"
