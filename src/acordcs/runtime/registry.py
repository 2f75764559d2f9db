"""Engine registry: which constructor builds the rule engine for a policy set's ``engine`` tag.

A constructor takes an :class:`EngineSetup` (what the policy set knows: its name, fuzzy semantics,
linguistic variables, and a way to call operations through the container) and returns an object
implementing :class:`~acordcs.runtime.rule_engine.RuleEngine` (``defrule``, ``set``, ``fire``, ``get``).

The two engine kinds of the metamodel are registered lazily: asking for ``fuzzy`` imports
``acordcs.runtime.fuzzy`` (``clips``: ``acordcs.runtime.clips``) the first time, if it exists.
"""

from __future__ import annotations

import importlib
import inspect
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from acordcs.runtime.errors import ConfigurationError, EngineNotAvailableError
from acordcs.runtime.rule_engine import RuleEngine


@dataclass(frozen=True)
class Variable:
    """A linguistic variable as a policy set declares it (the model's CtxVariable): its universe and
    terms as FCL text (``slow := trape 0 0 40 80; ...``). The fuzzy engine builds its
    :class:`~acordcs.runtime.fuzzy.variable.LinguisticVariable` from it."""

    lo: float
    hi: float
    terms: str = ""


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


Constructor = Callable[[EngineSetup], RuleEngine]
RULE_SYNTAX = {"fuzzy": "fuzzy", "clips": "crisp"}

_registry: dict[str, tuple[Constructor, str]] = {}
_lock = threading.Lock()


def register_engine(kind: str, constructor: Constructor, *, syntax: str | None = None) -> None:
    """Register (or replace) the constructor for an engine kind; ``syntax``: ``fuzzy`` or ``crisp``
    rules (default: by kind, ``crisp`` for unknown kinds)."""
    syntax = syntax or RULE_SYNTAX.get(kind, "crisp")
    if syntax not in ("fuzzy", "crisp"):
        raise ConfigurationError(f"rule syntax must be 'fuzzy' or 'crisp', not {syntax!r}")
    with _lock:
        _registry[kind] = (constructor, syntax)


def unregister_engine(kind: str) -> None:
    with _lock:
        _registry.pop(kind, None)


def registered_engines() -> list[str]:
    return sorted(_registry)


def lookup_engine(kind: str) -> tuple[Constructor, str]:
    """The constructor and rule syntax for ``kind``; imports the built-in engines on first use."""
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
    engine_cls = module.FuzzyEngine
    params = inspect.signature(engine_cls).parameters
    engine = engine_cls(semantics=setup.semantics) if "semantics" in params else engine_cls()
    for name, var in setup.variables.items():
        engine.define_variable(name, var.lo, var.hi, var.terms)
    return engine


def _clips(setup: EngineSetup) -> RuleEngine:
    module = importlib.import_module("acordcs.runtime.clips")
    engine = module.ClipsEngine()
    for name in dict.fromkeys((*setup.inputs, *setup.outputs)):
        engine.declare(name)
    for target in setup.operations:
        engine.declare_operation(target)
        engine.bind_operation(target, lambda *args, _t=target: setup.call(_t, args))
    return engine


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
    register_engine(kind, constructor)
