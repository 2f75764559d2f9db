"""The rule engines behind the paper's four calls (``defrule``, ``set``, ``fire``, ``get``).

- :mod:`.rule_engine`: the interface every engine implements and :class:`RuleError`;
- :mod:`.errors`: what building an engine for a policy set can fail with;
- :mod:`.plan`: a policy set's plan, its rules as the descriptor resolved them;
- :mod:`.engine_registry`: which constructor builds the engine of a policy set's ``engine`` tag
  (the built-in table, and the entry-point group ``acordcs.engines`` for plug-ins);
- :mod:`.fuzzy`, :mod:`.clips`: the fuzzy engine and the CLIPS engine, each built from a plan,
  each writing itself out (FCL; a CLIPS program).

The runtime hosts engines (:mod:`acordcs.runtime.policy`); the generator writes rule files through
them (target ``rules``). Neither package is imported from here: importing ``acordcs.engines``
loads no engine.
"""
