"""Running an XSLT 3.0 target with Saxon (saxonche) over the descriptor XML.

The stylesheet gets the descriptor document as its source and four parameters (all strings):
``source-file`` (the model file's name, for headers), ``generator`` (``acordcs-gen 0.1.0``),
``target`` (its own name) and ``descriptor-schema`` (the URI of the shipped
``acordcs-descriptor.xsd``). Each ``xsl:result-document`` is a file, its ``href`` relative to the
output directory; the principal result lists the files::

    <files xmlns="http://acordcs.org/codegen/1.0">
      <file path="WebLab.descriptor.xml" element="WebLab" ids="id1 id2"/>
    </files>

``path`` is the file's path as a relative '/'-separated path (the href, before URI encoding),
``element`` the model element it comes from (for messages), ``ids`` the model element ids it holds,
``once="yes"`` a file written only when absent, the user's from then on, ``regions="hash"`` a file
with protected regions in that syntax, ``executable="yes"`` a file written executable (as
``TargetContext.emit``'s arguments of the same names).
A file written but not listed, listed but not written, or outside the output directory fails the
target.

Saxon writes nothing: the stylesheet runs inside XPath's ``fn:transform`` with the delivery format
``serialized``, called by a small driver stylesheet (``transform-target.xsl``), so that every result document
comes back as the string Saxon's serializer made of it, with the serialization parameters of its
``xsl:result-document`` (``method``, ``indent``, ``encoding``: a character the encoding cannot hold
fails the target, as it would on disk). The build encodes each string in the encoding its XML
declaration names, else UTF-8, and writes it only if it differs from the file on disk: a file is
written once, into place, and an unchanged one not at all. (saxonche's own capture of result
documents, ``set_capture_result_documents``, hands back unserialized trees: the serialization
parameters are lost.)

Saxon prints its errors on the process's standard error itself; they are caught there (the
descriptor of file 2 is redirected while Saxon runs) and become part of the :class:`BuildError`.
``xsl:message`` output is collected by the driver, not printed: the build reports it.
"""

from __future__ import annotations

import codecs
import contextlib
import os
import re
import sys
import tempfile
from collections.abc import Iterator, Mapping
from functools import cache
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Protocol
from urllib.parse import unquote, urlsplit

from acordcs.generator.errors import BuildError
from acordcs.generator.paths import path_problem
from acordcs.generator.regions import PREFIXES

if TYPE_CHECKING:
    from acordcs.generator.target_context import TargetContext


class Target(Protocol):
    """What running a stylesheet needs of a target (:class:`acordcs.generator.target.Target` is
    one; named by its fields, so that this module does not import the one that imports it)."""

    @property
    def name(self) -> str: ...
    @property
    def stylesheet(self) -> Path | None: ...
    @property
    def origin(self) -> str: ...


LISTING_NAMESPACE = "http://acordcs.org/codegen/1.0"
_YES = ("yes", "true", "1")

BASE_OUTPUT = "file:///acordcs-output/"
"""The base output URI the stylesheets run with: the output directory as they see it. A fixed URI
(nothing is written there), so that a stylesheet's output does not depend on where it is built."""

DRIVER = "transform-target.xsl"
"""The stylesheet (beside this module) that runs a target's stylesheet with ``fn:transform`` and
returns its outputs' URIs and serializations (:func:`_outputs` reads them)."""

# Static errors: the stylesheet did not compile (the others happen while it runs).
_STATIC = re.compile(r"\b(?:XTSE|XPST|XQST)\d{4}\b")
_XML_DECLARATION = re.compile(r"<\?xml[^>]*?\sencoding\s*=\s*[\"']([A-Za-z0-9._-]+)[\"']")


