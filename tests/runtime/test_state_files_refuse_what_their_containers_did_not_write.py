"""A persistent component's state file is hostile input: it is taken only when it is strict JSON of
the state file's shape, within its size, for this application and component, every property of
the type the model declares, and signed with the application's token when there is one. Anything
else is refused with a warning naming the file, the component and why; the file is moved aside
(kept, named in the warning), and the component starts from the model's initial values. A property
the model no longer declares is ignored."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

from acordcs.runtime.persistence import FORMAT, SIGNATURE, StateStore, state_file
from tests.support.descriptors import component, prop

TOKEN = "the-application-token"
FAN = component(
    "Fan",
    properties=(prop("speed", 20.0), prop("filterHours", 0), prop("label", ""), prop("on", False)),
    persistent=True,
)
STATE = {
    "properties": {"speed": 55.5, "filterHours": 321, "label": "plant", "on": True},
    "fields": {"history": [1, 2.5, "x"], "notes": {"a": None}},
}


def store(
    run: Path, *, token: str | None = TOKEN, said: list[str] | None = None, **kw
) -> StateStore:
    lines = said if said is not None else []
    return StateStore(run, "Ventilation", FAN, token=token, say=lines.append, **kw)


def written(run: Path, token: str | None = TOKEN) -> dict:
    """The file a container writes for STATE, as JSON."""
    assert store(run, token=token).write(STATE)
    return json.loads(state_file(run, "Fan").read_text())


def refused(run: Path, why: str, *, token: str | None = TOKEN) -> str:
    """Loads the file there: refused, saying ``why`` (a regex); returns the warning. The file is
    moved aside, byte for byte, to the name the warning gives."""
    path = state_file(run, "Fan")
    before = path.read_bytes() if path.is_file() and not path.is_symlink() else None
    said: list[str] = []
    assert store(run, token=token, said=said).load() is None
    (line,) = said
    assert line.startswith(f"warning: Fan: state file {path} refused: "), line
    assert re.search(why, line), line
    assert line.endswith("the component starts from the model's initial values")
    aside = Path(re.search(r"moved aside to (\S+);", line).group(1))
    assert aside.parent == run and aside.name.startswith("Fan.state.json.refused-")
    assert not os.path.lexists(path)
    if before is not None:
        assert aside.read_bytes() == before
    return line


def test_what_a_container_wrote_reads_back_typed_and_signed(tmp_path):
    doc = written(tmp_path)
    assert doc["format"] == FORMAT and doc["component"] == "Fan"
    assert doc["state"] == STATE and len(doc[SIGNATURE]) == 64
    said: list[str] = []
    assert store(tmp_path, said=said).load() == STATE
    assert said == [
        f"Fan: state restored from {state_file(tmp_path, 'Fan')} (4 properties, 2 state fields)"
    ]
    assert oct(state_file(tmp_path, "Fan").stat().st_mode & 0o777) == "0o600"


def test_no_file_is_no_state_and_no_warning(tmp_path):
    said: list[str] = []
    left = tmp_path / ".Fan.state.json.x1y2.tmp"  # what a write killed before its rename left
    left.write_text('{"half": ')
    assert store(tmp_path, said=said).load() is None
    assert said == []
    assert not left.exists()


def edit(run: Path, change) -> None:
    """The written file with ``change(doc)`` applied, rewritten without a new signature."""
    path = state_file(run, "Fan")
    doc = json.loads(path.read_text())
    change(doc)
    path.write_text(json.dumps(doc))


def test_an_edited_value_breaks_the_signature(tmp_path):
    written(tmp_path)
    edit(tmp_path, lambda d: d["state"]["properties"].update(filterHours=0))
    refused(tmp_path, "its signature does not match: it was not written by this application's")


def test_a_file_signed_with_another_token_is_refused(tmp_path):
    written(tmp_path, token="another token")
    refused(tmp_path, "signature does not match")


def test_an_unsigned_file_is_refused_when_there_is_a_token(tmp_path):
    written(tmp_path, token=None)
    refused(tmp_path, "it is not signed, and this application has a token")


def test_without_a_token_an_unsigned_file_is_taken(tmp_path):
    written(tmp_path, token=None)
    assert store(tmp_path, token=None).load() == STATE


@pytest.mark.parametrize(
    ("content", "why"),
    [
        (b"", r"it is not JSON \(Expecting value at line 1, column 1\)"),
        (b'{"format": "acordcs-state/1"', "it is not JSON"),
        (b"\xff\xfe{}", "it is not UTF-8 text"),
        (b"[1, 2]", "it is not a JSON object"),
        (b'{"state": NaN}', "not strict JSON: NaN is no JSON number"),
        (b'{"a": 1, "a": 2}', "not strict JSON: the key 'a' appears twice"),
        (b"[" * 100_000 + b"]" * 100_000, "it nests too deeply"),
        (b'{"format": "acordcs-state/9"}', "its format is 'acordcs-state/9'"),
        (
            b'{"format": "acordcs-state/1", "eval": "__import__(\'os\')"}',
            "keys a state file does not: eval",
        ),
    ],
)
def test_corrupt_files_are_refused_and_kept(tmp_path, content, why):
    state_file(tmp_path, "Fan").write_bytes(content)
    refused(tmp_path, why)


def test_an_oversized_file_is_refused_unread(tmp_path):
    state_file(tmp_path, "Fan").write_bytes(b" " * 2_000_000)
    refused(tmp_path, r"it is larger than")


def test_a_link_or_a_fifo_is_refused_without_following_or_waiting(tmp_path):
    secret = tmp_path / "elsewhere.json"
    secret.write_text("{}")
    state_file(tmp_path, "Fan").symlink_to(secret)
    refused(tmp_path, "it is a symbolic link")
    assert secret.read_text() == "{}"
    os.mkfifo(state_file(tmp_path, "Fan"))
    refused(tmp_path, r"it is a named pipe \(FIFO\)")


def test_the_file_of_another_component_is_refused(tmp_path):
    written(tmp_path)
    other = StateStore(tmp_path, "Ventilation", component("Pump", persistent=True), token=TOKEN)
    os.rename(state_file(tmp_path, "Fan"), state_file(tmp_path, "Pump"))
    said: list[str] = []
    other.say = said.append
    assert other.load() is None
    assert "it is the state of component 'Fan', not 'Pump'" in said[0]


@pytest.mark.parametrize(
    ("name", "value", "why"),
    [
        ("filterHours", "321", r"its property 'filterHours': M::filterHours is an int: not '321'"),
        ("filterHours", 1.5, "is an int: not 1.5"),
        ("filterHours", True, "is an int: not True"),
        ("speed", "fast", "is a double: not 'fast'"),
        ("on", 1, "is a bool: not 1"),
        ("label", 7, "is a string: not 7"),
    ],
)
def test_a_value_of_the_wrong_type_refuses_the_file(tmp_path, name, value, why):
    # signed as the container would: the type is checked even for a file it wrote
    state = {"properties": {**STATE["properties"], name: value}, "fields": {}}
    assert store(tmp_path).write(state)
    refused(tmp_path, why)


def test_a_property_the_model_removed_is_ignored(tmp_path):
    older = StateStore(
        tmp_path,
        "Ventilation",
        component("Fan", properties=(*FAN.properties, prop("retired", 3)), persistent=True),
        token=TOKEN,
    )
    assert older.write({"properties": {**STATE["properties"], "retired": 9}, "fields": {}})
    said: list[str] = []
    state = store(tmp_path, said=said).load()
    assert state == {"properties": STATE["properties"], "fields": {}}
    assert said[0].endswith(
        "(4 properties, 0 state fields; ignored, no longer in the model: retired)"
    )


def test_a_long_string_code_set_reads_back(tmp_path):
    # longer than a string the management interface takes (10,000 characters): code may set it
    assert store(tmp_path).write({"properties": {"label": "x" * 50_000}, "fields": {}})
    assert store(tmp_path).load()["properties"] == {"label": "x" * 50_000}


def test_a_double_written_as_an_integer_is_taken_as_a_double(tmp_path):
    assert store(tmp_path).write({"properties": {"speed": 60}, "fields": {}})
    (value,) = store(tmp_path).load()["properties"].values()
    assert (value, type(value)) == (60.0, float)


def test_a_file_that_cannot_be_moved_aside_is_left_and_never_overwritten(tmp_path, monkeypatch):
    path = state_file(tmp_path, "Fan")
    path.write_bytes(b"garbage")

    def no_rename(src, dst):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(os, "rename", no_rename)  # as a directory another user owns makes it
    said: list[str] = []
    kept = store(tmp_path, said=said)
    assert kept.load() is None
    assert "could not be moved aside (Permission denied), so it is left as it is" in said[0]
    assert kept.write(STATE) is False
    assert path.read_bytes() == b"garbage"


def test_a_value_that_is_not_json_is_left_out_and_said_once(tmp_path):
    said: list[str] = []
    kept = store(tmp_path, said=said)
    state = {"properties": {"speed": float("nan"), "filterHours": 3}, "fields": {"obj": object()}}
    assert kept.write(state) and kept.write(state)
    assert kept.load() == {"properties": {"filterHours": 3}, "fields": {}}
    assert [line.split(":")[1] for line in said[:2]] == [" Fan", " Fan"]
    assert "property 'speed' is not kept" in said[0] and "state field 'obj' is not kept" in said[1]
    assert len(said) == 3  # the two said once, then the restore line


def test_a_state_over_the_limit_is_not_written(tmp_path):
    said: list[str] = []
    kept = store(tmp_path, said=said, limit=1000)
    assert kept.write({"properties": {"label": "x" * 2000}, "fields": {}}) is False
    assert not state_file(tmp_path, "Fan").exists()
    assert "over the 1,000 a state file may hold: not written" in said[0]
