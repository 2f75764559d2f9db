"""One CLIPS environment (clipspy) with its messages captured and a lean function call.

clipspy's ``Environment.call`` converts every argument through generic helpers that allocate a new
``CLIPSValue`` each; on a 4-argument call that is half of a cycle's budget. :meth:`Bridge.call` reuses
one value and clipspy's own function-call builder, and converts the result with clipspy's
``python_value``. No ``Fact`` wrapper is ever created (those make the per-cycle cost grow).
"""

from __future__ import annotations

import clips
from clips import common
from clips._clips import ffi, lib
from clips.values import Symbol, python_value

from acordcs.runtime.clips.prelude import fixed_constructs

# Values passed to CLIPS: the engine validates them before they get here.
Scalar = bool | int | float | str | None


class ClipsFailure(Exception):
    """CLIPS refused a construct or a call; the message is what CLIPS printed."""


class _Capture(clips.Router):
    """Takes CLIPS's error and warning output (clipspy would print it to stderr) for our messages.

    Above clipspy's own error router (priority 40), so that one never accumulates text either.
    """

    LIMIT = 4000  # a runaway native rule must not grow this without bound

    def __init__(self) -> None:
        super().__init__("acordcs-capture", 50)
        self.text = ""

    def query(self, name: str) -> bool:
        return name in ("stderr", "stdwrn")

    def write(self, name: str, message: str) -> None:
        if len(self.text) < self.LIMIT:
            self.text += message

    def take(self) -> str:
        if not self.text:
            return ""
        text, self.text = self.text, ""
        return " ".join(text.split())


class Bridge:
    """The environment, its prelude, building constructs and the one call per fire."""

    def __init__(self) -> None:
        self.env = clips.Environment()
        self._capture = _Capture()
        self.env.add_router(self._capture)
        self._ptr = self.env._env  # the C environment, for the lean call
        self._builder = common.environment_builder(self._ptr, "function")
        self._arg = ffi.new("CLIPSValue *")
        self._result = ffi.new("CLIPSValue *")
        self._true = lib.CreateBoolean(self._ptr, True)
        self._false = lib.CreateBoolean(self._ptr, False)
        for construct in fixed_constructs():
            self.build(construct)

    @property
    def captured(self) -> bool:
        """Whether CLIPS printed anything since :meth:`messages` was last called."""
        return bool(self._capture.text)

    def messages(self) -> str:
        """What CLIPS printed to stderr/stdwrn since the last call (and forget it)."""
        return self._capture.take()

    def build(self, construct: str, module: str | None = None) -> None:
        """Build one construct, in ``module`` when it is not module-qualified. Raises ClipsFailure."""
        self._capture.take()
        previous = self.env.current_module
        try:
            if module is not None:
                self.env.current_module = self.env.find_module(module)
            self.env.build(construct)
        except clips.CLIPSError as err:
            raise ClipsFailure(
                self._capture.take() or str(err) or "CLIPS rejected the construct"
            ) from None
        finally:
            if module is not None:
                self.env.current_module = previous

    def run(self, expression: str) -> None:
        """Evaluate an expression for its effect; the result is dropped unconverted (no wrappers)."""
        self._capture.take()
        try:
            self.env.eval(f"(progn {expression} TRUE)")
        except clips.CLIPSError as err:
            raise ClipsFailure(self._capture.take() or str(err)) from None

    def undefine_rule(self, qualified_name: str) -> None:
        try:
            self.env.find_rule(qualified_name).undefine()
        except (LookupError, clips.CLIPSError):
            self._capture.take()  # already gone: nothing to undo

    def has_module(self, name: str) -> bool:
        try:
            self.env.find_module(name)
        except LookupError:
            return False
        return True

    def call(self, function: bytes, args: list[Scalar]) -> object:
        """Call a CLIPS function with scalar arguments in one round trip. Raises ClipsFailure."""
        ptr, arg, builder, append = self._ptr, self._arg, self._builder, lib.FCBAppend
        lib.FCBReset(builder)
        for value in args:
            kind = type(value)
            if kind is float:
                arg.value = lib.CreateFloat(ptr, value)
            elif kind is int:
                arg.value = lib.CreateInteger(ptr, value)
            elif kind is bool:
                arg.value = self._true if value else self._false
            elif kind is Symbol:
                arg.value = lib.CreateSymbol(ptr, value.encode())
            elif kind is str:
                arg.value = lib.CreateString(ptr, value.encode())
            else:  # None: never set
                arg.value = lib.CreateSymbol(ptr, b"nil")
            append(builder, arg)
        code = lib.FCBCall(builder, function, self._result)
        lib.FCBReset(builder)
        if code != lib.FCBE_NO_ERROR:
            raise ClipsFailure(
                self._capture.take() or f"CLIPS call {function.decode()} failed (code {code})"
            )
        return self._convert(self._result)

    def _convert(self, result: object) -> object:
        """The call's result; a multifield of scalars (the usual case) without clipspy's generic,
        per-value dispatch, which is a good part of a cycle."""
        if result.header.type != common.CLIPSType.MULTIFIELD:
            return python_value(self._ptr, result)
        multifield = result.multifieldValue
        contents = multifield.contents
        out = []
        for i in range(multifield.length):
            item = contents + i
            kind = item.header.type
            if kind == 0:
                out.append(item.floatValue.contents)
            elif kind == 1:
                out.append(item.integerValue.contents)
            elif kind == 2:
                out.append(Symbol(ffi.string(item.lexemeValue.contents).decode()))
            elif kind == 3:
                out.append(ffi.string(item.lexemeValue.contents).decode())
            else:
                out.append(python_value(self._ptr, item))
        return tuple(out)

    def value_of(self, global_name: str) -> object:
        """A global's value read directly (used to recover after a failed call)."""
        return self.env.find_global(global_name).value
