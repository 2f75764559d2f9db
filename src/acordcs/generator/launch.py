"""The ``acordcs-gen`` executable: :func:`acordcs.generator.cli.main`, started and ended for speed.

Three things only a short-lived process can do, which together make ``validate`` on a large
model about a third faster (README, "Benchmarks"):

- the cyclic garbage collector is off: nearly every object the command makes (modules, the model
  view, rule trees) lives until the end, so each collection would scan a growing heap for nothing;
- the model files named on the command line are parsed on a second thread while the interpreter
  imports the rest of the toolchain (libxml2 parses without holding the GIL);
- for ``validate``, the main thread spends the rest of the parse parsing the model's rules from the
  raw bytes into the rule parser's cache (:mod:`acordcs.generator.rule_warmup`);
- the process ends with ``os._exit`` once the output is flushed: tearing down the interpreter would
  free the parsed tree and tens of thousands of model objects one by one, for nothing.

Tests and library users call ``main()``, which does none of them.
"""

from __future__ import annotations

import gc
import os
import sys

TYPE_CHECKING = False  # importing typing costs ~3 ms before the parse thread can start
if TYPE_CHECKING:
    from typing import NoReturn

# Subcommands whose arguments are model files. Arguments that are not files (option values, ...)
# are skipped; a file that is not used costs a wasted parse, never a wrong result.
_READS_MODELS = frozenset(("validate", "inspect"))


def _warm_rules(files: list[str]) -> None:
    """While a model is still being parsed, parse its rules from the raw bytes (rule_warmup.py)."""
    from acordcs.generator.rule_warmup import warm
    from acordcs.generator.xmlsafe import bytes_being_parsed

    for path in files:
        found = bytes_being_parsed(path)
        if found is not None:
            data, parsed = found
            # Until the tree is there: the walk needs it more than the checks need their rules.
            warm(data, stop=parsed.is_set)


def run() -> NoReturn:
    gc.disable()
    # The parse thread needs the GIL between its C calls; a busy main thread would hand it over
    # only every 5 ms.
    sys.setswitchinterval(0.0005)
    args = sys.argv[1:]
    files = [a for a in args[1:] if not a.startswith("-") and os.path.isfile(a)]
    if args and args[0] in _READS_MODELS:
        from acordcs.generator.xmlsafe import prefetch

        prefetch(files)
    from acordcs.generator.cli import main

    if args and args[0] == "validate":
        _warm_rules(files)

    code = main()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing more can be said
            code = code or 1
    os._exit(code)