@cache
def _saxon():
    """The Saxon processor and the compiled driver (both made once per process)."""
    from saxonche import PySaxonProcessor

    processor = PySaxonProcessor(license=False)
    path = str(resources.files("acordcs.transforms") / DRIVER)
    driver = processor.new_xslt30_processor().compile_stylesheet(stylesheet_file=path)
    driver.set_result_as_raw_value(True)  # the map itself, not a serialization of it
    driver.set_save_xsl_message(True)
    return processor, driver


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


def _saxon_said(caught: list[str]) -> str:
    """What Saxon printed, by error (a line starting a block, indented lines after it), without the
    errors it reports again at the driver's call of ``fn:transform`` and without repeats."""
    blocks: list[list[str]] = []
    for line in "\n".join(caught).splitlines():
        if line[:1].isspace() and blocks:
            blocks[-1].append(line)
        elif line.strip():
            blocks.append([line])
    kept: list[str] = []
    for block in blocks:
        text = "\n".join(block)
        if DRIVER not in text and text not in kept:
            kept.append(text)
    return "\n".join(kept)


def _fail(target: Target, err: Exception, caught: list[str]) -> BuildError:
    said = str(err).strip() or type(err).__name__
    extra = _saxon_said(caught)
    if extra.strip() == said:
        extra = ""
    what = "compiling the stylesheet" if _STATIC.search("\n".join(caught)) else "the transformation"
    message = f"target {target.name}: {what} failed: {said}"
    if extra:
        message += f"\nSaxon said:\n{extra}"
    return BuildError(
        message,
        file=str(target.stylesheet),
        hint="nothing was written; this is a fault of the stylesheet (or of the descriptor it "
        "reads): fix it, or build the other targets with --target",
    )


def run_stylesheet(
    target: Target, context: TargetContext, parameters: Mapping[str, str] | None = None
) -> None:
    """Run ``target``'s stylesheet over the descriptor and emit its result documents into
    ``context``, as listed by its principal result. ``parameters``: string parameters besides
    the four every stylesheet gets, from a Python target that runs a stylesheet (what is decided
    once in Python is not written again in XSLT)."""
    from saxonche import PySaxonApiError

    from acordcs.generator.headers import clean

    path = target.stylesheet
    assert path is not None
    if not path.is_file():
        raise BuildError(
            f"target {target.name}: stylesheet {path} cannot be read",
            hint=f"reinstall the package that provides target {target.name} ({target.origin}), "
            "or give the path of an XSLT 3.0 file",
        )
    processor, driver = _saxon()
    values = {
        "source-file": clean(context.source_name),
        "generator": context.generator,
        "target": target.name,
        "descriptor-schema": _schema_uri(),
        **(parameters or {}),
    }
    driver.clear_parameters()
    driver.clear_xsl_messages()
    driver.set_parameter("stylesheet", processor.make_string_value(path.resolve().as_uri()))
    driver.set_parameter("base", processor.make_string_value(BASE_OUTPUT))
    driver.set_parameter(
        "parameters",
        processor.make_map2({k: processor.make_string_value(v) for k, v in values.items()}),
    )
    with _stderr_captured() as caught:
        try:
            document = _parsed(processor, context.descriptor_xml)
            result = driver.transform_to_value(xdm_node=document)
            serialized = _outputs(result.head.string_value if result.size else "")
        except PySaxonApiError as err:
            failure: Exception | None = err
        else:
            failure = None
    messages = _messages(driver)
    if failure is not None:
        caught = [*caught, *(f"xsl:message: {m}" for m in messages)]
        raise _fail(target, failure, caught)
    context.messages.extend(messages)
    listing = serialized.pop(BASE_OUTPUT, None)
    if listing is None:
        listing = serialized.pop("output", "")
    _collect(target, context, listing, _documents(target, serialized))


def _outputs(framed: str) -> dict[str, str]:
    """The driver's result read: URI -> text, from ``<length>:<uri><length>:<text>`` pairs (lengths
    in characters)."""
    out: dict[str, str] = {}
    at, pieces = 0, []
    while at < len(framed):
        colon = framed.index(":", at)
        length = int(framed[at:colon])
        pieces.append(framed[colon + 1 : colon + 1 + length])
        at = colon + 1 + length
        if len(pieces) == 2:
            out[pieces[0]] = pieces[1]
            pieces = []
    return out


