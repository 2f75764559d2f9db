"""Supporting services as components (paper, section 3): an access service and a QoS broker.

:class:`AccessService` enforces use upon reservation and authentication and counts the users of each
experiment (the WebLab's usage monitor polls ``users``). :class:`SessionGuard` is the matching
security interceptor: guarded operations take a ``session=`` keyword, checked (and removed) before the
call; a call without a valid session is vetoed. :class:`QoSBroker` shares a bandwidth capacity among
port connections and writes each grant into the connection's ``bandwidth`` QoS property.

Outcomes the caller must handle (a refused reservation) are return values, not exceptions: an
exception from a component is a fault.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any, ClassVar

from acordcs.runtime import events as ev
from acordcs.runtime.clock import Timer
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.errors import CallVetoed
from acordcs.runtime.events import Event
from acordcs.runtime.interceptors import Interceptor, Invocation


@dataclass
class Reservation:
    user: str
    experiment: str
    start: float
    end: float
    token: str


class AccessService(CtxComponent):
    """Reservations (time slots per experiment), authentication (token -> session), user counts."""

    properties: ClassVar[dict[str, object]] = {"users": 0, "max_users": 4, "reservations": 0}
    state_fields = ("reservations_", "sessions_")

    def __init__(self) -> None:
        self.reservations_: list[dict[str, Any]] = []
        self.sessions_: dict[str, dict[str, Any]] = {}
        self._sweeper: Timer | None = None

    def on_start(self) -> None:
        # Sessions end with their reservation even if nobody calls: sweep once a second.
        self._sweeper = self.clock.call_every(1.0, self.expire)

    def on_stop(self) -> None:
        if self._sweeper is not None:
            self._sweeper.cancel()

    def reserve(self, user: str, experiment: str, start: float, end: float) -> dict[str, Any]:
        """Book ``[start, end)`` (clock seconds); ``{"ok": True, "token": ...}`` or a reason."""
        if not end > start:
            return {"ok": False, "reason": f"empty slot [{start}, {end})"}
        overlapping = [
            r
            for r in self.reservations_
            if r["experiment"] == experiment and r["start"] < end and start < r["end"]
        ]
        if any(r["user"] == user for r in overlapping):
            return {"ok": False, "reason": f"{user} already holds an overlapping reservation"}
        if len(overlapping) >= int(self.get("max_users")):  # type: ignore[call-overload]
            return {"ok": False, "reason": f"experiment {experiment} is fully booked then"}
        token = self.clock.rng("access", self.name).bytes(8).hex()
        self.reservations_.append(asdict(Reservation(user, experiment, start, end, token)))
        self.set("reservations", len(self.reservations_))
        return {"ok": True, "token": token}

    def authenticate(self, user: str, token: str) -> str | None:
        """A session id if ``token`` is ``user``'s reservation and its slot is now; else None."""
        self.expire()
        now = self.clock.now()
        for r in self.reservations_:
            if r["user"] == user and r["token"] == token and r["start"] <= now < r["end"]:
                session = f"{user}:{token}"
                self.sessions_[session] = r
                self._count()
                return session
        return None

    def valid(self, session: str) -> bool:
        self.expire()
        return session in self.sessions_

    def logout(self, session: str) -> None:
        if self.sessions_.pop(session, None) is not None:
            self._count()

    def users_of(self, experiment: str) -> int:
        self.expire()
        return sum(1 for r in self.sessions_.values() if r["experiment"] == experiment)

    def expire(self) -> None:
        now = self.clock.now()
        ended = [s for s, r in self.sessions_.items() if r["end"] <= now]
        for s in ended:
            del self.sessions_[s]
        before = len(self.reservations_)
        self.reservations_ = [r for r in self.reservations_ if r["end"] > now]
        if ended:
            self._count()
        if len(self.reservations_) != before:
            self.set("reservations", len(self.reservations_))

    def _count(self) -> None:
        self.set("users", len(self.sessions_))


class SessionGuard(Interceptor):
    """Vetoes calls that do not carry a valid ``session=`` of the access service named ``access``."""

    name = "session-guard"

    def __init__(self, container: Container, access: str = "Access") -> None:
        self.container = container
        self.access = access

    def before(self, call: Invocation) -> None:
        if call.component == self.access:
            return
        session = call.kwargs.pop("session", None)
        if session is None or not self.container.invoke(self.access, "valid", (session,)):
            raise CallVetoed(
                f"{call.component}.{call.operation}() refused: "
                + ("no session given" if session is None else "session not valid now"),
                where=f"container {self.container.name!r}",
                hint="authenticate with the access service and pass session=...",
            )


class QoSBroker(CtxComponent):
    """Shares ``capacity`` bits/s among connections; a grant sets the connection's ``bandwidth``.

    Requests are served in arrival order up to what is left; lowering ``capacity`` (a policy may)
    scales every grant down proportionally.
    """

    properties: ClassVar[dict[str, object]] = {"capacity": 10e6, "allocated": 0.0}
    state_fields = ("requests_", "grants_")

    def __init__(self) -> None:
        self.requests_: dict[str, float] = {}
        self.grants_: dict[str, float] = {}

    def on_start(self) -> None:
        self.container.subscribe(
            ev.PROPERTY_CHANGED,
            self._capacity_changed,
            name=f"broker:{self.name}",
            element=self.name,
            attribute="capacity",
        )

    def on_stop(self) -> None:
        self.container.unsubscribe(f"broker:{self.name}")

    def request(self, connection: str, bandwidth: float) -> float:
        """Ask for ``bandwidth`` bits/s on a connection; returns the grant (0 when none is left)."""
        if bandwidth < 0:
            raise ValueError(f"bandwidth must be >= 0 bits/s, not {bandwidth}")
        self.requests_[connection] = float(bandwidth)
        others = sum(g for c, g in self.grants_.items() if c != connection)
        grant = max(0.0, min(float(bandwidth), float(self.get("capacity")) - others))  # type: ignore[arg-type]
        self._grant(connection, grant)
        return grant

    def release(self, connection: str) -> None:
        self.requests_.pop(connection, None)
        if self.grants_.pop(connection, None) is not None:
            self.set("allocated", sum(self.grants_.values()))

    def allocation(self, connection: str) -> float:
        return self.grants_.get(connection, 0.0)

    def allocations(self) -> dict[str, float]:
        return dict(self.grants_)

    def _grant(self, connection: str, grant: float) -> None:
        self.grants_[connection] = grant
        if self.container.has_property(connection, "bandwidth"):
            self.container.set_property(connection, "bandwidth", grant)
        self.set("allocated", sum(self.grants_.values()))

    def _capacity_changed(self, event: Event) -> None:
        capacity = float(event.value)  # type: ignore[arg-type]
        total = sum(self.grants_.values())
        if total > capacity and total > 0:
            scale = capacity / total
            for connection, grant in list(self.grants_.items()):
                self._grant(connection, grant * scale)
