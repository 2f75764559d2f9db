"""Benchmark: ``acordcs-gen validate`` on a synthetic 2,000-class BOUML export, against lxml.

Prints, measured in one run on the same file:
- B: the time lxml takes to parse and re-serialize the file, and the whole-process time of
  ``acordcs-gen validate`` on it, interpreter start included, as a multiple of B (target: at most
  3 B), with the executable's one speed device on and off (:func:`acordcs.cli.run`'s exit without
  the interpreter's teardown), and with the cyclic garbage collector off, a device measured and not
  kept (it saved about 8%, under the 10% a device must save). The variants are alternated, 15 runs
  each, and their medians compared: the host's speed drifts between minutes;
- the same for a model with no classes (start-up alone), to show where the time goes;
- in-process read + check time of an ISO-8859-1 BOUML export with over 1,000 stereotype
  applications (target: well under a second);
- reading (``read_uml``, in-process) a 3.5 MB Umbrello export and a 2 MB MagicDraw export, tiled
  from the real ones in ``../shared/reference/xmi-other-tools`` (see ``tiled_exports.py``), beside the
  BOUML reader on a synthetic BOUML export of the same size (target: no slower; alternated, 15 runs);
- the same model converted to the text notation (``acordcs-gen convert``): ``acordcs-gen validate``
  on the text against on its XMI, whole process (target: no slower; alternated, 15 runs), and the
  text read into its outline by the fast reader and by lark's parser of ``acord.lark`` (medians of 7);
- the model's 1,200 rules parsed by our parser (its fast reader, lark's LALR parser for what it
  declines) and by lark's own parser on the same grammar with the same builders (each a median of
  7 in a fresh interpreter; medians of 5 such runs, alternated), and what a fresh interpreter takes
  to parse its first rule (imports included);
- with ``--before SRC`` (the ``src`` directory of another checkout, e.g. ``git worktree add
  /tmp/before <commit>``; may be given more than once), the same figures for that checkout's code
  in the same run, on the same interpreter and packages, its sources byte-compiled as ours are:
  its ``validate`` alternated with B and ours, its parse of the same rules.

Run: ``.venv/bin/python benchmarks/bench_validate.py [--before SRC]...``
"""

from __future__ import annotations

import argparse
import compileall
import gc
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from lxml import etree

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/, tests/ of the repository
from tools.bouml_writer.synthetic import generate

ROUNDS = 7
PAIRS = 15
CLI = [str(Path(sys.executable).with_name("acordcs-gen")), "validate"]
# The executable with its device (os._exit) off: `main()` instead of `run()`, ending with the
# interpreter's teardown; and with a device that was measured and not kept: the collector off.
_RUN = "import sys; from acordcs.cli import {entry}; sys.exit({entry}())"
VARIANTS = {
    "as installed (acordcs-gen)": CLI,
    "without os._exit": [sys.executable, "-c", _RUN.format(entry="main"), "validate"],
    "not kept: garbage collector off": [
        sys.executable,
        "-c",
        "import gc; gc.disable(); " + _RUN.format(entry="run"),
        "validate",
    ],
}


def median_seconds(fn, rounds: int = ROUNDS) -> float:
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def alternated(*fns, rounds: int = PAIRS, before=None) -> list[float]:
    """Medians of ``fns`` run one after the other ``rounds`` times: the host's speed drifts (a
    noisy neighbour, frequency changes), and a ratio of two medians taken minutes apart measures
    the drift as much as the code. Each round runs them in another order (shuffled, the same
    sequence every run): in a fixed order, a variant always run right after another (after B's
    parse, or after a process that filled the page cache) is measured in that one's wake.
    ``before`` runs, untimed, before each call."""
    import random

    order = random.Random(20261126)
    times: list[list[float]] = [[] for _ in fns]
    for _ in range(rounds):
        turn = list(range(len(fns)))
        order.shuffle(turn)
        for n in turn:
            if before is not None:
                before()
            start = time.perf_counter()
            fns[n]()
            times[n].append(time.perf_counter() - start)
    return [statistics.median(runs) for runs in times]


def lxml_round_trip(path: Path) -> None:
    etree.tostring(etree.parse(str(path)))


def run_cli(path: Path, command: list[str] = CLI, env: dict[str, str] | None = None) -> None:
    done = subprocess.run([*command, str(path)], capture_output=True, text=True, env=env)
    if done.returncode != 0:
        raise SystemExit(f"validate failed on {path}:\n{done.stdout}{done.stderr}")


def with_source(src: Path) -> dict[str, str]:
    """The environment that runs ``src``'s acordcs instead of the installed one."""
    return {**os.environ, "PYTHONPATH": str(src)}