_LAST: list = []  # [(descriptor bytes, its parsed document)]: the last descriptor parsed


def _parsed(processor, data: bytes):
    """``data`` (a descriptor document) parsed by Saxon, once for all the stylesheets of a build
    (they get the same bytes object)."""
    if _LAST and _LAST[0][0] is data:
        return _LAST[0][1]
    document = processor.parse_xml(xml_text=data.decode("utf-8"))
    _LAST[:] = [(data, document)]
    return document


def _messages(driver) -> list[str]:
    try:
        found = driver.get_xsl_messages()
    except Exception:  # saxonche gives nothing when no message was sent
        return []
    if found is None:
        return []
    out = []
    for n in range(found.size):
        item = found.item_at(n)
        out.append(str(getattr(item, "string_value", item)).strip())
    return out


def _documents(target: Target, serialized: dict[str, str]) -> dict[str, bytes]:
    """The result documents by path relative to the output directory, encoded."""
    base = urlsplit(BASE_OUTPUT).path
    out: dict[str, bytes] = {}
    for uri, text in serialized.items():
        parts = urlsplit(uri)
        where = unquote(parts.path)
        if parts.scheme != "file" or parts.netloc or not where.startswith(base):
            shown = where[len(base) - 1 :] if where.startswith(base[:-1]) else uri
            raise BuildError(
                f"target {target.name}: the stylesheet wrote a result document outside the output "
                f"directory ({shown!r})",
                file=str(target.stylesheet),
                hint="give xsl:result-document a relative href, inside the output directory",
            )
        out[where[len(base) :]] = _encode(target, where[len(base) :], text)
    return out


def _encode(target: Target, path: str, text: str) -> bytes:
    """``text`` in the encoding its XML declaration names, else UTF-8."""
    declared = _XML_DECLARATION.match(text)
    encoding = declared.group(1) if declared else "utf-8"
    try:
        return text.encode(codecs.lookup(encoding).name if declared else "utf-8")
    except (LookupError, UnicodeEncodeError) as err:
        raise BuildError(
            f"target {target.name}: result document {path!r} cannot be written in encoding "
            f"{encoding!r}: {err}",
            file=str(target.stylesheet),
            hint="use UTF-8 (encoding='UTF-8' on xsl:result-document)",
        ) from None


def _collect(
    target: Target, context: TargetContext, listing: str, documents: dict[str, bytes]
) -> None:
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
        data = documents.get(path)
        if data is None or path in listed:
            raise BuildError(
                f"target {target.name}: the stylesheet lists {path!r} "
                + ("twice" if path in listed else "but did not write it"),
                file=str(target.stylesheet),
                hint="list exactly the xsl:result-document hrefs it writes, each once",
            )
        listed.add(path)
        regions = entry.get("regions", "")
        if regions and regions not in PREFIXES:
            raise BuildError(
                f"target {target.name}: listed file {path!r} has regions={regions!r}, not a "
                "syntax of protected regions",
                file=str(target.stylesheet),
                hint=f"regions is one of {', '.join(map(repr, PREFIXES))}, or absent",
            )
        context.emit(
            path,
            data,
            element=entry.get("element", ""),
            ids=tuple((entry.get("ids") or "").split()),
            once=entry.get("once", "") in _YES,
            regions=regions,
            executable=entry.get("executable", "") in _YES,
        )
    unlisted = sorted(set(documents) - listed)
    if unlisted:
        raise BuildError(
            f"target {target.name}: the stylesheet wrote {', '.join(map(repr, unlisted))} "
            "without listing it",
            file=str(target.stylesheet),
            hint="list every xsl:result-document in the principal result",
        )
