"""The model files a command is given: ``-`` for standard input (XMI, or the text notation when
it starts as one does: a comment or a keyword), and files that are not models
(a Papyrus diagram ``.notation``, its ``.di``) refused before they are read.

A Papyrus ``.notation`` file is XMI and declares the UML namespace, so the reader alone would read
it as an empty model and pass it: the user picked the wrong file of the three Papyrus writes.
"""

from __future__ import annotations

import os
import re
import shutil
import stat
import sys
import tempfile
from pathlib import Path

from acordcs.diagnostics import diagnostic
from acordcs.model.reading import ModelReading, read_model
from acordcs.notation import SUFFIX as NOTATION_SUFFIX
from acordcs.xmi.uml import UmlModel

STDIN = "-"
STDIN_NAME = "<stdin>"  # how diagnostics name standard input

# Papyrus saves a model as three files: NAME.uml (the model), NAME.notation (diagrams), NAME.di.
_DIAGRAM_SUFFIXES = {
    ".notation": "a Papyrus diagram file",
    ".di": "a Papyrus editor file",
}
# Diagram files that were renamed: the GMF notation or Papyrus sash namespace, and no model in the
# first 64 KB (a .uml file never declares them).
_DIAGRAM_NS = re.compile(
    rb"xmlns:\w+=\"http://www\.eclipse\.org/(gmf/runtime/[\d.]+/notation|papyrus/[\d.]+/sashdi)\""
)
_MODEL_CONTENT = re.compile(rb"<(uml:Model|uml:Package|uml:Profile|packagedElement)[\s>/]")


def read_models(paths: tuple[str, ...] | list[str], *, check: bool = True) -> list[ModelReading]:
    """Read every path (``-`` once at most: standard input) as :func:`read_model` does."""
    return [read_one(p, check=check) for p in paths]


def read_one(path: str, *, check: bool = True) -> ModelReading:
    """One model, or a reading holding the X101/X109 diagnostic that refuses it (exit code 2)."""
    if path == STDIN:
        return _read_stdin(check)
    refusal = _not_a_model(path)
    if refusal is not None:
        return _refused(path, refusal)
    return read_model(path, check=check)


def _not_a_model(path: str) -> str | None:
    """Why ``path`` is not a model file, or None."""
    what = _DIAGRAM_SUFFIXES.get(Path(path).suffix.lower())
    try:
        regular = stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return None  # the reader says why it cannot be read (X101)
    if what is None and not regular:
        return None  # a pipe or a device: never opened here (it could block); the reader refuses it
    if what is None:
        try:
            with open(path, "rb") as handle:
                head = handle.read(65536)
        except OSError:
            return None  # the reader says why it cannot be read (X101)
        if not _DIAGRAM_NS.search(head) or _MODEL_CONTENT.search(head):
            return None
        what = "a Papyrus diagram file"
    model = Path(path).with_suffix(".uml").name
    return (
        f"{what}, not a model: it holds diagrams that point into the model; validate the model "
        f"file beside it ({model}) or, from BOUML, the XMI 2.1 export"
    )


# How a model in the text notation starts: a comment, or a keyword of a model's first line.
_NOTATION_START = re.compile(
    rb"(//|#|/\*|(model|package|container|component|port|connection|monitor|policyset|policy)\b)"
)


def _is_text_notation(path: str) -> bool:
    """Standard input has no name to tell its form by: the text notation starts with a comment
    or a keyword (after blanks and a byte order mark); anything else is read as XMI, which says
    what is wrong with what is not XML (X108)."""
    with open(path, "rb") as handle:
        head = handle.read(4096).lstrip(b"\xef\xbb\xbf \t\r\n")
    return _NOTATION_START.match(head) is not None


def _refused(path: str, why: str) -> ModelReading:
    refusal = diagnostic("X109", why, file=path)
    return ModelReading(path, UmlModel(file=path, dialect="unreadable"), None, [refusal])


def _read_stdin(check: bool) -> ModelReading:
    """Standard input, copied to a private temporary file (the reader reads files), then named
    ``<stdin>`` in every diagnostic."""
    stream = sys.stdin.buffer if hasattr(sys.stdin, "buffer") else None
    if stream is None or sys.stdin.isatty():
        why = "standard input is a terminal: pipe a model into it (acordcs-gen validate - < model.xmi)"
        return ModelReading(
            STDIN_NAME,
            UmlModel(file=STDIN_NAME, dialect="unreadable"),
            None,
            [diagnostic("X101", why, file=STDIN_NAME)],
        )
    folder = tempfile.mkdtemp(prefix="acordcs-stdin-")
    try:
        copy = os.path.join(folder, "stdin.xmi")
        with open(copy, "wb") as handle:
            shutil.copyfileobj(stream, handle)
        if _is_text_notation(copy):
            os.replace(copy, copy := os.path.join(folder, "stdin" + NOTATION_SUFFIX))
        reading = read_model(copy, check=check)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    reading.file = reading.uml.file = STDIN_NAME
    for d in reading.diagnostics:
        d.file = STDIN_NAME
    return reading
