"""Target ``rules``: one FCL file per fuzzy policy set, one CLIPS file per crisp one.

``rules/<PolicySet>.fcl`` is the set's FCL function block (:mod:`.fcl`: names mapped to plain
identifiers so that jFuzzyLogic reads it); ``rules/<PolicySet>.clp`` is the set's CLIPS program
(:mod:`.clips`). Each starts with a header naming the policy set, its qualified name and id, and
the model file.

The one built-in target that is not an XSLT stylesheet (``config``, ``java``, ``python`` and
``shell`` are), by design: each file is the engine the
runtime builds for the set from its plan (:mod:`acordcs.engines.plan`), written out by the engine
package itself (the fuzzy engine's FCL writer; the CLIPS engine's program, with the constructs its
compiler made). A stylesheet would have to compile rules to CLIPS, and lay out FCL, a second time.
"""

from __future__ import annotations

from acordcs.generator.target import target
from acordcs.generator.targets.refused_names import NameRefused, refused
from acordcs.vocabularies import CLIPS_ENGINE, FUZZY_ENGINE


def _what(ps) -> str:
    return f"policy set '{ps.name}' ({ps.qualified_name}, id {ps.id})"


@target("rules", description="one FCL file per fuzzy policy set, one CLIPS file per crisp one")
def rules(context) -> None:
    """One FCL file per fuzzy policy set, one CLIPS file per crisp one."""
    from acordcs.engines.rule_engine import RuleError
    from acordcs.errors import RuntimeFailure
    from acordcs.generator.errors import BuildError

    app = context.application
    for ps in app.policy_sets:
        ids = (ps.id, *(p.id for p in ps.policies), *(b.id for b in ps.bound))
        try:
            if ps.engine == FUZZY_ENGINE:
                path, text = f"rules/{ps.name}.fcl", _fcl(context, ps)
            elif ps.engine == CLIPS_ENGINE:
                path, text = f"rules/{ps.name}.clp", _clips(context, ps)
            else:
                continue
        except NameRefused as err:
            raise refused(context, err, "FCL" if ps.engine == FUZZY_ENGINE else "CLIPS") from None
        except (RuleError, RuntimeFailure) as err:  # a rule or binding an engine refuses
            raise BuildError(
                f"target rules: policy set {ps.name}: {err.message}",
                file=context.source,
                element=ps.qualified_name,
                hint="validate the model (acordcs-gen validate) and fix what it reports",
            ) from None
        context.emit(path, text, element=ps.qualified_name, ids=ids)


def _fcl(context, ps) -> str:
    from acordcs.generator.targets.fcl_file import fcl_for

    made = fcl_for(ps)
    note = ""
    if made.hedged:
        note = (
            "Its rules use the hedges VERY or SOMEWHAT after IS, an acordcs extension "
            "jFuzzyLogic does not read."
        )
    head = context.header("fcl", _what(ps), note)
    if made.renamed:
        lines = ["Names in this file (FCL name := model name):"]
        lines += [f"  {fcl} := {model} ({what})" for what, model, fcl in made.renamed]
        from acordcs.generator.headers import comment

        head += comment("fcl", lines)
    return head + "\n" + made.text


def _clips(context, ps) -> str:
    from acordcs.generator.targets.clips_file import clips_for

    body = clips_for(ps)
    use = [
        "Use: (load <this file>) (reset) (acord-init); then, to fire a policy's rules,",
        "(acord-fire-set <Policy> FALSE <variable number> <value> ...): it returns the records of",
        "what the rules did (acord-variable and acord-site facts say what their numbers stand for).",
    ]
    from acordcs.generator.headers import comment

    return context.header("clips", _what(ps)) + comment("clips", use) + "\n" + body
