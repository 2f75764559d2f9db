"""The sequence numbers of MQTT context publishers, as one client sees them: losses (gaps, and a
lost tail told by a publisher's end marker), documents that come late (after a later one: a
broker resuming a session may send a new document before those it queued), repeats, forged
jumps, restarted sequences and publishers beyond the cap (see :mod:`acordcs.runtime.context.mqtt`).

:meth:`SequenceBook.admit` answers :data:`REFUSED`, :data:`NEW` (the publisher's latest) or
:data:`LATE` (a number counted lost that came after all: delivered, not the latest; ``lost`` goes
down by one). The numbers of a gap are remembered, up to :data:`MAX_MISSING` per publisher, so
that a late one is told from a repeat."""

from __future__ import annotations

import logging
import threading

log = logging.getLogger("acordcs.runtime.context.mqtt")

REFUSED, NEW, LATE = 0, 1, 2
MAX_MISSING = 1024
"""Numbers of a publisher's gaps remembered, the most recent ones (a number no longer remembered
that comes later is taken for a repeat); bounded, as hostile publishers may make gaps at will."""
RESYNC_AFTER = 3
"""Documents in a row, with rising numbers at or below the last one taken, after which a
publisher's sequence is taken as restarted (the higher number was forged or a lost process's)."""


def every_power_of_two(n: int) -> bool:
    """Log the 1st, 2nd, 4th, 8th... occurrence only: a flood cannot flood the log."""
    return n & (n - 1) == 0


