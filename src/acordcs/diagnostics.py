"""Diagnostics: one record per finding, with a stable code, severity, message, element and place.

Every code is declared once in :data:`CODES` with its severity and a one-line title; the table of
docs/diagnostics.md and the SARIF rule metadata are both produced from it.

The text form is the one compilers print, ``file:line:col: severity: CODE message``, so that editors'
problem matchers (VS Code's ``$gcc``) make every line clickable.
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass
from enum import IntEnum

_UNPRINTABLE = frozenset(("Cc", "Cf", "Zl", "Zp", "Cs"))


def printable(text: str) -> str:
    """``text`` with control, format (bidi) and line-separator characters escaped as ``\\uXXXX``."""
    if text.isprintable():
        return text
    return "".join(
        f"\\u{ord(ch):04x}" if unicodedata.category(ch) in _UNPRINTABLE else ch for ch in text
    )


# A quoted value longer than this is cut in messages: a tag holding a whole rule list would make one
# line of output thousands of characters long (R205 quotes two of them).
MAX_QUOTED = 80
_LONG = f"{{{MAX_QUOTED + 1},}}"
# A value quoted as repr() quotes it: the opening quote at the start or after a space, bracket or
# '=', the closing one not inside a word ("model's" is no quote), the value on one line. Backslashes
# are not escapes here: messages also quote single characters such as '\'.
_OPEN = r"(?<![^\s(\[{=])"
_QUOTED = re.compile(rf"{_OPEN}'[^'\n]{_LONG}'(?!\w)|{_OPEN}\"[^\"\n]{_LONG}\"(?!\w)")


def shorten(message: str, limit: int = MAX_QUOTED) -> str:
    """``message`` with every quoted value longer than ``limit`` characters cut to its first
    ``limit - 1`` and an ellipsis (``'if a is b then c is d; if …'``)."""
    if len(message) <= limit:
        return message
    return _QUOTED.sub(lambda m: m[0][:limit] + "\u2026" + m[0][0], message)


def suggestion(word: str, names: list[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``names``, or ''."""
    # difflib is quadratic-ish: a bounded candidate list keeps huge hostile models fast
    import difflib  # only when a name is not found

    close = difflib.get_close_matches(word, names[:500], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def article(word: str) -> str:
    """The indefinite article before ``word`` in a message: ``an`` before a vowel sound
    (``an asynchronous port``, ``an Operation``, ``an unset``), else ``a`` (``a UML``, ``a Usage``)."""
    lower = word.lower()
    if lower[:1] == "u":
        return "a" if lower.startswith(("uml", "us", "uni", "uti", "ure")) else "an"
    return "an" if lower[:1] in ("a", "e", "i", "o") else "a"


def within_edits(a: str, b: str, limit: int) -> bool:
    """Whether ``a`` becomes ``b`` in at most ``limit`` single-character insertions, deletions or
    substitutions (Levenshtein distance, case-insensitive), without computing more than needed."""
    a, b = a.casefold(), b.casefold()
    if abs(len(a) - len(b)) > limit:
        return False
    previous = list(range(len(b) + 1))
    for i, x in enumerate(a, start=1):
        current = [i]
        for j, y in enumerate(b, start=1):
            current.append(min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (x != y)))
        if min(current) > limit:
            return False
        previous = current
    return previous[-1] <= limit


class Severity(IntEnum):
    INFO = 0
    WARNING = 1
    ERROR = 2

    def __str__(self) -> str:
        return self.name.lower()


E, W, INFO = Severity.ERROR, Severity.WARNING, Severity.INFO

