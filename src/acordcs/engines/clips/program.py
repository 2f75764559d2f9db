"""A CLIPS engine written out as one program another CLIPS loads and fires the same way.

The program holds what :class:`~acordcs.engines.clips.ClipsEngine` built in its environment: the
prelude (:mod:`.prelude`), one global per variable (``?*Element.attribute*``, its current value,
the model's default for an engine built from a plan), the dispatchers, one module per rule set
with its compiled rules. What the records of a fire stand for (variable numbers, call and
constant sites) is stated as facts (``acord-variable``, ``acord-site``), so a program other than
ours can read them. Use::

    (load "Recovering.clp") (reset) (acord-init)
    (acord-fire-set RecoveryRules FALSE 1 0.0)   ; set variable 1 to 0.0, run RecoveryRules
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from acordcs.engines.clips.clips_compiler import NUMERIC_FLAG, Target, quote
from acordcs.engines.clips.prelude import (
    FIRE,
    RUN,
    assign_dispatcher,
    fixed_constructs,
    put_dispatcher,
)
from acordcs.engines.clips.values import Value


@dataclass(frozen=True, slots=True)
class ProgramVariable:
    """A variable of the engine: its name, number, CLIPS global, value and declared type."""

    name: str
    index: int
    target: Target
    value: Value
    type_name: str = ""


def literal(value: Value) -> str:
    """A value as a CLIPS literal (``nil`` for unset). Raises ValueError for what CLIPS cannot
    hold as a literal (a NUL in a string, a number that is not finite)."""
    if value is None:
        return "nil"
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, str):
        if "\x00" in value:
            raise ValueError("a CLIPS string cannot hold a NUL character")
        return quote(value)
    if isinstance(value, int):
        return repr(value) if abs(value) < 2**63 else repr(float(value))
    if isinstance(value, float) and math.isfinite(value):
        return repr(value)
    raise ValueError(f"{value!r} cannot be written as a CLIPS literal")


def program_text(
    variables: Sequence[ProgramVariable],
    rule_sets: Sequence[tuple[str, Sequence[Sequence[str]]]],
    *,
    sites: Sequence[tuple[int, int, object]],
    rule_labels: dict[int, str],
    operations: Sequence[str],
    read: Sequence[int],
) -> str:
    """The program (see the module docstring): ``rule_sets`` as (name, each rule's constructs),
    ``sites`` the engine's numbered call and constant sites (entry 0 unused), ``rule_labels`` each
    crisp rule's ``Set::label`` by number, ``operations`` the operation names by number,
    ``read`` the variables some crisp rule reads (their facts are asserted by ``acord-init``)."""
    globals_ = [NUMERIC_FLAG] + [v.target.global_name for v in variables]
    out = list(fixed_constructs())
    out += [
        f"(defglobal MAIN {v.target.global_name} = {literal(v.value)} ?*acord-vf{v.index}* = FALSE)"
        for v in variables
    ]
    out.append(put_dispatcher(globals_))
    out.append(assign_dispatcher([v.name for v in variables], [v.target for v in variables]))
    out += [RUN, FIRE]
    out.append(
        "(deftemplate MAIN::acord-variable (slot number) (slot name) (slot type))\n"
        '(deftemplate MAIN::acord-site (slot number) (slot kind) (slot rule (default ""))'
        " (slot target) (slot arguments (default 0)) (slot value))"
    )
    facts = [
        f"  (acord-variable (number {v.index}) (name {quote(v.name)}) (type {quote(v.type_name)}))"
        for v in variables
    ]
    if facts:
        out.append("(deffacts MAIN::acord-variables\n" + "\n".join(facts) + ")")
    names = {v.index: v.name for v in variables}
    site_facts = []
    for number, (op, index, value) in enumerate(sites[1:], start=1):
        if op:  # a call: (op, rule, nargs)
            site_facts.append(
                f"  (acord-site (number {number}) (kind call) (rule {quote(rule_labels[index])})"
                f" (target {quote(operations[op])}) (arguments {value}))"
            )
        else:  # a constant assigned: (0, variable index, value)
            site_facts.append(
                f"  (acord-site (number {number}) (kind assign)"
                f" (target {quote(names[index])}) (value {literal(value)}))"  # type: ignore[arg-type]
            )
    if site_facts:
        out.append("(deffacts MAIN::acord-sites\n" + "\n".join(site_facts) + ")")
    init = " ".join(f"(bind ?*acord-vf{i}* (assert (acord-var (i {i}))))" for i in read)
    out.append(f"(deffunction MAIN::acord-init () {init} TRUE)")
    for name, rules in rule_sets:
        module = [f"(defmodule {name} (import MAIN ?ALL))"]
        for constructs in rules:
            module += constructs
        out.append("\n".join(module))
    return "\n\n".join(c.strip() for c in out if c) + "\n"