class SequenceBook:
    """Per publisher: the epoch (publishing process) and last sequence number taken, with the
    counts of what the numbers reveal. ``where`` names the broker in diagnostics."""

    def __init__(self, max_publishers: int, max_seq_jump: int, where: str) -> None:
        self.max_publishers, self.max_seq_jump, self.where = max_publishers, max_seq_jump, where
        self.lost = 0  # messages missing from the sequence of a publisher
        self.duplicates = 0
        self.implausible = 0  # sequence jumps larger than max_seq_jump, ignored
        self.resynchronised = 0  # publishers whose sequence was taken as restarted
        self.refused_publishers = 0  # documents of publishers beyond max_publishers
        self.ended = 0  # end markers received: publishers that closed
        self.late = 0  # documents counted lost that came after a later one
        self._lock = threading.Lock()
        self._behind: dict[str, tuple[int, int]] = {}  # publisher -> (last seq below, count)
        self._seen: dict[str, tuple[bytes, int]] = {}  # publisher -> (epoch, last seq)
        self._missing: dict[str, set[int]] = {}  # publisher -> numbers of its gaps
        # publisher -> numbers above a resynchronisation point taken already (a resumed session's
        # new documents that came before its queued ones): not lost when the sequence passes them
        self._taken: dict[str, set[int]] = {}

    def forget(self, publisher: str) -> None:
        """``publisher`` was retired: its next document starts afresh."""
        with self._lock:
            self._seen.pop(publisher, None)
            self._behind.pop(publisher, None)
            self._missing.pop(publisher, None)
            self._taken.pop(publisher, None)

    def figures(self) -> dict[str, int]:
        return {
            "lost": self.lost,
            "duplicates": self.duplicates,
            "implausible": self.implausible,
            "resynchronised": self.resynchronised,
            "refused_publishers": self.refused_publishers,
            "ended": self.ended,
            "late": self.late,
        }

    def admit(self, publisher: str, epoch: bytes, seq: int) -> int:
        """Whether the document ``seq`` of ``publisher`` is :data:`NEW`, :data:`LATE` or
        :data:`REFUSED` (a repeat, a forged jump, a publisher beyond the cap), counting each."""
        with self._lock:
            previous = self._seen.get(publisher)
            if previous is None and len(self._seen) >= self.max_publishers:
                self.refused_publishers += 1
                if every_power_of_two(self.refused_publishers):
                    log.warning(
                        "%s: ignoring the documents of publisher %r: this client already keeps "
                        "max_publishers=%d publishers' documents (%d refused so far); raise "
                        "max_publishers, retire() publishers that are gone, or restrict who may "
                        "publish at the broker (acl_file)",
                        self.where,
                        publisher,
                        self.max_publishers,
                        self.refused_publishers,
                    )
                return REFUSED
            if previous is not None and previous[0] == epoch:
                last = previous[1]
                missing = self._missing.get(publisher)
                if seq <= last and missing and seq in missing:
                    missing.discard(seq)
                    self.lost -= 1
                    self.late += 1
                    if self._behind_last(publisher, epoch, seq, last):
                        return NEW  # resynchronised at this number
                    self.duplicates -= 1  # counted by _behind_last: it was not one
                    return LATE
                taken = self._taken.get(publisher)
                if taken and seq in taken:  # it came before the resynchronisation: a repeat
                    self.duplicates += 1
                    return REFUSED
                if seq <= last:
                    return NEW if self._behind_last(publisher, epoch, seq, last) else REFUSED
                if seq - last > self.max_seq_jump:
                    # said before counted: whoever waits for the count finds the warning logged
                    log.warning(
                        "%s: ignoring seq %d after %d, a jump over max_seq_jump=%d (a forged "
                        "message? sign documents with payload_key)",
                        publisher,
                        seq,
                        last,
                        self.max_seq_jump,
                    )
                    self.implausible += 1
                    return REFUSED
                if seq > last + 1:
                    self._gap(publisher, last, seq)
            self._behind.pop(publisher, None)
            self._seen[publisher] = (epoch, seq)
            return NEW

    def _gap(self, publisher: str, last: int, seq: int) -> None:
        """The numbers between ``last`` and ``seq`` did not come (yet): counted lost, the most
        recent remembered in case they come late. Under the lock."""
        taken = self._taken.get(publisher)
        came = len(taken.intersection(range(last + 1, seq))) if taken else 0
        if taken:
            taken.difference_update(range(last + 1, seq + 1))
        gap = seq - last - 1 - came
        if gap == 0:
            return
        self.lost += gap
        log.warning("%s: %d document(s) lost before seq %d", publisher, gap, seq)
        missing = self._missing.setdefault(publisher, set())
        missing.update(range(max(last + 1, seq - MAX_MISSING), seq))
        if len(missing) > MAX_MISSING:
            kept = sorted(missing)[-MAX_MISSING:]
            missing.clear()
            missing.update(kept)

    def ended_at(self, publisher: str, epoch: bytes, seq: int) -> None:
        """``publisher`` closed after its document ``seq``: the documents after the last one taken
        never came (a lost tail, which no later document would reveal as a gap)."""
        with self._lock:
            self.ended += 1
            previous = self._seen.get(publisher)
            if previous is None or previous[0] != epoch or seq <= previous[1]:
                return  # nothing taken from this run of the publisher, or nothing missing
            if seq - previous[1] > self.max_seq_jump:
                self.implausible += 1
                return
            missing = seq - previous[1]
            self.lost += missing
            self._seen[publisher] = (epoch, seq)
        log.warning(
            "%s: %d document(s) lost after seq %d: its publisher closed after seq %d",
            publisher,
            missing,
            seq - missing,
            seq,
        )

    def _behind_last(self, publisher: str, epoch: bytes, seq: int, last: int) -> bool:
        """A number at or below the last one taken: a repeat (the retained copy after a
        re-subscribe), unless :data:`RESYNC_AFTER` rising ones come in a row: then the last number
        was not the publisher's (forged), and its sequence goes on from ``seq``. Under the lock."""
        below, count = self._behind.get(publisher, (-1, 0))
        count = count + 1 if seq > below else 1
        if count < RESYNC_AFTER:
            self._behind[publisher] = (seq, count)
            self.duplicates += 1
            return False
        del self._behind[publisher]
        self.resynchronised += 1
        # the numbers counted lost above ``seq`` were the gap before the higher number, which
        # was not this sequence's: they are still to come
        missing = self._missing.get(publisher)
        above: set[int] = set()
        if missing:
            above = {n for n in missing if n > seq}
            missing.difference_update(above)
            self.lost -= len(above)
        if last - seq <= MAX_MISSING:
            self._taken[publisher] = set(range(seq + 1, last + 1)) - above
        log.warning(
            "%s: %d documents in a row numbered below seq %d: taking seq %d as its sequence "
            "(the higher number was forged, or sent by another process under this name)",
            publisher,
            count,
            last,
            seq,
        )
        self._seen[publisher] = (epoch, seq)
        return True
