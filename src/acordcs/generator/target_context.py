"""What a target is given, and what it gives back.

Every target, a Python function or an XSLT stylesheet, is run with one argument: a
:class:`TargetContext` holding the application descriptor (as data and as XML), the model file's
name, and :meth:`TargetContext.emit` to produce a file. Nothing a target emits reaches the output
directory until every target of the build has succeeded (see :mod:`acordcs.generator.pipeline`).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from acordcs.diagnostics import Diagnostic, diagnostic
from acordcs.generator.headers import GENERATOR, header

if TYPE_CHECKING:
    from acordcs.descriptor import Application


@dataclass(frozen=True, slots=True)
class GeneratedFile:
    """One generated file: its path (relative, '/'-separated), its bytes, the target that made it,
    the model element it was generated from (``element``: a qualified name, for messages) and the
    ids of the model elements it holds (``ids``: the manifest's traceability). ``once``: a file
    written only when absent, then the user's (generation gap: the class a user implements):
    never overwritten, never deleted (see :mod:`acordcs.generator.writer`). ``regions``: the
    syntax of the file's protected regions (``"hash"``), whose text the user's copy keeps when
    the file is regenerated (:mod:`acordcs.generator.regions`); empty: none. ``executable``: written
    with the execute permissions (``0o777`` less the umask; others ``0o666`` less it)."""

    path: str
    data: bytes
    target: str
    element: str = ""
    ids: tuple[str, ...] = ()
    once: bool = False
    regions: str = ""
    executable: bool = False


@dataclass
class TargetContext:
    """What one target gets. ``source`` is the model file as given on the command line,
    ``source_name`` its base name (what headers name: the same bytes wherever the build runs from);
    ``messages`` are notes for the user (a stylesheet's ``xsl:message`` output), printed by the
    build. A target writes nothing itself: what it emits stays in memory until the build writes
    it. ``workdir``: a directory a caller may give a Python target for the files of a tool it
    runs (the build gives none: such a target makes its own with :mod:`tempfile`)."""

    target: str
    application: Application
    descriptor_xml: bytes
    source: str
    workdir: Path | None = None
    generator: str = GENERATOR
    files: list[GeneratedFile] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    locate: Callable[[str], int] | None = None

    @property
    def source_name(self) -> str:
        return os.path.basename(self.source) or self.source

    def emit(
        self,
        path: str,
        content: str | bytes,
        *,
        element: str = "",
        ids: tuple[str, ...] = (),
        once: bool = False,
        regions: str = "",
        executable: bool = False,
    ) -> None:
        """Produce ``path`` (relative to the output directory, '/'-separated) with ``content``
        (text is written as UTF-8 with '\\n' line ends); ``element`` names the model element it
        comes from, ``ids`` the ids of the elements it holds. With ``once``, the file is written
        only if absent and belongs to the user from then on: never overwritten nor deleted; when
        its element leaves the model, builds report it as orphaned. With ``regions`` (a syntax of
        :data:`acordcs.generator.regions.PREFIXES`, e.g. ``"hash"``), the text between the file's
        ``BEGIN USER key``/``END USER key`` marker lines is the user's: a build keeps it. With
        ``executable``, the file is written executable (a script)."""
        data = content.encode("utf-8") if isinstance(content, str) else bytes(content)
        self.files.append(
            GeneratedFile(path, data, self.target, element, tuple(ids), once, regions, executable)
        )

    def header(self, syntax: str, what: str, note: str = "") -> str:
        """The header comment a file of this target starts with (see :mod:`.headers`): ``what``
        names the model element, e.g. ``policy set 'SpeedLimiting' (WebLab::...::SpeedLimiting)``."""
        return header(syntax, self.target, what, self.source_name, note)

    def problem(
        self, code: str, message: str, *, element: str | None = None, element_id: str | None = None
    ) -> Diagnostic:
        """A diagnostic about the model (a G7xx code) at the model element ``element_id``."""
        line = self.locate(element_id) if self.locate and element_id else 0
        return diagnostic(
            code, message, file=self.source, line=line, element=element, xmi_id=element_id
        )
