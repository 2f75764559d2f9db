"""The ACORD-CS text notation (``docs/notation.md``): a model written as text, equal to its UML
form, read by every command as XMI is and converted both ways (``acordcs-gen convert``).

A model file whose name ends in :data:`SUFFIX` is read as the notation; any other as XMI. The
grammar is ``acord.lark``; the text is parsed into an outline (:mod:`.outline`, :mod:`.syntax`)
and read as the neutral UML view the XMI readers make (:mod:`.text_model`), so that the checks,
the descriptor and the build are the same for both.
"""

from __future__ import annotations

import os
import stat

from acordcs.diagnostics import diagnostic
from acordcs.xmi.uml import UmlModel

SUFFIX = ".acord"


def is_notation(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` names a model in the notation (by its suffix)."""
    return os.fspath(path).lower().endswith(SUFFIX)


def read_bytes(path: str) -> bytes:
    """The bytes of the model file ``path``: only a regular file (a named pipe would block, a
    device never end), at most the notation's size limit. Raises NotationError (X101, M102)."""
    from acordcs.notation.syntax import MAX_BYTES, NotationError, NotationLimitError

    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with open(fd, "rb") as handle:
            status = os.fstat(handle.fileno())
            if not stat.S_ISREG(status.st_mode):
                raise NotationError(
                    "cannot read file: it is not a regular file; give the path of a model file",
                    file=path,
                    code="X101",
                )
            data = handle.read(MAX_BYTES + 1)
    except OSError as err:
        reason = err.strerror or str(err)
        raise NotationError(f"cannot read file: {reason}", file=path, code="X101") from None
    if len(data) > MAX_BYTES:
        raise NotationLimitError(
            f"file is over the notation's {MAX_BYTES // 2**20} MiB limit: split the model",
            file=path,
        )
    return data


def read_text_model(path: str) -> UmlModel:
    """The UML view of the model in the notation at ``path``; never raises for bad input: what
    makes the text unreadable is its diagnostic (M101, M102, X101: exit code 2)."""
    from acordcs.notation.syntax import NotationError, parse_text
    from acordcs.notation.text_model import uml_of

    try:
        outline = parse_text(read_bytes(path), path)
    except NotationError as err:
        found = diagnostic(
            err.code, err.message, file=path, line=err.line or 0, column=err.column or 0
        )
        return UmlModel(file=path, dialect="unreadable", diagnostics=[found])
    return uml_of(outline, path)
