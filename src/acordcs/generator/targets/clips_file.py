"""A crisp policy set of the descriptor as one CLIPS file: the engine the runtime runs, written out.

The CLIPS engine is built from the set's plan (:func:`acordcs.engines.clips.engine_for_plan` over
:func:`acordcs.engines.plan.plan_from_descriptor`: the rules as the descriptor resolved them, the
variables typed as their attributes with the model's defaults) and written by
:meth:`acordcs.engines.clips.ClipsEngine.program` (see :mod:`acordcs.engines.clips.program` for
what the file holds and how to use it). Every name reaching the file is an identifier (checked
first); strings are escaped by the compiler's :func:`~acordcs.engines.clips.clips_compiler.quote`.
"""

from __future__ import annotations

from acordcs.descriptor import PolicySet
from acordcs.generator.targets.refused_names import NameRefused, require_identifiers


def _check(ps: PolicySet) -> None:
    names: list[tuple[str, object, str, str]] = [("policy set", ps.name, ps.id, ps.qualified_name)]
    for p in ps.policies:
        if p.name == "MAIN":
            raise NameRefused("policy (MAIN is CLIPS's own module)", p.name, p.id, p.qualified_name)
        names.append(("policy", p.name, p.id, p.qualified_name))
        names += [("rule label", r.label, p.id, p.qualified_name) for r in p.rules]
    for b in ps.bound:
        names += [("element", part, b.id, ps.qualified_name) for part in b.element.split(".")]
        names.append((b.kind, b.member, b.id, ps.qualified_name))
        if isinstance(b.default, str) and "\x00" in b.default:
            raise NameRefused("default value", b.default, b.id, ps.qualified_name)
    require_identifiers(names)


def clips_for(ps: PolicySet) -> str:
    """The CLIPS program of one crisp policy set (without the header). Raises NameRefused (a name
    that is not an identifier) or RuleError (a rule the compiler refuses: validate the model)."""
    from acordcs.engines.clips import engine_for_plan
    from acordcs.engines.plan import plan_from_descriptor

    _check(ps)
    return engine_for_plan(plan_from_descriptor(ps)).program()
