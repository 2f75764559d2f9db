"""Tagged values: known tags, types, permitted values, positive frequencies, linguistic variables."""

from __future__ import annotations

import math
from collections.abc import Iterator
from itertools import pairwise

from acordcs.diagnostics import Diagnostic, article, within_edits
from acordcs.model.architecture import MONITOR, POLICY_SET, VARIABLE
from acordcs.model.checks.check_context import Context
from acordcs.model.queries import (
    parse_integer,
    parse_real,
    parsed_terms,
    suggestion,
    variable_range,
)
from acordcs.rules import RuleSyntaxError, TermDef
from acordcs.typed_values import parse_boolean

MISSPELT = 2
"""An unknown tag within this many edits of a tag of its stereotype is a misspelling of it (T320)."""

_PARSERS = {
    "Real": parse_real,
    "Integer": parse_integer,
    "Boolean": parse_boolean,
}


def tag_values(ctx: Context) -> Iterator[Diagnostic]:
    for role in ctx.arch.roles.values():
        for name, value in role.tags.items():
            declared = role.stereotype.tag(name)
            line, column = role.tag_line(name), role.tag_column(name)
            if declared is None:
                names = [t.name for t in role.stereotype.tags]
                close = [n for n in names if within_edits(name, n, MISSPELT)]
                if close:  # a typo: what the modeller meant is left unset, so it is an error
                    yield ctx.diag(
                        "T320",
                        f"<<{role.kind}>> has no tag {name!r} (did you mean {close[0]!r}?); "
                        f"{close[0]!r} is left unset: rename the tag",
                        role,
                        line=line,
                        column=column,
                        subject=name,
                    )
                    continue
                yield ctx.diag(
                    "T303",
                    f"<<{role.kind}>> has no tag {name!r}{suggestion(name, names)} (its tags: "
                    f"{', '.join(names) or 'none'}); it is ignored",
                    role,
                    line=line,
                    column=column,
                    subject=name,
                )
                continue
            if not value.strip():
                continue  # empty means unset (BOUML writes every declared tag)
            parser = _PARSERS.get(declared.type)
            if parser is not None and parser(value) is None:
                yield ctx.diag(
                    "T304",
                    f"tag {name!r} must be {article(declared.type)} {declared.type}, not {value!r}",
                    role,
                    line=line,
                    column=column,
                    subject=name,
                )
            elif declared.values and value.strip() not in declared.values:
                yield ctx.diag(
                    "T305",
                    f"tag {name!r} is {value!r}{suggestion(value.strip(), list(declared.values))}; "
                    f"permitted: {', '.join(declared.values)}",
                    role,
                    line=line,
                    column=column,
                    subject=name,
                )
        if role.kind in (MONITOR, POLICY_SET):
            frequency = role.tags.get("frequency", "").strip()
            value = parse_real(frequency) if frequency else None
            if value is not None and value <= 0:
                yield ctx.diag(
                    "T306",
                    f"frequency is {frequency} Hz; it must be positive (leave it unset for an "
                    "event-driven element)",
                    role,
                    line=role.tag_line("frequency"),
                )


def linguistic_variables(ctx: Context) -> Iterator[Diagnostic]:
    # What the terms say against the range depends on the three tags only, and models repeat a
    # few term lists over many variables: each distinct (terms, min, max) is examined once.
    findings: dict[tuple[str, str, str], list[tuple[str, str | tuple[float, float]]]] = {}
    for role in ctx.arch.of_kind(VARIABLE):
        line = role.tag_line("terms")
        bounds = variable_range(role)
        if bounds is None:
            yield ctx.diag(
                "T310",
                f"variable {role.name!r} needs tags min and max with min < max (has min="
                f"{role.tags.get('min')!r}, max={role.tags.get('max')!r})",
                role,
                line=role.tag_line("min"),
            )
        text = role.tags.get("terms", "")
        if not text.strip():
            yield ctx.diag(
                "T307",
                f"variable {role.name!r} has no terms; add a tag terms such as "
                "'low := trape 0 0 20 40; high := trape 20 40 100 100'",
                role,
                line=line,
            )
            continue
        terms = parsed_terms(text)
        if isinstance(terms, RuleSyntaxError):
            err = terms
            # the column is in the tag's value; in the file too when the file says where its
            # terms are (the text notation)
            where = role.application.place_in_file("terms", err.column - 1) if err.column else None
            yield ctx.diag(
                "T307",
                f"terms of {role.name!r}, column {err.column}: {err.message}",
                role,
                line=where[0] if where else line,
                column=where[1] if where else None,
            )
            continue
        # The tags' text, not the numbers: -0 and 0 are equal but printed differently.
        key = (text, role.tags.get("min", ""), role.tags.get("max", ""))
        found = findings.get(key)
        if found is None:
            found = findings[key] = _term_findings(terms, bounds)
        for code, what in found:
            if isinstance(what, tuple) and bounds is not None:  # T309 names the variable
                what = (
                    f"no term of {role.name!r} covers [{what[0]:g}, {what[1]:g}] of its range "
                    f"[{bounds[0]:g}, {bounds[1]:g}]: an input there fires no rule"
                )
            yield ctx.diag(code, what, role, line=line)


