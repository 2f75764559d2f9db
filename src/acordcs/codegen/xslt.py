"""Running an XSLT 3.0 target with Saxon (saxonche) over the descriptor XML.

The stylesheet gets the descriptor document as its source and four parameters (all strings):
``source-file`` (the model file's name, for headers), ``generator`` (``acordcs-gen 0.1.0``),
``target`` (its own name) and ``descriptor-schema`` (the URI of the shipped
``acordcs-descriptor.xsd``). Saxon writes each ``xsl:result-document`` itself, relative hrefs
resolved against the target's temporary directory; the principal result lists what was written::

    <files xmlns="http://acordcs.org/codegen/1.0">
      <file path="WebLab.descriptor.xml" element="WebLab" ids="id1 id2"/>
    </files>

``path`` is the file's path as a relative '/'-separated path (the href, before URI encoding),
``element`` the model element it comes from (for messages), ``ids`` the model element ids it holds,
``once="yes"`` a file written only when absent, the user's from then on (``TargetContext.emit``).
A file written but not listed, or listed but not written, fails the target.

Saxon prints its errors on the process's standard error itself; they are caught there (the
descriptor of file 2 is redirected while Saxon runs) and become part of the :class:`BuildError`.
``xsl:message`` output is collected, not printed: the build reports it.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator, Mapping
from functools import cache
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from acordcs.codegen.errors import BuildError
from acordcs.codegen.paths import path_problem

if TYPE_CHECKING:
    from acordcs.codegen.context import TargetContext
    from acordcs.codegen.registry import Target

LISTING_NAMESPACE = "http://acordcs.org/codegen/1.0"


@cache
def _saxon():
    from saxonche import PySaxonProcessor

    processor = PySaxonProcessor(license=False)
    return processor, processor.new_xslt30_processor()


def _schema_uri() -> str:
    return Path(str(resources.files("acordcs.descriptor") / "acordcs-descriptor.xsd")).as_uri()


@contextlib.contextmanager
def _stderr_captured() -> Iterator[list[str]]:
    """File descriptor 2 redirected to a temporary file while the block runs; what was written
    there is appended to the yielded list when the block ends (normally or not)."""
    caught: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError, AttributeError):  # no real fd 2: nothing to redirect
        yield caught
        return
    with tempfile.TemporaryFile() as sink:
        os.dup2(sink.fileno(), 2)
        try:
            yield caught
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)
            text = sink.read().decode("utf-8", "replace").strip()
            if text:
                caught.append(text)


def _fail(target: Target, what: str, err: Exception, caught: list[str]) -> BuildError:
    said = str(err).strip() or type(err).__name__
    extra = "\n".join(t for t in caught if t and said not in t)
    message = f"target {target.name}: {what} failed: {said}"
    if extra:
        message += f"\nSaxon said:\n{extra}"
    return BuildError(
        message,
        file=str(target.stylesheet),
        hint="nothing was written; this is a fault of the stylesheet (or of the descriptor it "
        "reads): fix it, or build the other targets with --target",
    )


_COMPILED: dict[tuple[Path, int, int], object] = {}


def _compile(target: Target):
    path = target.stylesheet
    assert path is not None
    try:
        info = path.stat()
    except OSError:
        raise BuildError(
            f"target {target.name}: stylesheet {path} cannot be read",
            hint=f"reinstall the package that provides target {target.name} ({target.origin})",
        ) from None
    key = (path, info.st_mtime_ns, info.st_size)  # an edited stylesheet is compiled again
    executable = _COMPILED.get(key)
    if executable is None:
        from saxonche import PySaxonApiError

        _, xslt = _saxon()
        with _stderr_captured() as caught:
            try:
                executable = xslt.compile_stylesheet(stylesheet_file=str(path))
            except PySaxonApiError as err:
                failure = err
            else:
                failure = None
        if failure is not None:
            raise _fail(target, "compiling the stylesheet", failure, caught)
        _COMPILED[key] = executable
    return executable


def run_stylesheet(
    target: Target, context: TargetContext, parameters: Mapping[str, str] | None = None
) -> None:
    """Run ``target``'s stylesheet over the descriptor: its result documents are written into
    ``context.workdir`` by Saxon, then emitted into ``context`` as listed by its principal result.
    ``parameters``: string parameters besides the four every stylesheet gets, from a Python target
    that runs a stylesheet (what is decided once in Python is not written again in XSLT)."""
    from saxonche import PySaxonApiError

    from acordcs.codegen.headers import clean

    processor, _ = _saxon()
    executable = _compile(target)
    executable.clear_parameters()
    executable.set_base_output_uri(context.workdir.as_uri() + "/")
    executable.set_save_xsl_message(True)
    executable.clear_xsl_messages()
    for name, value in (
        ("source-file", clean(context.source_name)),
        ("generator", context.generator),
        ("target", target.name),
        ("descriptor-schema", _schema_uri()),
        *(parameters or {}).items(),
    ):
        executable.set_parameter(name, processor.make_string_value(value))
    with _stderr_captured() as caught:
        try:
            document = processor.parse_xml(xml_text=context.descriptor_xml.decode("utf-8"))
            listing = executable.transform_to_string(xdm_node=document)
        except PySaxonApiError as err:
            failure: Exception | None = err
        else:
            failure = None
    messages = _messages(executable)
    if failure is not None:
        caught = [*caught, *(f"xsl:message: {m}" for m in messages)]
        raise _fail(target, "the transformation", failure, caught)
    for text in messages:
        context.messages.append(text)
    _collect(target, context, listing or "")


def _messages(executable) -> list[str]:
    try:
        found = executable.get_xsl_messages()
    except Exception:  # saxonche gives nothing when no message was sent
        return []
    if found is None:
        return []
    out = []
    for n in range(found.size):
        item = found.item_at(n)
        out.append(str(getattr(item, "string_value", item)).strip())
    return out


def _collect(target: Target, context: TargetContext, listing: str) -> None:
    from acordcs import safexml

    try:
        root = safexml.parse(listing.encode("utf-8"))
    except Exception as err:
        raise BuildError(
            f"target {target.name}: the stylesheet's principal result is not a file listing: {err}",
            file=str(target.stylesheet),
            hint=f'its main output must be <files xmlns="{LISTING_NAMESPACE}"> with one <file '
            'path="..."/> per result document',
        ) from None
    root_tag = "nothing" if root is None else root.tag
    tag = f"{{{LISTING_NAMESPACE}}}"
    if root is None or root_tag != tag + "files":
        raise BuildError(
            f"target {target.name}: the stylesheet's principal result is <{root_tag}>, "
            "not a file listing",
            file=str(target.stylesheet),
            hint=f'its main output must be <files xmlns="{LISTING_NAMESPACE}">',
        )
    listed: set[str] = set()
    for entry in root.iter(tag + "file"):
        path = entry.get("path", "")
        problem = path_problem(path)
        if problem:
            raise BuildError(
                f"target {target.name}: listed file {path!r} cannot be generated: {problem}",
                file=str(target.stylesheet),
                hint="a generated path is relative, inside the output directory",
            )
        file = context.workdir / path
        try:
            data = file.read_bytes()
        except OSError:
            raise BuildError(
                f"target {target.name}: the stylesheet lists {path!r} but did not write it",
                file=str(target.stylesheet),
                hint="list exactly the xsl:result-document hrefs it writes",
            ) from None
        listed.add(path)
        ids = tuple((entry.get("ids") or "").split())
        once = entry.get("once", "") in ("yes", "true", "1")
        context.emit(path, data, element=entry.get("element", ""), ids=ids, once=once)
    written = {
        p.relative_to(context.workdir).as_posix()
        for p in context.workdir.rglob("*")
        if p.is_file() or p.is_symlink()
    }
    unlisted = sorted(written - listed)
    if unlisted:
        raise BuildError(
            f"target {target.name}: the stylesheet wrote {', '.join(map(repr, unlisted))} "
            "without listing it",
            file=str(target.stylesheet),
            hint="list every xsl:result-document in the principal result",
        )
