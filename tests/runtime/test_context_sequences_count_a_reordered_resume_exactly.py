"""A resumed MQTT session whose broker sends a new document before the ones it queued (mosquitto
2.0.11 does): every queued one is delivered late, none is counted lost, the new one that came
first is not counted lost when the sequence passes it, and its repeat is refused."""

from __future__ import annotations

from acordcs.runtime.context.sequences import LATE, NEW, REFUSED, SequenceBook


def book() -> SequenceBook:
    return SequenceBook(max_publishers=8, max_seq_jump=10_000, where="broker")


def test_queued_documents_after_a_new_one_are_late_and_nothing_is_lost():
    seqs = book()
    admitted = [seqs.admit("p", b"e", n) for n in range(1, 501)]
    assert admitted == [NEW] * 500
    assert seqs.admit("p", b"e", 801) == NEW  # the new one, first
    assert seqs.lost == 300  # 501..800 not come yet
    queued = [seqs.admit("p", b"e", n) for n in range(501, 801)]
    assert queued[:2] == [LATE, LATE]  # then the sequence is taken up again from 503
    assert all(a in (LATE, NEW) for a in queued)
    assert seqs.admit("p", b"e", 801) == REFUSED  # taken already: a repeat now
    assert seqs.admit("p", b"e", 802) == NEW
    assert seqs.lost == 0 and seqs.late >= 2
    assert seqs.figures()["lost"] == 0


def test_a_real_gap_after_the_reordering_is_still_counted():
    seqs = book()
    for n in range(1, 11):
        seqs.admit("p", b"e", n)
    seqs.admit("p", b"e", 21)
    for n in range(11, 21):
        seqs.admit("p", b"e", n)
    assert seqs.lost == 0
    assert seqs.admit("p", b"e", 25) == NEW  # 22, 23, 24 never come
    assert seqs.lost == 3
