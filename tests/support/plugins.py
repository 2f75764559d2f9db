"""What the plug-in tests' entry points name: an engine kind and model checks of "another package"."""

from __future__ import annotations

from acordcs.diagnostics import diagnostic
from acordcs.engines.engine_registry import EngineSetup, Registered


class EchoEngine:
    """A crisp engine that copies each variable set to ``<name>.echo``."""

    def __init__(self, setup: EngineSetup) -> None:
        self.setup = setup
        self.values: dict[str, object] = {}

    def defrule(self, rule: str, ruleset: str) -> str:
        return rule

    def set(self, variable: str, value: object) -> None:
        self.values[variable] = value
        self.values[variable + ".echo"] = value

    def fire(self, ruleset: str) -> None:
        return None

    def get(self, variable: str) -> object:
        return self.values[variable]


ECHO = Registered(EchoEngine, "crisp")


def no_component_named_test(ctx):
    """A check of another package: every component named ``Test`` is refused."""
    for role in ctx.arch.of_kind("CtxComponent"):
        if role.name == "Test":
            yield diagnostic("N601", "a component named Test", file=ctx.uml.file)


def counts_components(ctx):
    """A check that finds nothing, and says so by being called."""
    CALLS.append(len(ctx.arch.of_kind("CtxComponent")))
    return ()


CALLS: list[int] = []
