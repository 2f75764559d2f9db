"""``make demo`` tells the truth: the README's transcript is what the demo's commands print (but
for the progress bar and the wall-clock figures), the experiment's claims hold, it writes the report
files, and report.html shows the claims, the tables, the tuning table and every plot in a real
browser; any subset of the experiment is reported, and a run that hits the time cap fails it."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

from weblab_experiment import tuning
from weblab_experiment.__main__ import SEEDS
from weblab_experiment.grid import CONDITIONS, SWEEP, fixed_name
from weblab_experiment.summary import METRICS
from weblab_sim.experiment import UNLIMITED

from tests.support.browser import headless_chromium
from tests.support.toolchain import ROOT, run_main

from .conftest import SAMPLE_DIR

README = (ROOT / "README.md").read_text(encoding="utf-8")
WHOLE = (SAMPLE_DIR / "README.md").read_text(encoding="utf-8")  # the whole transcript
TIMING = re.compile(r"simulated s in [\d.]+ wall s|^WebLab runs: |^report: ")
CLAIMS = 14  # the claims shown for the default path
NOT_CLAIMED = 1  # of which made on other paths only (summary.SCOPES)
OBSERVED = 2  # and said as seen or not on these runs, never claimed
ELIDED = re.compile(r"^\[\.\.\. .* \.\.\.\]$")


def demo_block(text: str = README) -> list[str]:
    return text.split("$ make demo\n", 1)[1].split("```", 1)[0].splitlines()


def experiment_lines(block: list[str]) -> list[str]:
    """The transcript's lines after the experiment's command, timings left out."""
    shown = block[block.index(next(ln for ln in block if ln.startswith("cd "))) + 1 :]
    return [ln for ln in shown if not TIMING.search(ln)]


def test_the_readme_shows_the_commands_make_demo_runs():
    recipe = (ROOT / "Makefile").read_text(encoding="utf-8").split("\ndemo:", 1)[1]
    commands = [ln.strip() for ln in recipe.split("\n\n", 1)[0].splitlines()[1:]]
    shown = [ln for ln in demo_block() if ln.startswith((".venv/bin/", "cd "))]
    assert shown == [c.replace("$(BIN)", ".venv/bin") for c in commands]


def test_the_readme_transcript_of_validate_and_build_is_real(tmp_path, monkeypatch):
    block = demo_block()
    monkeypatch.chdir(ROOT)
    validated = run_main(["validate", "samples/weblab/weblab.xmi"])
    assert validated.out.splitlines() == [block[1]]
    # the build as on a fresh clone: only the WebLab's committed code in the output directory
    tracked = subprocess.run(
        ["git", "ls-files", "samples/weblab/app"], cwd=ROOT, capture_output=True, text=True
    ).stdout.split()
    assert tracked, "the WebLab's user classes are committed"
    for rel in [*tracked, "samples/weblab/weblab.xmi"]:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / rel, tmp_path / rel)
    monkeypatch.chdir(tmp_path)
    built = run_main(["build", "-q", "samples/weblab/weblab.xmi", "-o", "samples/weblab/app"])
    assert built.code == 0, built.both
    assert built.out.splitlines() == [block[3]]


def test_the_readme_transcript_of_the_experiment_is_real(demo):
    lines, _ = demo
    printed = [ln for ln in lines if not TIMING.search(ln)]
    assert experiment_lines(demo_block(WHOLE)) == printed
    assert demo_block(WHOLE)[:5] == demo_block()[:5]  # one run: the same commands and build
    # The README's excerpt: the same lines in the same order, "[... ...]" standing for some left out.
    at = 0
    for line in experiment_lines(demo_block()):
        if ELIDED.match(line):
            continue
        assert line in printed[at:], f"not in the output (or out of order): {line!r}"
        at = printed.index(line, at) + 1
    assert any(ELIDED.match(ln) for ln in demo_block()), "the README says where lines were left out"


def test_the_claims_hold_and_the_data_files_say_so(demo):
    _, out = demo
    data = json.loads((out / "results.json").read_text(encoding="utf-8"))
    made = [c for c in data["claims"] if c["claimed"]]
    assert made and all(c["holds"] for c in made), data["claims"]
    assert data["unfinished_runs"] == []
    assert data["meta"]["conditions"] == [
        *CONDITIONS,
        *(fixed_name(v) for v in SWEEP),
        *(fixed_name(v, UNLIMITED) for v in SWEEP),
    ]
    adaptive = data["results"]["default"]["adaptive"]
    assert set(adaptive) == {"residential", "campus", "LAN"}
    for metric in ("cycles_per_s", "speed_mm_s", "time_s", "recoveries", "fps"):
        assert set(adaptive["LAN"][metric]) == {"mean", "sd", "n"}
        assert adaptive["LAN"][metric]["n"] == SEEDS
    rows = (out / "results.csv").read_text(encoding="utf-8").splitlines()
    assert rows[0] == "path,condition,profile,metric,mean,sd,n"
    assert len(rows) == 1 + len(data["meta"]["conditions"]) * 3 * len(METRICS)


def test_the_report_shows_claims_tables_tuning_and_plots_in_a_browser(demo):
    _, out = demo
    with headless_chromium(1200, 900) as browser:
        browser.get((out / "report.html").as_uri())
        claims = browser.find_elements("css selector", "#claims-default li")
        assert len(claims) == CLAIMS
        verdicts = [c.text.split(":", 1)[0] for c in claims]
        assert verdicts.count("holds") == CLAIMS - NOT_CLAIMED - OBSERVED, verdicts
        assert "does not hold" not in verdicts
        assert sum(v.endswith("shown on these runs") for v in verdicts) == OBSERVED
        assert len(browser.find_elements("css selector", "#table1-default tbody tr")) == 6
        assert len(browser.find_elements("css selector", "#conditions-default tbody tr")) == 48
        for family in ("fixed", "no_speed_policy"):  # each family's six fixed speeds
            assert (
                len(browser.find_elements("css selector", f"#sweep-{family}-default tbody tr")) == 6
            )
        shown = [
            [td.text for td in tr.find_elements("css selector", "td")]
            for tr in browser.find_elements("css selector", "#tuning-table tbody tr")
        ]
        assert shown == [[r.parameter, r.value, r.basis, r.why] for r in tuning.rows()]
        images = browser.find_elements("css selector", "img")
        assert len(images) == 5
        for image in images:  # each plot loaded and drawn, not a broken image
            assert browser.execute_script("return arguments[0].naturalWidth", image) > 400
            for link in image.find_elements("xpath", "../figcaption/a"):
                assert Path(link.get_attribute("href").removeprefix("file://")).stat().st_size
        text = browser.find_element("tag name", "body").text
        assert not re.search(r"± 0(\.0+)?(?![\d.])", text), "an SD of 0 is shown"
        assert "UndefinedError" not in text
        browser.save_screenshot(str(out / "report-screenshot.png"))
    assert (out / "report-screenshot.png").stat().st_size > 10_000


def experiment(tmp_path: Path, *args: str) -> tuple[subprocess.CompletedProcess, Path]:
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, "-m", "weblab_experiment", "--no-progress", "--out", str(out), *args],
        cwd=SAMPLE_DIR,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert "Traceback" not in done.stderr, done.stderr
    return done, out


def test_any_subset_of_conditions_and_profiles_from_any_first_seed_is_reported(
    tmp_path, weblab_app
):
    done, out = experiment(
        tmp_path, "--seeds", "1", "--first-seed", "3", "--profiles", "LAN",
        "--conditions", "fixed_50", "--jobs", "1",
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert "1 runs (1 conditions x 1 profiles x 1 path x 1 seeds, 3 to 3)" in done.stdout
    data = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert data["meta"]["first_seed"] == 3 and list(data["results"]["default"]) == ["fixed_50"]
    with headless_chromium(1000, 800) as browser:
        browser.get((out / "report.html").as_uri())
        assert browser.find_elements("css selector", "#conditions-default tbody tr")
        assert not browser.find_elements("css selector", "#table1-default")  # no adaptive runs


def test_a_run_that_hits_the_time_cap_is_a_failure_listed_counted_and_exit_1(tmp_path, weblab_app):
    done, out = experiment(
        tmp_path, "--seeds", "1", "--profiles", "LAN", "--conditions", "adaptive",
        "--time-cap", "5", "--jobs", "1",
    )  # fmt: skip
    assert done.returncode == 1, done.stdout + done.stderr
    assert (
        "DOES NOT HOLD: default: every run of every condition finishes within the 5 s cap "
        "(0 of 1 runs finished; 1 hit the cap, 0 failed: adaptive LAN seed 0)"
    ) in done.stdout
    assert "DID NOT FINISH: path default, adaptive, LAN, seed 0: hit the 5 s cap" in done.stdout
    data = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert [(r["condition"], r["seed"]) for r in data["unfinished_runs"]] == [("adaptive", 0)]
    with headless_chromium(1000, 800) as browser:
        browser.get((out / "report.html").as_uri())
        listed = browser.find_elements("css selector", "#unfinished-runs li")
        assert [li.text.split(":")[0] for li in listed] == ["path default, adaptive, LAN, seed 0"]


def test_a_demo_without_the_built_application_says_how_to_build_it(tmp_path):
    # run() finds no generated package where the demo builds it: exit 2 and the command to run
    sample = tmp_path / "weblab"
    shutil.copytree(SAMPLE_DIR / "weblab_sim", sample / "weblab_sim")
    shutil.copytree(SAMPLE_DIR / "weblab_experiment", sample / "weblab_experiment")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "weblab_experiment",
            "--seeds",
            "1",
            "--profiles",
            "LAN",
            "--conditions",
            "adaptive",
            "--no-progress",
            "--out",
            str(tmp_path / "out"),
            "--jobs",
            "1",
        ],
        cwd=sample,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert "Traceback" not in done.stderr
    assert "acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app" in (
        done.stdout + done.stderr
    )


def test_bad_arguments_are_refused_with_the_choices():
    done = subprocess.run(
        [sys.executable, "-m", "weblab_experiment", "--profiles", "moon"],
        cwd=SAMPLE_DIR,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2
    assert "unknown profile moon; the profiles are residential, campus, LAN" in done.stderr
