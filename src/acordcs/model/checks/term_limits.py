"""The fuzzy engine's limits on a linguistic variable (T315): at most ``MAX_TERMS`` terms, and at
most ``MAX_POINTS`` points in a point-list term. The engine refuses such a variable when the
application starts; the validator says so first, with the same numbers."""

from __future__ import annotations

from collections.abc import Iterator

from acordcs.diagnostics import Diagnostic
from acordcs.model.architecture import VARIABLE
from acordcs.model.checks.check_context import Context
from acordcs.model.queries import variable_terms
from acordcs.rules.tree import MAX_POINTS, MAX_TERMS


def term_limits(ctx: Context) -> Iterator[Diagnostic]:
    for role in ctx.arch.of_kind(VARIABLE):
        terms = variable_terms(role)
        line = role.tag_line("terms")
        if len(terms) > MAX_TERMS:
            yield ctx.diag(
                "T315",
                f"variable {role.name!r} has {len(terms):,} terms; the fuzzy engine takes at most "
                f"{MAX_TERMS:,} per variable (every firing and the generated rule set grow with "
                "them); merge terms or split the variable",
                role,
                line=line,
            )
        for term in terms:
            points = len(term.parameters) // 2 if term.shape == "points" else 0
            if points > MAX_POINTS:
                yield ctx.diag(
                    "T315",
                    f"term {term.name.text!r} of {role.name!r} is a point list of {points:,} "
                    f"points; the fuzzy engine takes at most {MAX_POINTS} per term (its generated "
                    "code has a branch per point); simplify the shape",
                    role,
                    line=line,
                    subject=term.name.text,
                )


CHECKS = (term_limits,)
"""This module's checks, in the order they run."""
