"""Protected regions (``acordcs.generator.regions``): the user's lines between ``BEGIN USER key``
and ``END USER key`` survive regeneration; regions whose element left the model go to
``<file>.lost``; a key twice is an error; marker-like text that is not a whole marker line is
text. Then the same through builds of the ``shell`` target's ``bin/env.sh``."""

from __future__ import annotations

import pytest

from acordcs.generator import regions
from tests.support.generator import build, weblab_variant
from tests.support.toolchain import WEBLAB

NEW = (
    "head v2\n# BEGIN USER a\n# END USER a\nmiddle\n# BEGIN USER b\ndefault b\n# END USER b\ntail\n"
)


def test_user_text_is_kept_and_defaults_fill_new_regions() -> None:
    old = "head v1\n# BEGIN USER a\nmine 1\nmine 2\n# END USER a\n"
    merged, lost = regions.merge("hash", NEW, old)
    assert merged == (
        "head v2\n# BEGIN USER a\nmine 1\nmine 2\n# END USER a\nmiddle\n"
        "# BEGIN USER b\ndefault b\n# END USER b\ntail\n"
    )
    assert lost == {}


def test_an_emptied_region_stays_empty() -> None:
    old = "# BEGIN USER b\n# END USER b\n"
    merged, _ = regions.merge("hash", NEW, old)
    assert "# BEGIN USER b\n# END USER b\n" in merged


def test_regions_of_elements_gone_are_returned_as_lost() -> None:
    old = "# BEGIN USER gone\nPORT=1\n# END USER gone\n# BEGIN USER a\nx=1\n# END USER a\n"
    merged, lost = regions.merge("hash", NEW, old)
    assert lost == {"gone": "PORT=1\n"} and "PORT=1" not in merged and "x=1\n" in merged
    text = regions.lost_text("hash", "bin/env.sh", lost)
    assert "# BEGIN USER gone\nPORT=1\n# END USER gone\n" in text
    assert regions.parse("hash", text)[0].key == "gone"


@pytest.mark.parametrize(
    "old, message",
    [
        ("# BEGIN USER a\n# END USER a\n# BEGIN USER a\n# END USER a\n", "appears twice"),
        ("# BEGIN USER a\nx\n", "not closed"),
        ("# END USER a\n", "without its begin"),
        ("# BEGIN USER a\n# BEGIN USER b\n# END USER b\n# END USER a\n", "begins inside"),
    ],
)
def test_malformed_regions_are_errors_with_a_line(old: str, message: str) -> None:
    with pytest.raises(regions.RegionError, match=message):
        regions.merge("hash", NEW, old)


def test_marker_text_inside_a_line_is_not_a_marker() -> None:
    hostile = "x='# END USER a' # BEGIN USER b\n  # END USER a\n#BEGIN USER a\n"
    old = f"# BEGIN USER a\n{hostile}# END USER a\n"
    merged, lost = regions.merge("hash", NEW, old)
    assert hostile in merged and lost == {}
    assert [r.key for r in regions.parse("hash", merged)] == ["a", "b"]


def test_keys_are_ids_or_a_digest_of_ids_that_could_forge_a_marker() -> None:
    assert regions.key("BOUML_0x20502_4") == "BOUML_0x20502_4"
    forged = regions.key("x\n# END USER application")
    assert forged.startswith("id-") and len(forged) == 19
    assert forged == regions.key("x\n# END USER application")


def test_env_file_regions_survive_a_rebuild_and_lost_ones_are_reported(tmp_path) -> None:
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-t", "shell").code == 0
    env = out / "bin" / "env.sh"
    text = env.read_text()
    text = text.replace(
        "# BEGIN USER application\n", "# BEGIN USER application\nACORDCS_PORT_BASE=48000\n"
    ).replace(
        "# BEGIN USER BOUML_0x20502_4\n", "# BEGIN USER BOUML_0x20502_4\nACORDCS_UserSide_HOST=h1\n"
    )
    env.write_text(text)
    assert build(WEBLAB, out, "-t", "shell", "--check").code == 0  # the user's lines: no change
    again = build(WEBLAB, out, "-t", "shell")
    assert again.code == 0 and "nothing changed (12 files up to date)" in again.out
    assert env.read_text() == text
    assert "up to date (shell; model unchanged" in build(WEBLAB, out, "-t", "shell").out
    # The container UserSide gets another id: its old region is lost.
    moved = weblab_variant(tmp_path, ('"BOUML_0x20502_4"', '"BOUML_0x99999_4"', 3))
    result = build(moved, out, "-t", "shell")
    assert result.code == 0, result.err
    assert "ACORDCS_PORT_BASE=48000\n" in env.read_text()
    assert "ACORDCS_UserSide_HOST=h1" not in env.read_text()
    lost = (out / "bin" / "env.sh.lost").read_text()
    assert (
        "# BEGIN USER BOUML_0x20502_4\nACORDCS_UserSide_HOST=h1\n# END USER BOUML_0x20502_4\n"
        in lost
    )
    assert "env.sh.lost" in result.err and "BOUML_0x20502_4" in result.err


def test_a_duplicated_region_stops_the_build_writing_nothing(tmp_path) -> None:
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-t", "shell").code == 0
    env = out / "bin" / "env.sh"
    env.write_text(env.read_text() + "# BEGIN USER application\n# END USER application\n")
    before = env.read_bytes()
    result = build(WEBLAB, out, "-t", "shell", "--force")
    assert result.code == 1 and "appears twice" in result.err and env.read_bytes() == before
