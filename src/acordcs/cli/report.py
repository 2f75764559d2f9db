"""Formatting diagnostics as text, gcc's lines, JSON or SARIF 2.1.0 (formatting only: the CLI
shows the result)."""

from __future__ import annotations

import json
from collections import Counter

from acordcs import __version__
from acordcs.diagnostics import CODES, Diagnostic, Severity, help_uri, printable
from acordcs.model.reading import ModelReading

_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def render(
    readings: list[ModelReading],
    fmt: str,
    *,
    exit_code: int = 0,
    at_least: Severity | None = None,
) -> str:
    """``readings`` in ``fmt``; ``exit_code`` goes into SARIF's invocation; ``at_least`` (text
    and gcc, ``--quiet``) keeps the diagnostics of that severity or worse and drops the summaries."""
    if fmt == "json":
        return json.dumps(as_json(readings), indent=2) + "\n"
    if fmt == "sarif":
        return json.dumps(as_sarif(readings, exit_code=exit_code), indent=2) + "\n"
    if fmt == "gcc":  # gcc's own words (error, warning, note), no summary: what editors match
        return "".join(
            d.format_text(_SARIF_LEVEL[d.severity]) + "\n"
            for r in readings
            for d in r.diagnostics
            if at_least is None or d.severity >= at_least
        )
    if at_least is not None:
        lines = [d.format_text() for r in readings for d in r.diagnostics if d.severity >= at_least]
        return "".join(line + "\n" for line in lines)
    return as_text(readings)


def _summary(diags) -> str:
    counts = Counter(d.severity for d in diags)
    parts = [
        f"{counts[s]} {s}{'s' if counts[s] != 1 else ''}"
        for s in (Severity.ERROR, Severity.WARNING, Severity.INFO)
    ]
    return ", ".join(parts)


def as_text(readings: list[ModelReading]) -> str:
    lines = []
    for reading in readings:
        lines += [d.format_text() for d in reading.diagnostics]
        # the file name as given: a newline in it must not start a forged diagnostic line
        lines.append(f"{printable(reading.file)}: {_summary(reading.diagnostics)}")
    return "\n".join(lines) + "\n"


def as_json(readings: list[ModelReading]) -> dict:
    files = []
    totals: Counter = Counter()
    for reading in readings:
        totals.update(str(d.severity) for d in reading.diagnostics)
        files.append(
            {
                "file": reading.file,
                "dialect": reading.uml.dialect,
                "readable": not reading.unreadable,
                "diagnostics": [d.to_dict() for d in reading.diagnostics],
            }
        )
    return {"files": files, "summary": {s: totals[s] for s in ("error", "warning", "info")}}


def _uri(path: str) -> str:
    """A URI for a path: relative as given (percent-encoded), or ``file://`` when absolute."""
    # Imported here: only SARIF needs them, and they cost `validate` 4 ms of start-up.
    from pathlib import PurePath
    from urllib.parse import quote

    pure = PurePath(path)
    return pure.as_uri() if pure.is_absolute() else quote(pure.as_posix())


def as_sarif(readings: list[ModelReading], *, exit_code: int = 0) -> dict:
    """SARIF 2.1.0 of the readings' diagnostics: see :func:`sarif_of`."""
    return sarif_of([d for r in readings for d in r.diagnostics], exit_code=exit_code)


def sarif_of(diagnostics: list[Diagnostic], *, exit_code: int = 0) -> dict:
    """SARIF 2.1.0 in the subset GitHub code scanning accepts (rules with levels, regions >= line 1).

    A result's fingerprint is its code, element id and subject (tag, rule), never its message:
    rewording a message must not reopen every alert. Two results with one fingerprint (two
    misspelt variables in one rule) are told apart by their order.
    """
    used = sorted({d.code for d in diagnostics})
    rules = []
    for code in used:
        rule = {
            "id": code,
            "name": CODES[code][1].title().replace(" ", "").replace("'", "")[:60],
            "shortDescription": {"text": CODES[code][1]},
            "defaultConfiguration": {"level": _SARIF_LEVEL[CODES[code][0]]},
        }
        uri = help_uri(code)
        if uri is not None:
            rule["helpUri"] = uri
        rules.append(rule)
    index = {code: n for n, code in enumerate(used)}
    results = []
    seen: Counter = Counter()
    for d in diagnostics:
        physical: dict = {"artifactLocation": {"uri": _uri(d.file)}}
        if d.line >= 1:
            region = {"startLine": d.line}
            if d.column >= 1:
                region["startColumn"] = d.column
            physical["region"] = region
        location: dict = {"physicalLocation": physical}
        if d.element:
            location["logicalLocations"] = [{"fullyQualifiedName": d.element, "kind": "type"}]
        key = d.fingerprint()
        seen[(d.file, key)] += 1
        if seen[(d.file, key)] > 1:
            key += f":{seen[(d.file, key)]}"
        results.append(
            {
                "ruleId": d.code,
                "ruleIndex": index[d.code],
                "level": _SARIF_LEVEL[d.severity],
                "message": {"text": d.message},
                "locations": [location],
                "partialFingerprints": {"acordcsFinding/v2": key},
            }
        )
    return {
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "acordcs-gen",
                        "version": __version__,
                        "informationUri": "https://github.com/acordcs/acordcs",
                        "rules": rules,
                    }
                },
                "invocations": [
                    {
                        # Exit 1 is a successful run that found problems; 2 is input it could
                        # not judge.
                        "executionSuccessful": exit_code != 2,
                        "exitCode": exit_code,
                    }
                ],
                "results": results,
                "columnKind": "unicodeCodePoints",
            }
        ],
    }
