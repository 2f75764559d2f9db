"""Engine registry: which constructor builds the rule engine for a policy set's ``engine`` tag.

A constructor takes an :class:`EngineSetup` (what the policy set knows: its name, fuzzy semantics,
linguistic variables, its plan, and a way to call operations through the container) and returns an
object implementing :class:`~acordcs.engines.rule_engine.RuleEngine` (``defrule``, ``set``,
``fire``, ``get``). The policy set then defines each rule with ``defrule`` and names variables as
its rules write them, unless the engine was registered with ``loads_plan``: then the constructor
builds the engine from ``setup.plan`` (:mod:`acordcs.engines.plan`), rules included, and variables
and operations are named ``Element.member``.

The two engine kinds of the metamodel are the table :data:`BUILTIN`, other packages' kinds the
entry points of group ``acordcs.engines`` (:mod:`acordcs.plugins` loads both); asking for
``fuzzy`` imports ``acordcs.engines.fuzzy`` (``clips``: ``acordcs.engines.clips``) the first time;
both load plans. :func:`register_engine` adds or replaces a kind in a running process (user code,
a hand-made engine).
"""

from __future__ import annotations

import importlib
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

from acordcs.diagnostics import article
from acordcs.engines.errors import EngineNotAvailableError
from acordcs.engines.rule_engine import RuleEngine
from acordcs.errors import ConfigurationError
from acordcs.plugins import PluginTable, Refused
from acordcs.rules.binding import rule_syntax
from acordcs.vocabularies import CLIPS_ENGINE, FUZZY_ENGINE

if TYPE_CHECKING:
    from acordcs.engines.plan import PolicyPlan
    from acordcs.rules import TermDef


@dataclass(frozen=True)
class Variable:
    """A linguistic variable as a policy set declares it (the model's CtxVariable): its universe and
    terms as FCL text (``slow := trape 0 0 40 80; ...``). The fuzzy engine builds its
    :class:`~acordcs.engines.fuzzy.variable.LinguisticVariable` from it."""

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
    """Every engine kind a policy set can name: the installed ones and those registered."""
    with _lock:
        return sorted({*_registry, *ENGINES.load()})


def lookup_engine(kind: str) -> Registered:
    """The constructor, rule syntax and plan loading of ``kind``; imports the built-in engines on
    first use."""
    with _lock:
        found = _registry.get(kind)
    if found is None:
        found = _installed(kind)
    if found is None:
        raise EngineNotAvailableError(
            f"no rule engine registered for engine kind {kind!r} "
            f"(registered: {', '.join(registered_engines()) or 'none'})",
            hint="; ".join(
                [
                    *ENGINES.problems,
                    "register_engine(kind, constructor) before adding the policy set",
                ]
            ),
        )
    return found


def _fuzzy(setup: EngineSetup) -> RuleEngine:
    module = importlib.import_module("acordcs.engines.fuzzy")
    return module.engine_for_plan(setup.plan)


def _clips(setup: EngineSetup) -> RuleEngine:
    module = importlib.import_module("acordcs.engines.clips")
    return module.engine_for_plan(setup.plan, call=setup.call)


FUZZY = Registered(_fuzzy, "fuzzy", loads_plan=True)
"""The fuzzy engine (:mod:`acordcs.engines.fuzzy`), built from a policy set's plan."""
CLIPS = Registered(_clips, "crisp", loads_plan=True)
"""The CLIPS engine (:mod:`acordcs.engines.clips`), built from a policy set's plan."""

ENTRY_POINT_GROUP = "acordcs.engines"
"""Other packages' engines: ``kind = "package.module:attribute"``, the attribute a
:class:`Registered` (constructor, rule syntax, whether it loads plans) or a constructor (crisp
rules by default, defined one by one with ``defrule``)."""

BUILTIN = {
    FUZZY_ENGINE: "acordcs.engines.engine_registry:FUZZY",
    CLIPS_ENGINE: "acordcs.engines.engine_registry:CLIPS",
}
"""The built-in engine kinds (the metamodel's): kind -> ``"module:attribute"`` of a
:class:`Registered`; the engine's own package is imported when a policy set first needs it."""

_PACKAGES = {FUZZY_ENGINE: "acordcs.engines.fuzzy", CLIPS_ENGINE: "acordcs.engines.clips"}


def _accept(kind: str, loaded: Any, origin: str) -> Registered:
    if isinstance(loaded, Registered):
        return loaded
    if callable(loaded):
        return Registered(loaded, rule_syntax(kind))
    raise Refused(
        f"is {article(type(loaded).__name__)} {type(loaded).__name__}, not an engine; point it at a Registered(constructor, "
        "syntax, loads_plan) or a constructor taking an EngineSetup"
    )


def table(**options: Any) -> PluginTable[Registered]:
    """A table of the built-in engine kinds and the entry points of :data:`ENTRY_POINT_GROUP`
    (``options``: ``entry_points``, ``extra``, as :class:`~acordcs.plugins.PluginTable` takes)."""
    return PluginTable(ENTRY_POINT_GROUP, "engine", BUILTIN, _accept, **options)


ENGINES: PluginTable[Registered] = table()
"""The engine kinds installed: the built-in ones and other packages' (loaded on first use)."""


def _installed(kind: str) -> Registered | None:
    found = ENGINES.load().get(kind)
    if found is None:
        return None
    package = _PACKAGES.get(kind)
    if package is not None and found in (FUZZY, CLIPS):
        try:
            importlib.import_module(package)
        except ImportError as exc:
            raise EngineNotAvailableError(
                f"engine kind {kind!r} needs {package}, which cannot be imported: {exc}",
                hint="install or write that engine, or register_engine() another one",
            ) from None
    with _lock:
        _registry.setdefault(kind, found)
        return _registry[kind]
