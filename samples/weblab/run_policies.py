"""Run the WebLab model's policies: the model file is read, checked, described and run in virtual time.

The speed-limiting (fuzzy) and recovering (CLIPS) policy sets come from ``weblab.xmi`` alone; this
script supplies only what a model cannot: the Recovery component's operations, and the control
monitor's readings (the values the locomotion interceptor would extract from the user's control
actions). Usage: ``python samples/weblab/run_policies.py [path/to/weblab.xmi]``.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import ClassVar

from acordcs.descriptor import describe
from acordcs.model.reading import read_model
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.ports import PortSpec

# The paper's Table 1: access network -> control cycles per second and mean speed (mm/s).
TABLE_1 = (("residential", 0.90, 69), ("campus", 1.46, 127), ("LAN", 1.72, 143))


class Recovery(CtxComponent):
    """Moves the robot back and turns it to look for the stripe (here: says so)."""

    properties: ClassVar[dict[str, object]] = {"retries": 0, "recoveries": 0}
    ports = (PortSpec("RecoveryLocomotionPort", "synchronous", "required"),)

    def recover(self) -> None:
        print("    Recovery.recover(): back up, turn, cap the speed, wait")

    def askUser(self) -> None:  # the model's operation name
        print("    Recovery.askUser(): three recoveries failed, the user is asked to help")


def main(argv: list[str]) -> int:
    path = argv[1] if len(argv) > 1 else str(Path(__file__).with_name("weblab.xmi"))
    reading = read_model(path)
    errors = [d for d in reading.diagnostics if d.severity >= 2]
    if reading.architecture is None or errors:
        for d in reading.diagnostics:
            print(d.format_text(), file=sys.stderr)
        return 1
    control: list[Monitor] = []

    def make_control(name: str, **kw) -> Monitor:
        control.append(Monitor(name, **kw))
        return control[-1]

    run = assemble(
        describe(reading.architecture),
        clock=VirtualClock(seed=1),
        factories={"Recovery": Recovery},
        monitors={"Control": make_control},
    )
    with run:
        weblab = run.container("WebLabSide")
        monitor = control[0]
        print(f"{path}: containers {', '.join(run.containers)}; policy sets of WebLabSide:")
        for name in ("SpeedLimiting", "Recovering", "BandwidthLimiting"):
            ps = weblab.policy_set(name)
            print(f"  {name}: {ps.engine_kind} engine, {ps.trigger} trigger")
        print(
            "SpeedLimiting on a straight stretch (angle 5 degrees), per access network of Table 1:"
        )
        for network, rate, paper in TABLE_1:
            monitor.update(cycleRate=rate, angle=5.0, speed=100.0)
            speed = weblab.get_property("Locomotion", "maxSpeed")
            print(
                f"  {network:11s} {rate:.2f} cycles/s -> maxSpeed {speed:6.1f} mm/s (paper: {paper})"
            )
        print("SpeedLimiting at 1.46 cycles/s as the turn gets sharper:")
        for angle in (5.0, 20.0, 45.0, 80.0):
            monitor.update(cycleRate=1.46, angle=angle, speed=100.0)
            print(
                f"  angle {angle:4.0f} -> maxSpeed {weblab.get_property('Locomotion', 'maxSpeed'):6.1f} mm/s"
            )
        print("Recovering: the control sets speed 0 four times, then moves again:")
        for speed in (0.0, 0.0, 0.0, 0.0, 60.0):
            print(f"  control sets speed {speed:g}")
            monitor.update(speed=speed)
        print(
            f"  recovery episodes counted: {weblab.get_property('Recovery', 'recoveries')} "
            f"(a stop and its retries count once, when the robot moves again); "
            f"faults: {weblab.faults.counts['total']}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
