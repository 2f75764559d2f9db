"""How long a hostile subscription delays another publisher's delivery (issue 22, item 1).
Standalone: ``.venv/bin/python benchmarks/bench_context_hostile.py [--baseline SRC] [--seconds S]``.

An attacker subscribes an XPath for every publisher and publishes a 960 KB flat document (9,000
elements of 100 characters: within the document limits) again and again; a legitimate publisher
publishes a small alarm every 20 ms, which a subscription of its own selects. The figure is the
alarm's delay, from ``publish`` to its callback (p50, p99, max). The attacker's expressions:

- ``//*[string-length(..) = 1]``, the issue's: the cost check now refuses it to an untrusted
  subscriber; run in a provider with ``Limits(trusted_subscribers=True)``, which admits it as the
  earlier check did;
- the costliest kind the check admits to an untrusted subscriber on this document,
  ``//*[contains(., 'xxxb')]``.

``--baseline SRC`` also runs the issue's expression for an untrusted subscriber with the ``acordcs``
package found in ``SRC`` (the ``src`` directory of another checkout, e.g. the version before this
change, whose check admitted it), in a child process, in the same run: the before/after pair.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import threading
import time

HOSTILE = "//*[string-length(..) = 1]"
ADMITTED = "//*[contains(., 'xxxb')]"
ALARM = "/robot/alarm[. > 3]"
DOCUMENT = "<r>" + ("<e>" + "x" * 100 + "</e>") * 9000 + "</r>"


def scenario(expression: str, trusted: bool, seconds: float) -> dict[str, object]:
    """Run the attacker and the legitimate publisher for ``seconds``; the alarm delays in ms."""
    import acordcs
    from acordcs.runtime.context import ContextProvider, Limits, SubscriptionError

    assert os.path.dirname(os.path.dirname(acordcs.__file__)) == os.path.abspath(
        os.environ.get("PYTHONPATH", os.path.dirname(os.path.dirname(acordcs.__file__)))
    ), f"acordcs imported from {acordcs.__file__}, not from PYTHONPATH"

    delays: list[float] = []
    sent: dict[int, float] = {}
    attacks = [0]
    with ContextProvider(Limits(trusted_subscribers=trusted)) as provider:
        try:
            provider.subscribe(lambda note: None, expression)
        except SubscriptionError as err:
            return {"refused": str(err).split(": too costly")[0]}

        def alarm(note) -> None:
            delays.append((time.perf_counter() - sent[note.seq]) * 1e3)

        provider.subscribe(alarm, ALARM, "robot")
        stop = threading.Event()

        def attack() -> None:
            while not stop.is_set():
                provider.publish("attacker", DOCUMENT)
                attacks[0] += 1

        attacker = threading.Thread(target=attack, daemon=True)
        attacker.start()
        time.sleep(0.2)  # the attacker's first evaluation is under way
        end = time.perf_counter() + seconds
        seq = 0
        while time.perf_counter() < end:
            seq += 1
            sent[seq] = time.perf_counter()
            provider.publish("robot", f"<robot><alarm>{seq % 5 + 4}</alarm></robot>")
            time.sleep(0.02)
        deadline = time.perf_counter() + 30
        while len(delays) < seq and time.perf_counter() < deadline:
            time.sleep(0.01)  # the last alarms may still wait behind the attacker
        stop.set()
        attacker.join(60)
    ordered = sorted(delays)
    return {
        "alarms": seq,
        "delivered": len(delays),
        "attacker documents": attacks[0],
        "p50": ordered[len(ordered) // 2] if ordered else None,
        "p99": ordered[int(len(ordered) * 0.99)] if ordered else None,
        "max": ordered[-1] if ordered else None,
    }


def show(label: str, result: dict[str, object]) -> None:
    if "refused" in result:
        print(f"{label}: refused at subscribe: {result['refused']}")
        return
    figures = ", ".join(
        f"{k} {v:.1f} ms" for k, v in result.items() if k in ("p50", "p99", "max") and v is not None
    )
    print(
        f"{label}: {result['delivered']}/{result['alarms']} alarms delivered, "
        f"attacker published {result['attacker documents']} documents; delay {figures}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", metavar="SRC", help="src directory of the version to compare")
    parser.add_argument("--seconds", type=float, default=8.0, help="legitimate publishing time")
    parser.add_argument("--child", nargs=3, metavar=("EXPRESSION", "TRUSTED", "SECONDS"))
    args = parser.parse_args()
    if args.child:
        expression, trusted, seconds = args.child
        print(json.dumps(scenario(expression, trusted == "1", float(seconds))))
        return
    print(f"cores: {os.cpu_count()}, load average at start: {os.getloadavg()[0]:.2f}")
    print(f"attacker's document: {len(DOCUMENT):,} bytes; alarm subscription {ALARM}")
    if args.baseline:
        child = subprocess.run(
            [sys.executable, __file__, "--child", HOSTILE, "0", str(args.seconds)],
            env={**os.environ, "PYTHONPATH": os.path.abspath(args.baseline)},
            capture_output=True,
            text=True,
            timeout=600,
            check=True,
        )
        before = json.loads(child.stdout.splitlines()[-1])
        show(f"before ({args.baseline}), untrusted, {HOSTILE}", before)
    show(f"untrusted, {HOSTILE}", scenario(HOSTILE, False, args.seconds))
    show(f"trusted (admitted), {HOSTILE}", scenario(HOSTILE, True, args.seconds))
    show(f"untrusted, {ADMITTED}", scenario(ADMITTED, False, args.seconds))
    print(f"load average at end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