# code: (severity, title). Codes never change meaning; retired codes are not reused.
CODES: dict[str, tuple[Severity, str]] = {
    # X: reading the file as XML
    "X101": (E, "file cannot be read"),
    "X102": (E, "document type declarations and entities are refused"),
    "X103": (
        E,
        "resource limit exceeded (nesting deeper than 256, text node too large, amplification)",
    ),
    "X104": (E, "file is truncated"),
    "X105": (E, "encoding declaration does not match the bytes"),
    "X106": (E, "namespace prefix used but not declared"),
    "X107": (E, "XML not well-formed; read in recovery mode so that the other checks could run"),
    "X108": (E, "XML not well-formed and not recoverable"),
    "X109": (E, "not an XMI/UML file"),
    "X110": (W, "the file declares a single-byte encoding but its bytes are UTF-8"),
    # M: reading the text notation (docs/notation.md)
    "M101": (E, "the text is not in the notation (syntax error)"),
    "M102": (E, "the text exceeds a safety limit (size, words, nesting)"),
    "M103": (E, "a relation names no element of the text, or several"),
    "M104": (E, "two elements of the text have the same id"),
    # R: reading XMI as UML
    "R201": (
        W,
        "unknown xmi:type or element, skipped (an error when it holds or relates an ACORD-CS element)",
    ),
    "R202": (
        W,
        "reference to an id that is not in the file (an error when an ACORD-CS element makes it)",
    ),
    "R203": (E, "id defined more than once"),
    "R204": (E, "stereotype application whose base element does not exist"),
    "R205": (
        W,
        "a tag is stated twice with different values (BOUML's two places, or two applications)",
    ),
    "R206": (INFO, "free stereotype read as the ACORDCS stereotype of the same name"),
    "R207": (W, "element without an id"),
    "R208": (E, "the file holds class-like elements but the reader found no classifier"),
    "R209": (INFO, "exporter not among the known tools; the file read cleanly"),
    "R210": (W, "exporter not among the known tools, and reading it found problems"),
    "R211": (INFO, "elements of a UML metaclass the reader does not read (skipped)"),
    # T: stereotypes and tagged values
    "T301": (E, "ACORDCS stereotype applied to the wrong metaclass"),
    "T302": (E, "unknown ACORDCS stereotype"),
    "T303": (W, "unknown tag"),
    "T304": (E, "tag value of the wrong type"),
    "T305": (E, "tag value not among the permitted values"),
    "T306": (E, "frequency must be positive"),
    "T307": (E, "linguistic terms missing or not parseable"),
    "T308": (E, "linguistic term outside the variable's range"),
    "T309": (W, "linguistic terms leave part of the range uncovered"),
    "T310": (E, "variable range missing or empty (min must be below max)"),
    "T311": (E, "linguistic term shape invalid (points out of order, non-positive width)"),
    "T312": (E, "two terms of a variable share a name"),
    "T313": (W, "the model applies no ACORDCS stereotype (nothing to check)"),
    "T314": (E, "container port outside 1-65535"),
    "T315": (
        E,
        "linguistic variable beyond the fuzzy engine's limits (1,000 terms, 500 points per term)",
    ),
    "T320": (E, "misspelt tag: within two edits of a tag of the stereotype"),
    "T321": (W, "a profile the model applies by reference is not found"),
    # L: rules
    "L401": (E, "rule syntax error"),
    "L402": (E, "rule variable is not an attribute in the policy set's scope"),
    "L403": (E, "ambiguous unqualified rule variable"),
    "L404": (E, "term not defined for the variable"),
    "L405": (E, "fuzzy output is also an input of the same policy set"),
    "L406": (E, "operation not found on the element"),
    "L407": (E, "operation called with the wrong number of arguments"),
    "L408": (E, "fuzzy rule uses an attribute that is not a linguistic variable"),
    "L409": (W, "policy has no rules"),
    "L410": (E, "duplicate rule label in a policy set"),
    # A: architecture
    "A501": (E, "port connection does not join a provided and a required port"),
    "A502": (E, "port connection joins ports of different kinds"),
    "A503": (E, "port connection does not join exactly two ports"),
    "A504": (E, "policy set adapts an element of a kind it cannot adapt"),
    "A505": (E, "monitor feeds no policy set"),
    "A506": (E, "element not deployed in any container"),
    "A507": (E, "element deployed in more than one container"),
    "A508": (E, "policy belongs to no policy set, or to several"),
    "A509": (W, "policy set has no policies"),
    "A510": (E, "periodic policy set without a frequency"),
    "A511": (W, "port owned by no component"),
    "A512": (E, "port owned by more than one component"),
    "A513": (W, "policy set adapts nothing and no monitor feeds it"),
    "A514": (E, "monitor lacks what its acquisition needs (source, xpath, operation, frequency)"),
    "A515": (W, "monitor tag that its acquisition does not read"),
    "A516": (E, "connector the deployment cannot honour (in-process between two containers)"),
    "A517": (E, "port connection joins a port that belongs to no component"),
    "A518": (
        W,
        "persistent component declares no property (only its class's state fields are kept)",
    ),
    # N: names that become identifiers
    "N601": (E, "name is not a valid identifier"),
    "N602": (E, "name is a reserved word in Python or Java"),
    "N603": (E, "name used twice where generated code needs it unique"),
    "N604": (E, "operation named like a member of the runtime's component API"),
    "N605": (W, "operation named on_<port>: it becomes that port's notification handler"),
    "N606": (E, "names that differ only in letter case"),
    # G: generating files from the model (acordcs-gen build)
    "G701": (E, "a model name cannot become part of a generated file's path"),
    "G702": (
        E,
        "two generated files would be one file (same path, or paths differing only in case)",
    ),
    "G703": (
        E,
        "a model name cannot be written into a generated file (not an identifier, or a name the generated code already has)",
    ),
    "G704": (W, "your code implements an operation or port the model renamed or removed"),
    "G705": (W, "your class does not compile: the container hosting it refuses to start"),
    # S: scenario files and their runs (acordcs-gen test)
    "S801": (E, "scenario file cannot be read (missing, not UTF-8, or larger than 1 MiB)"),
    "S802": (E, "scenario file is not YAML this reader takes (syntax, anchors, aliases, tags)"),
    "S803": (E, "scenario file does not follow the format (unknown key, wrong shape, missing key)"),
    "S804": (E, "scenario names something the model does not have"),
    "S805": (E, "scenario value of the wrong type, not finite, or outside its variable's range"),
    "S806": (E, "scenario file exceeds a limit (scenarios, steps, expectations, nesting, values)"),
    "S810": (E, "a scenario's expectation did not hold"),
    "S811": (E, "a scenario's run recorded a fault (an action, operation or engine raised)"),
    "S812": (W, "a rule no scenario fired, or a term no input reached (rule coverage)"),
    # Z: the toolchain itself
    "Z901": (E, "internal error in a check (a bug in acordcs: please report it)"),
    "Z902": (W, "a check another package declares could not be loaded"),
}


