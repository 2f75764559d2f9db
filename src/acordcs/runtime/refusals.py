"""Refusals of an endpoint, counted, and logged without letting a refused peer grow the log.

An endpoint that refuses strangers (a wrong token in the Pyro5 handshake, a console request from a
foreign site) must neither stay silent about it nor log every refusal: a local process without
the token refused 3,000 times in 2 s grew a container's log by 333 KB (issue 36). As the context
provider does for the notifications it drops, :class:`Refusals` counts each kind of refusal and
logs the 1st, 2nd, 4th, 8th... of each kind only, each line naming the endpoint, the peer's
address, why, the running count and what to do: a flood of *n* refusals costs the log about
log2(*n*) lines per kind (12 for 3,000), and the exact counts are in the endpoint's status.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Mapping
from typing import Any


def peer_address(address: Any) -> str:
    """A peer's address as ``host:port`` (``[host]:port`` for IPv6) from what ``getpeername``
    or an ASGI scope's ``client`` gives; ``an unknown address`` when there is none."""
    if isinstance(address, list | tuple) and len(address) >= 2:
        host, port = str(address[0]), address[1]
        return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
    if isinstance(address, str) and address:
        return address[:80]
    return "an unknown address"


class Refusals:
    """The refusals of the endpoint ``where`` (its name in the log lines), by kind: ``kinds``
    maps each kind to why it is refused (the words of the log line), ``todo`` says what to do
    (the end of every line). Thread-safe."""

    def __init__(
        self, logger: logging.Logger, where: str, kinds: Mapping[str, str], todo: str
    ) -> None:
        self._log = logger
        self.where = where
        self._why = dict(kinds)
        self._todo = todo
        self._counts = dict.fromkeys(self._why, 0)
        self._lock = threading.Lock()

    def refused(
        self, kind: str, peer: str, what: str = "a connection", detail: str | None = None
    ) -> int:
        """Count a refusal of ``kind`` of ``what`` from ``peer`` (:func:`peer_address`); log it,
        with ``detail`` after the kind's reason when given, if it is the 1st, 2nd, 4th, 8th...
        of its kind. Returns the count of its kind."""
        with self._lock:
            self._counts[kind] += 1
            count = self._counts[kind]
        if count & (count - 1) == 0:
            why = self._why[kind] + (f" ({detail[:200]})" if detail else "")
            self._log.warning(
                "%s: refused %s from %s: %s (%d refused so far for that reason, logged on the "
                "1st, 2nd, 4th, 8th... only; %s)",
                self.where,
                what[:80],
                peer,
                why,
                count,
                self._todo,
            )
        return count

    def counts(self) -> dict[str, int]:
        """How many refusals of each kind so far."""
        with self._lock:
            return dict(self._counts)