def _term_findings(
    terms: list[TermDef], bounds: tuple[float, float] | None
) -> list[tuple[str, str | tuple[float, float]]]:
    """(code, message) for what is wrong with ``terms``; for T309, (code, the gap)."""
    out: list[tuple[str, str | tuple[float, float]]] = []
    seen: set[str] = set()
    problems = [shape_problem(term) for term in terms]
    for term, problem in zip(terms, problems, strict=True):
        if term.name.text in seen:
            out.append(("T312", f"term {term.name.text!r} is defined twice"))
        seen.add(term.name.text)
        if problem:
            out.append(("T311", f"term {term.name.text!r}: {problem}"))
        elif bounds is not None:
            lo, hi = bounds
            outside = [x for x in support_points(term) if x < lo or x > hi]
            if outside:
                out.append(
                    (
                        "T308",
                        f"term {term.name.text!r} has point {outside[0]:g} outside the range "
                        f"[{lo:g}, {hi:g}]",
                    )
                )
    if bounds is not None and terms and not any(problems):
        gap = uncovered(terms, *bounds)
        if gap is not None:
            out.append(("T309", gap))
    return out


def shape_problem(term: TermDef) -> str | None:
    """Why the fuzzy engine would refuse this term, or None.

    The same rules as ``acordcs.engines.fuzzy.membership.make_membership`` (a property test keeps the
    two in step): the validator must not pass a model the engine then refuses at start-up.
    """
    p = term.parameters
    if not all(math.isfinite(v) for v in p):
        return "parameters must be finite numbers"
    if term.shape in ("trapezoid", "triangle"):
        if any(b < a for a, b in pairwise(p)):
            return f"points {' '.join(f'{x:g}' for x in p)} must not decrease"
        if p[0] == p[-1]:
            return "has zero width"
    elif term.shape == "points":
        xs, ys = p[0::2], p[1::2]
        if len(xs) < 2:
            return "a point list needs at least two (x, y) points"
        if any(b < a for a, b in pairwise(xs)):
            return "point x values must not decrease"
        if any(a == c for a, c in zip(xs, xs[2:], strict=False)):
            return "three points share one x; a vertical edge has two"
        if xs[0] == xs[-1]:
            return "the point list has zero width; use a singleton for a single point"
        if any(not 0.0 <= y <= 1.0 for y in ys):
            return "membership degrees must lie in [0, 1]"
    elif term.shape == "gaussian" and p[1] <= 0:
        return "the standard deviation must be positive"
    elif term.shape == "bell" and (p[0] <= 0 or p[1] <= 0):
        return "width a and slope b must be positive"
    elif term.shape == "sigmoid" and p[0] == 0:
        return "the sigmoid gain must not be 0"
    return None


def support_points(term: TermDef) -> list[float]:
    """The x positions that define the term (centres for smooth shapes)."""
    p = term.parameters
    if term.shape == "points":
        return list(p[0::2])
    if term.shape in ("gaussian",):
        return [p[0]]
    if term.shape == "bell":
        return [p[2]]
    if term.shape == "sigmoid":
        return [p[1]]
    return list(p)


def _positive_spans(term: TermDef) -> list[tuple[float, float]]:
    """Open intervals where the term's membership is positive (piecewise-linear shapes)."""
    p = term.parameters
    if term.shape == "points":
        xs, ys = list(p[0::2]), list(p[1::2])
        spans = [
            (x1, x2)
            for x1, x2, y1, y2 in zip(xs, xs[1:], ys, ys[1:], strict=False)
            if y1 > 0 or y2 > 0
        ]
        if ys[0] > 0:  # FCL point lists extend flat beyond their ends
            spans.append((-math.inf, xs[0]))
        if ys[-1] > 0:
            spans.append((xs[-1], math.inf))
        return spans
    if term.shape == "singleton":
        return []
    return [(p[0], p[-1])]


def uncovered(terms: list[TermDef], lo: float, hi: float) -> tuple[float, float] | None:
    """The first stretch of positive length in [lo, hi] where every term is zero, or None.

    Smooth shapes (gaussian, bell, sigmoid) are positive everywhere; singletons cover single points
    only (as output terms should), so they do not count as coverage.
    """
    if any(t.shape in ("gaussian", "bell", "sigmoid") for t in terms):
        return None
    if all(t.shape == "singleton" for t in terms):
        return None  # an output variable with singleton terms (Sugeno style)
    reach = lo
    for left, right in sorted(span for t in terms for span in _positive_spans(t)):
        if left > reach:
            return (reach, min(left, hi))
        reach = max(reach, right)
        if reach >= hi:
            return None
    return (reach, hi) if reach < hi else None


CHECKS = (tag_values, linguistic_variables)
"""This module's checks, in the order they run."""