UNREADABLE_TEXT = frozenset(("M101", "M102"))
"""The codes of a text in the notation that could not be read at all (exit code 2), as X codes are."""


def documentation_url() -> str | None:
    """The project's documentation, as pyproject.toml declares it (``[project.urls]
    Documentation``, read from the installed package's metadata), or None."""
    from importlib import metadata  # only SARIF needs it: validate's start-up does not pay

    try:
        urls = metadata.metadata("acordcs").get_all("Project-URL") or []
    except metadata.PackageNotFoundError:
        return None
    for entry in urls:
        label, _, url = entry.partition(",")
        if label.strip().lower() == "documentation" and url.strip():
            return url.strip().rstrip("/")
    return None


def help_uri(code: str) -> str | None:
    """Where ``code`` is explained, with an example and the fix (SARIF ``helpUri``): its section
    of ``diagnostics.md`` (one anchor per code, ``#l402``) under the declared documentation URL;
    None when none is declared (SARIF wants an absolute URI or none)."""
    base = documentation_url()
    return f"{base}/diagnostics.md#{code.lower()}" if base else None


@dataclass(slots=True)
class Diagnostic:
    code: str
    severity: Severity
    message: str
    file: str
    line: int = 0  # 0: unknown (the finding is about the whole file)
    column: int = 0  # 0: unknown; shown as 1, the start of the line
    element: str | None = None  # qualified name
    xmi_id: str | None = None
    unreadable: bool = False  # the input could not be read at all: exit code 2
    # What within the element the finding is about (a tag name, a rule's label or "Rule#2"): with
    # the code and the element's id, the finding's identity across runs (SARIF fingerprints).
    subject: str | None = None
    # Causes and consequences (:mod:`acordcs.model.causes`): the keys of what would explain this
    # finding (a stereotype not read, a relation lost), and the keys this finding explains. A
    # finding another reported one explains is not printed; the cause counts it.
    because: tuple[str, ...] = ()
    explains: tuple[str, ...] = ()

    def location(self) -> str:
        """``file:line:col`` (column 1 when unknown), or ``file`` when the line is unknown."""
        return f"{self.file}:{self.line}:{self.column or 1}" if self.line else self.file

    def format_text(self, severity: str | None = None) -> str:
        """One line, ``file:line:col: severity: CODE message [element (id)]`` (``severity``: the
        word said instead of the severity's own, as gcc's ``note`` for info); names from the model
        cannot break it (newlines, bidi controls are escaped)."""
        text = f"{self.location()}: {severity or self.severity}: {self.code} {self.message}"
        if self.element or self.xmi_id:
            where = " ".join(
                p for p in (self.element, f"({self.xmi_id})" if self.xmi_id else None) if p
            )
            text += f" [{where}]"
        return printable(text)

    def fingerprint(self) -> str:
        """What stays the same while the finding does: code, element and subject, not the wording."""
        return f"{self.code}:{self.xmi_id or self.element or ''}:{self.subject or ''}"

    def to_dict(self) -> dict:
        """Line and column from 1, or None when the finding is about the whole file."""
        return {
            "code": self.code,
            "severity": str(self.severity),
            "message": self.message,
            "file": self.file,
            "line": self.line or None,
            "column": (self.column or 1) if self.line else None,
            "element": self.element,
            "xmi_id": self.xmi_id,
        }


def diagnostic(
    code: str,
    message: str,
    *,
    file: str,
    line: int | None = 0,
    column: int | None = 0,
    element: str | None = None,
    xmi_id: str | None = None,
    subject: str | None = None,
    severity: Severity | None = None,
    because: tuple[str, ...] = (),
    explains: tuple[str, ...] = (),
) -> Diagnostic:
    """A diagnostic with the severity its code declares (or ``severity``, for the codes whose
    severity depends on what the finding touches: R201, R202); long quoted values in ``message``
    cut. ``because`` and ``explains``: see :class:`Diagnostic`."""
    severity = CODES[code][0] if severity is None else severity
    return Diagnostic(
        code,
        severity,
        shorten(message),
        file,
        line or 0,
        column or 0,
        element,
        xmi_id,
        unreadable=code in UNREADABLE_TEXT
        or (code.startswith("X") and code != "X107" and severity is Severity.ERROR),
        subject=subject,
        because=because,
        explains=explains,
    )