def main() -> int:
    from acordcs.model.reading import read_model

    options = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    options.add_argument(
        "--before", type=Path, action="append", default=[], help="src directory to compare with"
    )
    befores = options.parse_args().before
    variants = {name: (command, None) for name, command in VARIANTS.items()}
    for before in befores:
        if not (before / "acordcs" / "__init__.py").is_file():
            raise SystemExit(f"--before {before}: not a src directory holding the acordcs package")
        # As make installs ours: with PYTHONDONTWRITEBYTECODE set, it would compile every run.
        compileall.compile_dir(str(before), quiet=1)
        # the executable's own code path (run()), with that checkout's package
        command = [sys.executable, "-c", _RUN.format(entry="run"), "validate"]
        variants[f"before ({before})"] = (command, with_source(before))

    with tempfile.TemporaryDirectory() as tmp:
        big = Path(tmp, "synthetic-2000.xmi")
        big.write_text(generate(classes=2000, seed=1), encoding="utf-8")
        empty = Path(tmp, "empty.xmi")
        empty.write_text(_empty_model(), encoding="utf-8")
        latin = Path(tmp, "synthetic-latin1.xmi")
        text = generate(classes=2000, seed=2).replace(
            'encoding="UTF-8"', 'encoding="ISO-8859-1"', 1
        )
        latin.write_bytes(
            text.replace('name="Plain', 'name="Configuração', 200).encode("iso-8859-1")
        )

        for command, env in variants.values():  # warm: byte-compiled, any cache filled
            run_cli(big, command, env)
        b, *timed = alternated(
            lambda: lxml_round_trip(big),
            *(lambda c=command, e=env: run_cli(big, c, e) for command, env in variants.values()),
        )
        whole = timed[0]
        notation = _text_notation(big)
        startup = median_seconds(lambda: run_cli(empty))
        reading = read_model(str(latin))
        read_latin = median_seconds(lambda: read_model(str(latin)))
        big_mb, latin_mb = big.stat().st_size / 1e6, latin.stat().st_size / 1e6

    print(
        f"synthetic model: 2,000 classes, {big_mb:.1f} MB; figures are medians of {ROUNDS} runs "
        f"(B and validate: {PAIRS} runs each, alternated)"
    )
    print(f"B  lxml parse + serialize            {b * 1e3:8.1f} ms")
    print(
        f"   acordcs-gen validate, whole process {whole * 1e3:8.1f} ms = {whole / b:5.2f} B (target <= 3 B)"
    )
    by_name = dict(zip(variants, timed, strict=True))
    for name, seconds in by_name.items():
        print(f"     {name:38s} {seconds * 1e3:8.1f} ms = {seconds / b:5.2f} B")
    without = by_name["without os._exit"]
    print(f"     os._exit saves {(without - whole) / without:6.1%} of the time without it")
    gc_off = by_name["not kept: garbage collector off"]
    print(
        f"     the collector off would save {(whole - gc_off) / whole:6.1%} (kept only at >= 10%)"
    )
    print(f"   acordcs-gen start-up, empty model   {startup * 1e3:8.1f} ms = {startup / b:4.1f} B")
    print(
        f"   ISO-8859-1 export, {latin_mb:.1f} MB, {len(reading.uml.applications)} stereotype "
        f"applications, {len(reading.diagnostics)} diagnostics: read + check {read_latin * 1e3:.1f} ms"
    )
    print(notation)
    _rule_parsers(reading, befores)
    _other_tools()
    return 0


