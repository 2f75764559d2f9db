"""One CLIPS environment (clipspy) with its messages captured and a lean function call; the one
module that touches clipspy's internals.

clipspy's ``Environment.call`` converts every argument through generic helpers that allocate a new
``CLIPSValue`` each, and its result field by field; on a 4-argument call that is half of a cycle's
budget. :meth:`Bridge.call` reuses one value and clipspy's own function-call builder, and leaves the
result to :mod:`.records`, which reads it directly. No ``Fact`` wrapper is ever created (those make
the per-cycle cost grow).

Everything the engine relies on below clipspy's public API (the cffi ``lib`` and ``ffi``, type codes,
the layout of the C values :mod:`.records` reads, the environment's C pointer, the function-call
builder, the generic value conversion) is imported here only, and checked when this module is
imported: a clipspy that changed any of it fails at import, naming what is missing.
"""

from __future__ import annotations

from collections.abc import Iterable

import clips
from clips import Symbol, common
from clips._clips import ffi, lib
from clips.values import python_value

# Values passed to CLIPS: the engine validates them before they get here.
Scalar = bool | int | float | str | None

# The C functions this module calls.
_LIB_FUNCTIONS = (
    "FCBReset",
    "FCBAppend",
    "FCBCall",
    "CreateFloat",
    "CreateInteger",
    "CreateSymbol",
    "CreateString",
    "CreateBoolean",
)
# The C struct fields read here, in the engine and in records.py.
_FIELDS = {
    "CLIPSValue": ("header", "floatValue", "integerValue", "lexemeValue", "multifieldValue"),
    "TypeHeader": ("type",),
    "Multifield": ("length", "contents"),
    "CLIPSFloat": ("contents",),
    "CLIPSInteger": ("contents",),
    "CLIPSLexeme": ("contents",),
}


def _missing_internals() -> list[str]:
    """The clipspy internals this package relies on that are not there (empty: all are)."""
    missing = [f"lib.{name}" for name in _LIB_FUNCTIONS if not hasattr(lib, name)]
    # records.py and the engine compare type codes as plain numbers: 0 float, 1 integer, 2 symbol,
    # 3 string, 4 multifield...; and a function call succeeded when its code is 0.
    if getattr(lib, "FCBE_NO_ERROR", None) != 0:
        missing.append("lib.FCBE_NO_ERROR == 0")
    if [int(t) for t in common.CLIPSType] != list(range(10)):
        missing.append(
            "common.CLIPSType codes 0..9 (FLOAT, INTEGER, SYMBOL, STRING, MULTIFIELD...)"
        )
    if not callable(getattr(common, "environment_builder", None)):
        missing.append("common.environment_builder")
    if "_env" not in getattr(clips.Environment, "__slots__", ()):
        missing.append("Environment._env (the C environment)")
    for struct, fields in _FIELDS.items():
        try:
            present = {name for name, _type in ffi.typeof(struct).fields}
        except ffi.error:
            present = set()
        missing.extend(f"{struct}.{field}" for field in fields if field not in present)
    return missing


if _missing := _missing_internals():
    raise ImportError(
        f"clipspy {getattr(clips, '__version__', '?')} lacks what acordcs.engines.clips relies on: "
        f"{', '.join(_missing)}; review acordcs/engines/clips/bridge.py and records.py "
        "(tests/engines/test_clips_records.py checks the conversions themselves)"
    )

# The C functions of the hot path, looked up once (an attribute of ``lib`` costs a lookup per use).
_reset, _append, _call = lib.FCBReset, lib.FCBAppend, lib.FCBCall
_float, _integer, _symbol, _string = (
    lib.CreateFloat,
    lib.CreateInteger,
    lib.CreateSymbol,
    lib.CreateString,
)
MULTIFIELD = int(common.CLIPSType.MULTIFIELD)
# For records.py: the bytes of a C string, and clipspy's generic conversion of a value (for those
# no rule produces, such as a native rule's fact address).
c_string = ffi.string
__all__ = ["MULTIFIELD", "Bridge", "ClipsFailure", "Scalar", "c_string", "python_value"]


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
    """The environment, building constructs and the one call per fire.

    ``constructs`` are built first, in order (the engine passes its prelude, :mod:`.prelude`).
    """

    def __init__(self, constructs: Iterable[str] = ()) -> None:
        self.env = clips.Environment()
        self.capture = _Capture()  # its text is non-empty when CLIPS printed something
        self.env.add_router(self.capture)
        self.ptr = self.env._env  # the C environment, for the lean call (checked at import)
        self._builder = common.environment_builder(self.ptr, "function")
        self._arg = ffi.new("CLIPSValue *")
        self._result = ffi.new("CLIPSValue *")
        self._true = lib.CreateBoolean(self.ptr, True)
        self._false = lib.CreateBoolean(self.ptr, False)
        for construct in constructs:
            self.build(construct)

    def messages(self) -> str:
        """What CLIPS printed to stderr/stdwrn since the last call (and forget it)."""
        return self.capture.take()

    def build(self, construct: str, module: str | None = None) -> None:
        """Build one construct, in ``module`` when it is not module-qualified. Raises ClipsFailure."""
        self.capture.take()
        previous = self.env.current_module
        try:
            if module is not None:
                self.env.current_module = self.env.find_module(module)
            self.env.build(construct)
        except clips.CLIPSError as err:
            raise ClipsFailure(
                self.capture.take() or str(err) or "CLIPS rejected the construct"
            ) from None
        finally:
            if module is not None:
                self.env.current_module = previous

    def run(self, expression: str) -> None:
        """Evaluate an expression for its effect; the result is dropped unconverted (no wrappers)."""
        self.capture.take()
        try:
            self.env.eval(f"(progn {expression} TRUE)")
        except clips.CLIPSError as err:
            raise ClipsFailure(self.capture.take() or str(err)) from None

    def undefine_rule(self, qualified_name: str) -> None:
        try:
            self.env.find_rule(qualified_name).undefine()
        except (LookupError, clips.CLIPSError):
            self.capture.take()  # already gone: nothing to undo

    def call(self, function: bytes, args: Iterable[Scalar]) -> object:
        """Call a CLIPS function with scalar arguments in one round trip. Raises ClipsFailure.

        Returns the ``CLIPSValue *`` result, valid until the next call (read it with
        :mod:`.records`). The arguments stay retained by the builder until the next call resets
        it: a reset after the call too would cost a C call for nothing.
        """
        ptr, arg, builder = self.ptr, self._arg, self._builder
        _reset(builder)
        for value in args:
            kind = type(value)
            if kind is float:
                arg.value = _float(ptr, value)
            elif kind is int:
                arg.value = _integer(ptr, value)
            elif kind is bool:
                arg.value = self._true if value else self._false
            elif kind is Symbol:
                arg.value = _symbol(ptr, value.encode())
            elif kind is str:
                arg.value = _string(ptr, value.encode())
            else:  # None: never set
                arg.value = _symbol(ptr, b"nil")
            _append(builder, arg)
        result = self._result
        code = _call(builder, function, result)
        if code:  # FCBE_NO_ERROR is 0 (checked at import)
            raise ClipsFailure(
                self.capture.take() or f"CLIPS call {function.decode()} failed (code {code})"
            )
        return result
