"""A container in its own OS process, served over Pyro5, for the remote-connector tests.

Usage: ``python rt_helpers_remote.py PORT`` prints ``READY <uri>`` once it serves, then runs until
killed (or its stdin closes, so it never outlives the test that started it).
"""

from __future__ import annotations

import os
import sys
import time
from typing import Any, ClassVar

from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.container import Container
from acordcs.runtime.ports import async_port, sync_port


class Robot(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 0.0}
    ports = (sync_port("control"), async_port("events"))

    def __init__(self) -> None:
        self.got: list[Any] = []

    def move(self, speed: float) -> float:
        self.set("speed", speed)
        return speed

    def slow(self, seconds: float) -> str:
        time.sleep(seconds)
        return "done"

    def pid(self) -> int:
        return os.getpid()

    def frame(self, header: bytes) -> bytes:
        """Bytes in, bytes out (a camera frame): fails unless the argument arrived as bytes."""
        if not isinstance(header, bytes):
            raise TypeError(f"header arrived as {type(header).__name__}")
        return header + bytes(range(256))

    def crash(self) -> None:
        raise ValueError("robot refuses")

    def on_events(self, message: Any) -> None:
        self.got.append(message)

    def received(self) -> list[Any]:
        return list(self.got)


def main() -> None:
    port = int(sys.argv[1])
    container = Container("remote")
    container.install_factory(ComponentFactory("Robot", Robot))
    container.create("Robot", "robot")
    server = ContainerServer(container, host="127.0.0.1", port=port)
    print("READY", server.uri, flush=True)
    # Serve until the parent closes our stdin (or kills us): never outlive the test.
    sys.stdin.read()
    server.close()
    container.close()


if __name__ == "__main__":
    main()
