"""The syntax tree of the ACORD-CS rule language: what :mod:`acordcs.rules.parser` parses to.

Every node is immutable and compares by value; the engines and the validator share them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import FrozenInstanceError, dataclass
from operator import attrgetter
from reprlib import recursive_repr
from typing import Literal

RuleKind = Literal["fuzzy", "crisp"]

# ---------------------------------------------------------------------------------------- the tree
# The tree classes behave as ``@dataclass(frozen=True, slots=True)`` made them (fields, equality,
# hashing, repr, immutability, copying, ``dataclasses.fields``), but their methods are written
# once, here: generating them cost 10 ms per process (each such class is built twice and exec's
# six functions), a tenth of validating a large model. ``@dataclass`` is still applied, with
# nothing to generate, for ``dataclasses.fields``, ``replace`` and ``asdict``.
_set = object.__setattr__
_TREE: set[type] = set()


def _tree(cls: type) -> type:
    """Register a tree class: its dataclass fields (with the class's ``_defaults``; only the
    ``_compare`` fields, all by default, take part in equality) and ``_key``, their values."""
    cls = dataclass(init=False, repr=False, eq=False)(cls)
    fields = cls.__dataclass_fields__  # type: ignore[attr-defined]
    compared = cls.__dict__.get("_compare", cls.__match_args__)  # type: ignore[attr-defined]
    for name, default in cls.__dict__.get("_defaults", ()):
        fields[name].default = default
    for name, field in fields.items():
        field.compare = name in compared
    if len(compared) == 1:
        cls._key = staticmethod(lambda node, name=compared[0]: (getattr(node, name),))  # type: ignore[attr-defined]
    else:
        cls._key = staticmethod(attrgetter(*compared))  # type: ignore[attr-defined]
    _TREE.add(cls)
    return cls


class _Frozen:
    __slots__ = ()
    __match_args__: tuple[str, ...] = ()  # the fields in order, set by @dataclass
    _key: Callable[[object], tuple]  # the compared fields' values, set by _tree

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return self._key(self) == self._key(other)
        return NotImplemented

    def __hash__(self) -> int:
        return hash(self._key(self))

    @recursive_repr()
    def __repr__(self) -> str:
        fields = ", ".join(f"{name}={getattr(self, name)!r}" for name in self.__match_args__)
        return f"{type(self).__qualname__}({fields})"

    def __setattr__(self, name: str, value: object) -> None:
        if type(self) in _TREE or name in self.__match_args__:
            raise FrozenInstanceError(f"cannot assign to field {name!r}")
        _set(self, name, value)

    def __delattr__(self, name: str) -> None:
        if type(self) in _TREE or name in self.__match_args__:
            raise FrozenInstanceError(f"cannot delete field {name!r}")
        object.__delattr__(self, name)

    def __getstate__(self) -> list:  # pickle and copy: slots, and __setattr__ refuses
        return [getattr(self, name) for name in self.__match_args__]

    def __setstate__(self, state: list) -> None:
        for name, value in zip(self.__match_args__, state, strict=False):
            _set(self, name, value)


@_tree
class Name(_Frozen):
    """A variable or operation reference as written, with its column in the rule text."""

    __slots__ = ("column", "text")
    text: str
    column: int

    def __init__(self, text: str, column: int) -> None:
        _set(self, "text", text)
        _set(self, "column", column)

    @property
    def element(self) -> str | None:
        """The qualifying element name (``A.b`` -> ``A``), or None when unqualified."""
        head, dot, _ = self.text.rpartition(".")
        return head if dot else None

    @property
    def member(self) -> str:
        """The attribute or operation name (``A.b`` -> ``b``)."""
        return self.text.rpartition(".")[2]


@_tree
class Is(_Frozen):
    """``var is [hedges] term``; hedges apply innermost last: ``not very high`` = 1 - high**2."""

    __slots__ = ("hedges", "term", "var")
    var: Name
    hedges: tuple[str, ...]
    term: Name

    def __init__(self, var: Name, hedges: tuple[str, ...], term: Name) -> None:
        _set(self, "var", var)
        _set(self, "hedges", hedges)
        _set(self, "term", term)


class _Unary(_Frozen):
    __slots__ = ()

    def __init__(self, operand: object) -> None:
        _set(self, "operand", operand)


@_tree
class Not(_Unary):
    """``not operand``."""

    __slots__ = ("operand",)
    operand: object


@_tree
class Neg(_Unary):
    """``- operand``."""

    __slots__ = ("operand",)
    operand: object


class _Binary(_Frozen):
    __slots__ = ()

    def __init__(self, op: str, left: object, right: object) -> None:
        _set(self, "op", op)
        _set(self, "left", left)
        _set(self, "right", right)


@_tree
class BoolOp(_Binary):
    """``and`` / ``or`` of two operands (left-associative chains nest on the left)."""

    __slots__ = ("left", "op", "right")
    op: Literal["and", "or"]
    left: object
    right: object


@_tree
class Compare(_Binary):
    """``left op right``, op one of ``== != < <= > >=``."""

    __slots__ = ("left", "op", "right")
    op: str
    left: object
    right: object


@_tree
class Arith(_Binary):
    """``left op right``, op one of ``+ - * /``."""

    __slots__ = ("left", "op", "right")
    op: str
    left: object
    right: object


@_tree
class Const(_Frozen):
    """A literal; ``column`` (where it is, for errors) takes no part in equality."""

    __slots__ = ("column", "value")
    value: int | float | str | bool
    column: int | None
    _defaults = (("column", None),)
    _compare = ("value",)

    def __init__(self, value: int | float | str | bool, column: int | None = None) -> None:
        _set(self, "value", value)
        _set(self, "column", column)


@_tree
class VarRef(_Frozen):
    """A variable read in a crisp expression."""

    __slots__ = ("var",)
    var: Name

    def __init__(self, var: Name) -> None:
        _set(self, "var", var)


@_tree
class Consequent(_Frozen):
    """``var is term`` after ``then`` (fuzzy)."""

    __slots__ = ("term", "var")
    var: Name
    term: Name

    def __init__(self, var: Name, term: Name) -> None:
        _set(self, "var", var)
        _set(self, "term", term)


@_tree
class Assign(_Frozen):
    """``var = value`` after ``then`` (crisp)."""

    __slots__ = ("value", "var")
    var: Name
    value: object

    def __init__(self, var: Name, value: object) -> None:
        _set(self, "var", var)
        _set(self, "value", value)


@_tree
class Call(_Frozen):
    """``Element.operation(args)`` after ``then`` (crisp)."""

    __slots__ = ("args", "target")
    target: Name
    args: tuple[object, ...]

    def __init__(self, target: Name, args: tuple[object, ...]) -> None:
        _set(self, "target", target)
        _set(self, "args", args)


@_tree
class Rule(_Frozen):
    """One parsed rule. ``actions`` are Consequents (fuzzy) or Assign/Call (crisp)."""

    __slots__ = ("actions", "condition", "kind", "label", "text", "weight")
    kind: RuleKind
    label: str | None
    condition: object
    actions: tuple[object, ...]
    weight: float
    text: str
    _defaults = (("weight", 1.0), ("text", ""))

    def __init__(
        self,
        kind: RuleKind,
        label: str | None,
        condition: object,
        actions: tuple[object, ...],
        weight: float = 1.0,
        text: str = "",
    ) -> None:
        _set(self, "kind", kind)
        _set(self, "label", label)
        _set(self, "condition", condition)
        _set(self, "actions", actions)
        _set(self, "weight", weight)
        _set(self, "text", text)

    def variables_read(self) -> list[Name]:
        """Variables the condition reads, in order of appearance (for fuzzy: inputs)."""
        return names_in(self.condition)

    def variables_written(self) -> list[Name]:
        """Variables the actions assign (for fuzzy: outputs)."""
        return [a.var for a in self.actions if isinstance(a, Consequent | Assign)]

    def calls(self) -> list[Call]:
        return [a for a in self.actions if isinstance(a, Call)]


@_tree
class TermDef(_Frozen):
    """A linguistic term: its name, shape and parameters (FCL order; points as x1 y1 x2 y2 ...)."""

    __slots__ = ("name", "parameters", "shape")
    name: Name
    shape: str
    parameters: tuple[float, ...]

    def __init__(self, name: Name, shape: str, parameters: tuple[float, ...]) -> None:
        _set(self, "name", name)
        _set(self, "shape", shape)
        _set(self, "parameters", parameters)


@dataclass(init=False, repr=False, eq=False)
class RuleLine:
    """One rule of a tag value: its text and where it sits in the tag (1-based line)."""

    __slots__ = ("label", "line", "text")
    text: str
    line: int
    label: str | None

    def __init__(self, text: str, line: int, label: str | None = None) -> None:
        self.text = text
        self.line = line
        self.label = label

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return _rule_line(self) == _rule_line(other)
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]  # mutable: unhashable, as the dataclass was
    __repr__ = _Frozen.__repr__  # type: ignore[assignment]


_rule_line = attrgetter("text", "line", "label")
RuleLine.__dataclass_fields__["label"].default = None  # type: ignore[attr-defined]


def names_in(node: object) -> list[Name]:
    """Variables an expression or condition reads, in order of appearance."""
    out: list[Name] = []
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, Is | VarRef):
            out.append(n.var)
        elif isinstance(n, BoolOp | Compare | Arith):
            stack.extend((n.right, n.left))
        elif isinstance(n, Not | Neg):
            stack.append(n.operand)
    return out


# ------------------------------------------------------------------------------- nesting limit
# Every consumer of the tree (the fuzzy and CLIPS compilers, CLIPS's own C parser, repr and
# equality) walks it recursively: a condition nested (or chained: ``a and b and c`` nests to the
# left) thousands deep would exhaust Python's stack at run time. The parser refuses such rules,
# so the validator reports them, and the engines check trees they are given directly.
MAX_DEPTH = 200
# The fuzzy engine's limits on a linguistic variable, checked by the model checks (T315), by
# define_variable and by the FCL reader: above them a firing and the generated rule set grow
# beyond what a controller needs (1,000 deeply overlapping output terms fire in ~0.1 s), and a
# point list's generated membership nests one branch per point (thousands exhaust Python's
# compiler stack).
MAX_TERMS = 1000
MAX_POINTS = 500
# A number's longest text: int() refuses 4,300 digits and more, and no rule needs more than a
# double's range.
MAX_NUMBER = 64


def number_value(text: str) -> int | float:
    """A crisp literal's value: integer literals stay integers (``retries + 1`` must not turn a
    count into 1.0)."""
    return int(text) if text.lstrip("+-").isdigit() else float(text)


_NESTING = (BoolOp, Compare, Arith, Not, Neg)


def deepest(node: object, limit: int = MAX_DEPTH) -> tuple[int, object] | None:
    """``(depth, node)`` for the first operator found deeper than ``limit`` levels of and, or, not,
    comparison and arithmetic below ``node``, or None when the whole tree is within the limit."""
    stack = [(node, 1)]
    while stack:
        n, depth = stack.pop()
        if not isinstance(n, _NESTING):
            continue
        if depth > limit:
            return depth, n
        if isinstance(n, Not | Neg):
            stack.append((n.operand, depth + 1))
        else:
            stack.extend(((n.right, depth + 1), (n.left, depth + 1)))
    return None


def rule_too_deep(rule: Rule, limit: int = MAX_DEPTH) -> tuple[int, object] | None:
    """:func:`deepest` over a rule's condition and the values of its actions."""
    roots: list[object] = [rule.condition]
    for action in rule.actions:
        if isinstance(action, Assign):
            roots.append(action.value)
        elif isinstance(action, Call):
            roots.extend(action.args)
    for root in roots:
        found = deepest(root, limit)
        if found:
            return found
    return None


def column_of(node: object) -> int | None:
    """The column of the leftmost name or literal in ``node`` (only those carry one)."""
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, Is | VarRef):
            return n.var.column
        if isinstance(n, Const) and n.column:
            return n.column
        if isinstance(n, BoolOp | Compare | Arith):
            stack.extend((n.right, n.left))
        elif isinstance(n, Not | Neg):
            stack.append(n.operand)
    return None


def depth_message(limit: int = MAX_DEPTH) -> str:
    """What a rule nested too deep is told (the parser, the validator and the engines say the same)."""
    return (
        f"the rule nests deeper than the limit of {limit} levels (each and, or, not, comparison "
        "or arithmetic operator of a chain counts one); split it into several rules"
    )