def _text_notation(big: Path) -> str:
    """The synthetic model as text: validate on it against validate on its XMI, and its reading
    by the fast reader against lark's parser (what the fast reader declines, lark reads)."""
    from acordcs.notation.fast_text import read_outline
    from acordcs.notation.syntax import MAX_DEPTH, lark_outline

    text = big.with_suffix(".acord")
    done = subprocess.run(
        [str(Path(sys.executable).with_name("acordcs-gen")), "convert", str(big), "-o", str(text)],
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        raise SystemExit(f"convert failed on {big}:\n{done.stdout}{done.stderr}")
    run_cli(text)  # warm: lark's analysed grammar cached
    on_text, on_xmi = alternated(lambda: run_cli(text), lambda: run_cli(big))
    source = text.read_text(encoding="utf-8")
    fast = median_seconds(lambda: read_outline(source, MAX_DEPTH))
    slow = median_seconds(lambda: lark_outline(source))
    return (
        f"   the same model as text, {text.stat().st_size / 1e6:.2f} MB (convert's output: the "
        f"ACORD-CS part): validate {on_text * 1e3:.1f} ms, on its XMI {on_xmi * 1e3:.1f} ms: "
        f"{on_text / on_xmi:.2f}x (target <= 1)\n"
        f"     read into its outline: fast reader {fast * 1e3:.1f} ms, lark's parser "
        f"{slow * 1e3:.1f} ms: {slow / fast:.1f}x faster"
    )


OTHER_TOOLS = {  # the real export tiled, the size to tile it to
    "Umbrello 1.6 (XMI 1.2)": ("umbrello__class_all-elements.xmi", 3_500_000),
    "MagicDraw 18.5 (XMI 2.5)": ("marklogic-uml2es__DHFEmployeeSample_md18.5.xml", 2_000_000),
}
BYTES_PER_CLASS = 2_276  # of the synthetic BOUML export (4.55 MB for 2,000 classes)


def _other_tools() -> None:
    """Reading other tools' exports against the BOUML reader on a BOUML export of the same size."""
    from tiled_exports import tiled

    from acordcs.xmi.readers import read_uml
    from tests.support.toolchain import XMI_OTHER_TOOLS as shared  # ../shared, as the tests find it

    if not shared.is_dir():
        print(f"   other tools' exports: {shared} not found, not measured")
        return
    with tempfile.TemporaryDirectory() as tmp:
        for title, (name, size) in OTHER_TOOLS.items():
            theirs = Path(tmp, name)
            theirs.write_bytes(tiled(shared / name, size))
            ours = Path(tmp, f"bouml-{name}.xmi")
            classes = round(theirs.stat().st_size / BYTES_PER_CLASS)
            ours.write_text(generate(classes=classes, seed=3), encoding="utf-8")
            read = read_uml(str(theirs))
            # Each read from a clean heap: a model is a graph of cycles (owners and members) that
            # the cyclic collector frees during whatever runs next; alternated without this, each
            # reader would pay for collecting the other's model.
            t_theirs, t_ours = alternated(
                lambda p=theirs: read_uml(str(p)),
                lambda p=ours: read_uml(str(p)),
                before=gc.collect,
            )
            print(
                f"   {title}, {theirs.stat().st_size / 1e6:.2f} MB ({len(read.classifiers):,} "
                f"classifiers, {len(read.diagnostics)} diagnostics): read {t_theirs * 1e3:.1f} ms; "
                f"BOUML reader on a {ours.stat().st_size / 1e6:.2f} MB BOUML export "
                f"{t_ours * 1e3:.1f} ms: {t_theirs / t_ours:.2f}x (target <= 1)"
            )


# Parses every rule given (a JSON list of [text, kind]) 8 times, the memo of parsed texts cleared
# each time, and prints the median of the last 7, then what its first rule took in this fresh
# interpreter (imports included). With "lark": lark's own parser on the same grammar, with the
# same builders, instead of parse_rule.
_PARSE_ALL = """
import json, statistics, sys, time
first = time.perf_counter()
from acordcs.rules import parse_rule
from acordcs.rules import parser as rules
parse_rule("if a is b then c is d")
first = time.perf_counter() - first
texts = json.load(open(sys.argv[1], encoding="utf-8"))
parse = parse_rule
if sys.argv[2:] == ["lark"]:
    import lark
    from acordcs.rules import lark_parser
    own = lark.Lark(lark_parser.grammar(), start=list(lark_parser.STARTS), parser="lalr",
                    maybe_placeholders=True, transformer=lark_parser.RuleTreeBuilder())
    parse = lambda text, kind: own.parse(text, start="start_" + kind)
times = []
for _ in range(8):
    rules.forget_parsed_rules()
    start = time.perf_counter()
    for text, kind in texts:
        parse(text, kind)
    times.append(time.perf_counter() - start)
print(statistics.median(times[1:]), first)
"""


def _rule_parsers(reading, befores: list[Path]) -> None:
    """Every rule of the model parsed by our parser, by lark's own on the same grammar and
    builders, and by each of ``befores``: each in a fresh interpreter, alternated 5 times."""
    from acordcs.model.architecture import POLICY_SET
    from acordcs.model.queries import policy_rules, rule_kind

    arch = reading.architecture
    texts = []
    for policy_set in arch.of_kind(POLICY_SET):
        kind = rule_kind(policy_set)
        for policy in arch.policies(policy_set):
            texts += [(prule.text, kind) for prule in policy_rules(policy)]
    runs: dict[str, list[tuple[float, float]]] = {"ours": [], "lark's own parser": []}
    sources = {f"before ({before})": before for before in befores}
    runs.update({name: [] for name in sources})
    with tempfile.TemporaryDirectory() as tmp:
        listed = Path(tmp, "rules.json")
        listed.write_text(json.dumps(texts), encoding="utf-8")
        for _ in range(5):
            for name in runs:
                env = with_source(sources[name]) if name in sources else None
                mode = ["lark"] if name == "lark's own parser" else []
                done = subprocess.run(
                    [sys.executable, "-c", _PARSE_ALL, str(listed), *mode],
                    capture_output=True,
                    text=True,
                    env=env,
                    check=True,
                )
                all_rules, first = map(float, done.stdout.split())
                runs[name].append((all_rules, first))
    ours = statistics.median(r[0] for r in runs["ours"])
    print(
        f"   {len(texts):,} rules parsed (fresh interpreters, alternated): ours {ours * 1e3:.1f} ms"
    )
    for name, measured in runs.items():
        if name != "ours":
            theirs = statistics.median(r[0] for r in measured)
            print(f"     {name}: {theirs * 1e3:.1f} ms; ours / it = {ours / theirs:.2f}")
    for name, measured in runs.items():
        if name != "lark's own parser":
            first = statistics.median(r[1] for r in measured)
            print(
                f"   the first rule in a fresh interpreter, imports included, {name}: {first * 1e3:.1f} ms"
            )


def _empty_model() -> str:
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" '
        'xmlns:xmi="http://schema.omg.org/spec/XMI/2.1">\n'
        '<uml:Model xmi:type="uml:Model" xmi:id="themodel" name="empty"/>\n</xmi:XMI>\n'
    )


if __name__ == "__main__":
    sys.exit(main())
