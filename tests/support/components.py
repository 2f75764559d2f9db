"""Shared pieces of the runtime tests: a small but real crisp rule engine, and a few components."""

from __future__ import annotations

import operator
from typing import Any, ClassVar

from acordcs.engines.engine_registry import EngineSetup
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import (
    Arith,
    Assign,
    BoolOp,
    Call,
    Compare,
    Const,
    Neg,
    Not,
    VarRef,
    parse_rule,
)
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.ports import async_port, stream_port, sync_port

_CMP = {
    "==": operator.eq,
    "!=": operator.ne,
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
}
_ARITH = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv}


class CrispEngine:
    """Evaluates the crisp rule syntax: every rule whose condition holds runs its actions, in order.

    Implements the RuleEngine protocol (defrule/set/fire/get); calls go to ``setup.call``.
    """

    def __init__(self, setup: EngineSetup) -> None:
        self.setup = setup
        self.rulesets: dict[str, dict[str, Any]] = {}
        self.values: dict[str, object] = {}
        self.fired: list[str] = []

    def defrule(self, rule: str, ruleset: str) -> str:
        parsed = parse_rule(rule, "crisp")
        rules = self.rulesets.setdefault(ruleset, {})
        label = parsed.label or f"rule{len(rules) + 1}"
        rules[label] = parsed
        return label

    def set(self, variable: str, value: object) -> None:
        self.values[variable] = value

    def get(self, variable: str) -> object:
        return self.values.get(variable)

    def fire(self, ruleset: str) -> None:
        if ruleset not in self.rulesets:
            raise RuleError(f"no rule set {ruleset!r}", ruleset=ruleset)
        for label, rule in self.rulesets[ruleset].items():
            if self._eval(rule.condition):
                self.fired.append(label)
                for action in rule.actions:
                    if isinstance(action, Assign):
                        self.values[action.var.text] = self._eval(action.value)
                    elif isinstance(action, Call):
                        args = tuple(self._eval(a) for a in action.args)
                        self.setup.call(action.target.text, args)

    def _eval(self, node: object) -> Any:
        if isinstance(node, Const):
            return node.value
        if isinstance(node, VarRef):
            if node.var.text not in self.values:
                raise RuleError(f"variable {node.var.text!r} has no value", column=node.var.column)
            return self.values[node.var.text]
        if isinstance(node, Compare):
            return _CMP[node.op](self._eval(node.left), self._eval(node.right))
        if isinstance(node, Arith):
            return _ARITH[node.op](self._eval(node.left), self._eval(node.right))
        if isinstance(node, Neg):
            return -self._eval(node.operand)
        if isinstance(node, Not):
            return not self._eval(node.operand)
        if isinstance(node, BoolOp):
            left = self._eval(node.left)
            if node.op == "and":
                return left and self._eval(node.right)
            return left or self._eval(node.right)
        raise RuleError(f"cannot evaluate {node!r}")


class Counter(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"count": 0, "limit": 10}
    ports = (sync_port("api", operations=("bump", "value")),)
    state_fields = ("history",)

    def __init__(self) -> None:
        self.history: list[int] = []

    def bump(self, by: int = 1) -> int:
        value = int(self.get("count")) + by  # type: ignore[call-overload]
        self.set("count", value)
        self.history.append(value)
        return value

    def value(self) -> int:
        return int(self.get("count"))  # type: ignore[call-overload]

    def fail(self) -> None:
        raise ZeroDivisionError("counter exploded on purpose")


class Client(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"calls": 0}
    ports = (sync_port("api", role="required"),)

    def use(self, by: int = 1) -> int:
        return self.port("api").call("bump", by)


class BetterCounter(Counter):
    """A replacement type: same ports, counts twice as fast, keeps the state."""

    def bump(self, by: int = 1) -> int:
        return super().bump(2 * by)


class Sender(CtxComponent):
    ports = (async_port("out", role="required"),)

    def send(self, message: Any) -> None:
        self.port("out").notify(message)


class Receiver(CtxComponent):
    ports = (async_port("inbox", capacity=3),)

    def __init__(self) -> None:
        self.got: list[Any] = []

    def on_inbox(self, message: Any) -> None:
        if message == "boom":
            raise RuntimeError("receiver cannot digest boom")
        self.got.append(message)


class Camera(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"frames": 0}
    ports = (stream_port("video", rate=10.0, source="grab"),)

    def grab(self) -> dict[str, int]:
        n = int(self.props["frames"]) + 1  # type: ignore[call-overload]
        self.props["frames"] = n
        return {"frame": n}


class Screen(CtxComponent):
    ports = (stream_port("video", role="required"),)

    def __init__(self) -> None:
        self.frames: list[int] = []

    def on_video(self, item: dict[str, int]) -> None:
        self.frames.append(item["frame"])
