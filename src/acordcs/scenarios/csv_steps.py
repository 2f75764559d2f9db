"""A scenario's steps from a CSV file (key ``csv``), each cell with its file:line:col.

The file is named relative to the scenario file and must be inside its directory (a scenario
file from elsewhere cannot make the command quote another file's lines); at most
:data:`~acordcs.scenarios.yaml_reading.MAX_BYTES`, UTF-8. Its first line is the header: ``time``
(seconds), then ``Element.attribute`` names; every other line a step: plain comma-separated
values (numbers, ``true``/``false``, unquoted text; an empty cell gives no value), ``#`` starting
a comment line.
"""

from __future__ import annotations

from pathlib import Path

from acordcs.scenarios.yaml_reading import MAX_BYTES, Located

Cells = list[tuple[Located, list[tuple[Located, Located]]]]


def read_csv_cells(node: Located, name: str) -> Cells:
    """Each row's time cell and (header, cell) pairs. Raises ScenarioFileError."""
    base = Path(node.file).resolve().parent
    path = (base / name).resolve()
    if not path.is_relative_to(base):
        raise node.fail(
            "S801", f"the CSV file {name!r} is not in the scenario file's directory; move it there"
        )
    shown = str(Path(node.file).parent / name)
    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_BYTES + 1)
    except OSError as exc:
        raise node.fail(
            "S801", f"cannot read the CSV file {name!r}: {exc.strerror or exc}"
        ) from None
    if len(data) > MAX_BYTES:
        raise node.fail("S801", f"the CSV file {name!r} is more than {MAX_BYTES} bytes")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise node.fail("S801", f"the CSV file {name!r} is not UTF-8 (byte {exc.start})") from None
    rows = [
        (number, line)
        for number, line in enumerate(text.splitlines(), 1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not rows:
        raise node.fail("S803", f"the CSV file {name!r} is empty; its first line names the columns")
    header_line, header_text = rows[0]
    header = _cells(shown, header_line, header_text)
    if not header or header[0].value != "time":
        first = header[0] if header else Located("", shown, header_line, 1)
        raise first.fail("S803", "the CSV file's first column is 'time' (seconds)")
    out: Cells = []
    for number, line in rows[1:]:
        cells = _cells(shown, number, line)
        if len(cells) != len(header):
            raise Located(line, shown, number, 1).fail(
                "S803", f"{len(cells)} cells where the header names {len(header)} columns"
            )
        time = Located(_scalar(cells[0].value), shown, number, cells[0].column)
        given = [
            (h, Located(_scalar(c.value), shown, number, c.column))
            for h, c in zip(header[1:], cells[1:], strict=True)
            if c.value != ""
        ]
        out.append((time, given))
    return out


def _cells(file: str, line: int, text: str) -> list[Located]:
    cells, column = [], 1
    for raw in text.split(","):
        stripped = raw.strip()
        cells.append(Located(stripped, file, line, column + len(raw) - len(raw.lstrip())))
        column += len(raw) + 1
    return cells


def _scalar(text: str) -> object:
    """A cell's value: an int, a float (finite or not: the caller refuses NaN), a bool, or text."""
    if text in ("true", "false"):
        return text == "true"
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            continue
    return text
