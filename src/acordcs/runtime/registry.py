"""Engine registry: which constructor builds the rule engine for a policy set's ``engine`` tag.

A constructor takes an :class:`EngineSetup` (what the policy set knows: its name, fuzzy semantics,
linguistic variables, its plan, and a way to call operations through the container) and returns an
object implementing :class:`~acordcs.runtime.rule_engine.RuleEngine` (``defrule``, ``set``,
``fire``, ``get``). The policy set then defines each rule with ``defrule`` and names variables as
its rules write them, unless the engine was registered with ``loads_plan``: then the constructor
builds the engine from ``setup.plan`` (:mod:`acordcs.runtime.plan`), rules included, and variables
and operations are named ``Element.member``.

The two engine kinds of the metamodel are registered lazily: asking for ``fuzzy`` imports
``acordcs.runtime.fuzzy`` (``clips``: ``acordcs.runtime.clips``) the first time, if it exists; both
load plans.
"""

from __future__ import annotations

import importlib
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

from acordcs.rules.binding import rule_syntax
from acordcs.runtime.errors import ConfigurationError, EngineNotAvailableError
from acordcs.runtime.rule_engine import RuleEngine

if TYPE_CHECKING:
    from acordcs.rules import TermDef
    from acordcs.runtime.plan import PolicyPlan


@dataclass(frozen=True)
class Variable:
    """A linguistic variable as a policy set declares it (the model's CtxVariable): its universe and
    terms as FCL text (``slow := trape 0 0 40 80; ...``). The fuzzy engine builds its
    :class:`~acordcs.runtime.fuzzy.variable.LinguisticVariable` from it."""

    lo: float
    hi: float
    terms: str | tuple[TermDef, ...] = ""


@dataclass
class EngineSetup:
    """What an engine constructor gets from the policy set it serves.

    ``call(target, args)`` invokes an operation written in a rule (``Recovery.recover`` or
    ``recover``) through the container, so interceptors and monitors see it.
    """

    policy_set: str
    kind: str
    semantics: str = "mamdani"
    variables: dict[str, Variable] = field(default_factory=dict)
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    operations: tuple[str, ...] = ()
    call: Callable[[str, tuple[Any, ...]], Any] = field(default=lambda target, args: None)
    plan: PolicyPlan | None = None


Constructor = Callable[[EngineSetup], RuleEngine]


class Registered(NamedTuple):
    """An engine kind's constructor, the syntax of its rules and whether it loads plans."""

    constructor: Constructor
    syntax: str
    loads_plan: bool = False


_registry: dict[str, Registered] = {}
_lock = threading.Lock()


def register_engine(
    kind: str, constructor: Constructor, *, syntax: str | None = None, loads_plan: bool = False
) -> None:
    """Register (or replace) the constructor for an engine kind; ``syntax``: ``fuzzy`` or ``crisp``
    rules (default: by kind, ``crisp`` for unknown kinds); ``loads_plan``: see the module docstring."""
    syntax = syntax or rule_syntax(kind)
    if syntax not in ("fuzzy", "crisp"):
        raise ConfigurationError(f"rule syntax must be 'fuzzy' or 'crisp', not {syntax!r}")
    with _lock:
        _registry[kind] = Registered(constructor, syntax, loads_plan)


def unregister_engine(kind: str) -> None:
    with _lock:
        _registry.pop(kind, None)


def registered_engines() -> list[str]:
    return sorted(_registry)


def lookup_engine(kind: str) -> Registered:
    """The constructor, rule syntax and plan loading of ``kind``; imports the built-in engines on
    first use."""
    with _lock:
        found = _registry.get(kind)
    if found is None and kind in _BUILTIN:
        _register_builtin(kind)
        with _lock:
            found = _registry.get(kind)
    if found is None:
        raise EngineNotAvailableError(
            f"no rule engine registered for engine kind {kind!r} "
            f"(registered: {', '.join(registered_engines()) or 'none'})",
            hint="register_engine(kind, constructor) before adding the policy set",
        )
    return found


def _fuzzy(setup: EngineSetup) -> RuleEngine:
    module = importlib.import_module("acordcs.runtime.fuzzy")
    return module.engine_for_plan(setup.plan)


def _clips(setup: EngineSetup) -> RuleEngine:
    module = importlib.import_module("acordcs.runtime.clips")
    return module.engine_for_plan(setup.plan, call=setup.call)


_BUILTIN: dict[str, tuple[str, Constructor]] = {
    "fuzzy": ("acordcs.runtime.fuzzy", _fuzzy),
    "clips": ("acordcs.runtime.clips", _clips),
}


def _register_builtin(kind: str) -> None:
    module_name, constructor = _BUILTIN[kind]
    try:
        importlib.import_module(module_name)
    except ImportError as exc:
        raise EngineNotAvailableError(
            f"engine kind {kind!r} needs {module_name}, which cannot be imported: {exc}",
            hint="install or write that engine, or register_engine() another one",
        ) from None
    register_engine(kind, constructor, loads_plan=True)
