"""The embedded context provider: API, policies, bad input and faulty subscribers."""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest
from lxml import etree

from acordcs.runtime.context import (
    ContextError,
    ContextProvider,
    Limits,
    Notification,
    PublishError,
    SubscriptionError,
)
from tests.support.services import wait_for


class Inbox:
    def __init__(self) -> None:
        self.notes: list[Notification] = []
        self.lock = threading.Lock()

    def __call__(self, note: Notification) -> None:
        with self.lock:
            self.notes.append(note)

    def __len__(self) -> int:
        with self.lock:
            return len(self.notes)

    def values(self) -> list[list[str]]:
        with self.lock:
            return [[n.text for n in note.nodes] for note in self.notes]


@pytest.fixture
def provider():
    with ContextProvider() as prov:
        yield prov
    # closing joined every delivery worker
    assert not [t for t in threading.enumerate() if t.name.startswith("acordcs-ctx-")]


def test_publish_notifies_with_publisher_seq_document_and_nodes(provider: ContextProvider) -> None:
    inbox = Inbox()
    provider.subscribe(inbox, "/robot/battery[. < 20]")
    assert provider.publish("robot1", "<robot><battery>50</battery></robot>") == 1
    assert provider.publish("robot1", b"<robot><battery>15</battery></robot>") == 2
    assert wait_for(lambda: len(inbox) == 1)
    note = inbox.notes[0]
    assert (note.publisher, note.seq) == ("robot1", 2)
    assert note.document.getroot().tag == "robot"
    assert [n.text for n in note.nodes] == ["15"]


def test_publisher_selection_and_everything(provider: ContextProvider) -> None:
    only_r2, everything = Inbox(), Inbox()
    provider.subscribe(only_r2, publisher="r2")
    provider.subscribe(everything)
    provider.publish("r1", "<a/>")
    provider.publish("r2", "<b/>")
    assert wait_for(lambda: len(everything) == 2 and len(only_r2) == 1)
    assert [(n.publisher, n.nodes[0].tag) for n in only_r2.notes] == [("r2", "b")]


def test_lxml_element_input_is_copied(provider: ContextProvider) -> None:
    inbox = Inbox()
    provider.subscribe(inbox, "/s/v")
    elem = etree.fromstring("<s><v>1</v></s>")
    provider.publish("p", elem)
    elem[0].text = "changed by the publisher afterwards"
    assert wait_for(lambda: len(inbox) == 1)
    assert inbox.values() == [["1"]]


def test_query_reads_latest_document_of_each_publisher(provider: ContextProvider) -> None:
    provider.publish("r1", "<robot><speed>1</speed></robot>")
    provider.publish("r1", "<robot><speed>3</speed></robot>")
    provider.publish("r2", "<robot><speed>0.5</speed></robot>")
    fast = provider.query("/robot/speed[. > 0.7]")
    assert [(r.publisher, r.seq, r.nodes[0].text) for r in fast] == [("r1", 2, "3")]
    assert [r.value for r in provider.query("count(//speed)")] == [1.0, 1.0]
    assert provider.query("number(/robot/missing)") == []  # NaN is false, as in XPath boolean()
    assert provider.query("/robot", publisher="r2")[0].publisher == "r2"
    assert provider.query("/robot", publisher="nobody") == []


def test_unsubscribe_stops_notifications(provider: ContextProvider) -> None:
    inbox, witness = Inbox(), Inbox()
    handle = provider.subscribe(inbox)
    provider.subscribe(witness)
    provider.publish("p", "<a/>")
    assert wait_for(lambda: len(inbox) == 1)
    assert provider.unsubscribe(handle) is True
    assert provider.unsubscribe(handle) is False
    provider.publish("p", "<a/>")
    assert wait_for(lambda: len(witness) == 2)
    assert len(inbox) == 1


def test_max_rate_keeps_the_latest(provider: ContextProvider) -> None:
    inbox = Inbox()
    handle = provider.subscribe(inbox, "/t", max_rate=2)
    for i in range(50):
        provider.publish("p", f"<t>{i}</t>")
    assert wait_for(lambda: inbox.notes and inbox.notes[-1].seq == 50)
    seqs = [n.seq for n in inbox.notes]
    assert seqs == sorted(seqs) and len(seqs) < 50
    assert handle.stats.coalesced + handle.stats.delivered == 50


def test_on_change_only_when_selection_changes(provider: ContextProvider) -> None:
    inbox = Inbox()
    handle = provider.subscribe(inbox, "/r/t[. > 30]", on_change=True)
    for value in (31, 31, 25, 31, 31, 40):
        provider.publish("p", f"<r><t>{value}</t></r>")
    provider.publish("other", "<r><t>31</t></r>")  # selections are tracked per publisher
    assert wait_for(lambda: len(inbox) == 5)
    assert [(n.publisher, n.seq, [x.text for x in n.nodes]) for n in inbox.notes] == [
        ("p", 1, ["31"]),
        ("p", 3, []),  # became empty
        ("p", 4, ["31"]),
        ("p", 6, ["40"]),
        ("other", 1, ["31"]),
    ]
    assert handle.stats.unchanged == 2


# -- bad input ------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "document",
    [b"<a><b></a>", "not xml", b"", b"<a>\xff</a>", b"<a/><b/>", 42],
)
def test_malformed_publish_is_rejected_and_nothing_else_changes(
    provider: ContextProvider, document
) -> None:
    inbox = Inbox()
    provider.subscribe(inbox)
    provider.publish("p", "<good/>")
    with pytest.raises(PublishError) as info:
        provider.publish("p", document)
    assert "publisher 'p'" in str(info.value) and info.value.hint
    assert provider.latest("p")[0] == 1 and provider.latest("p")[1].getroot().tag == "good"
    assert provider.publish("p", "<again/>") == 2  # the refused document used no sequence number
    assert wait_for(lambda: len(inbox) == 2)
    assert [n.seq for n in inbox.notes] == [1, 2]
    assert provider.stats()["rejected"] == 1


def test_str_with_foreign_encoding_declaration_is_refused(provider: ContextProvider) -> None:
    with pytest.raises(PublishError, match="declares encoding 'latin-1'"):
        provider.publish("p", "<?xml version='1.0' encoding='latin-1'?><a>\u00e9</a>")
    assert provider.publish("p", "<?xml version='1.0' encoding='UTF-8'?><a>\u00e9</a>") == 1
    assert (
        provider.publish(
            "p", "<?xml version='1.0' encoding='ISO-8859-1'?><a>\u00e9</a>".encode("latin-1")
        )
        == 2
    )
    assert provider.latest("p")[1].getroot().text == "\u00e9"


def test_malformed_publish_reports_line_and_column(provider: ContextProvider) -> None:
    with pytest.raises(PublishError) as info:
        provider.publish("p", "<a>\n  <b></c>\n</a>")
    assert info.value.line == 2 and info.value.column


def test_xxe_target_is_never_read(provider: ContextProvider, tmp_path: Path) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    doc = f'<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file://{secret}">]><r>&x;</r>'
    with pytest.raises(PublishError, match="DOCTYPE"):
        provider.publish("p", doc)
    # In UTF-16 too (the byte scan reads it; tests/test_safexml.py holds libxml2 itself to never
    # opening the target when a declaration gets past the scan). The target is a FIFO: had anything
    # opened it, publish() would block until a writer appears
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    doc16 = f'<!DOCTYPE r [<!ENTITY x SYSTEM "file://{fifo}">]><r>&x;</r>'.encode("utf-16")
    outcome: list[BaseException | int] = []

    def attempt() -> None:
        try:
            outcome.append(provider.publish("p", doc16))
        except BaseException as err:
            outcome.append(err)

    worker = threading.Thread(target=attempt)
    worker.start()
    worker.join(10)
    if worker.is_alive():  # unblock the parser so that the test can end, then fail
        fd = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)
        os.close(fd)
        worker.join(5)
        pytest.fail("the parser opened the external entity's target")
    assert isinstance(outcome[0], PublishError) and "DOCTYPE" in str(outcome[0])
    assert provider.latest("p") is None


@pytest.mark.parametrize("encoding", ["utf-8", "utf-16"])
def test_entity_bomb_is_refused(provider: ContextProvider, encoding: str) -> None:
    entities = '<!ENTITY a0 "lol">' + "".join(
        f'<!ENTITY a{i} "{f"&a{i - 1};" * 10}">' for i in range(1, 10)
    )
    bomb = f"<!DOCTYPE r [{entities}]><r>&a9;</r>".encode(encoding)
    # UTF-8: refused by the byte scan; UTF-16: by libxml2's amplification limit or the DOCTYPE check
    with pytest.raises(PublishError, match=r"DOCTYPE|amplification"):
        provider.publish("p", bomb)
    assert provider.latest("p") is None


def test_undeclared_entity_is_malformed(provider: ContextProvider) -> None:
    with pytest.raises(PublishError, match="not well-formed"):
        provider.publish("p", "<r>&undeclared;</r>")


def test_size_depth_and_node_limits() -> None:
    small = ContextProvider(Limits(max_bytes=100, max_nodes=50))
    with small, pytest.raises(PublishError, match="exceeds the limit of 100 bytes"):
        small.publish("p", "<a>" + "x" * 200 + "</a>")
    with ContextProvider(Limits(max_nodes=50)) as prov:
        with pytest.raises(PublishError, match="nodes, more than the limit of 50"):
            prov.publish("p", "<a>" + "<b/>" * 60 + "</a>")
        with pytest.raises(PublishError, match="Excessive depth"):
            prov.publish("p", "<a>" * 300 + "</a>" * 300)
    with ContextProvider(Limits(max_depth=10)) as prov:
        with pytest.raises(PublishError, match="deeper than 10"):
            prov.publish("p", "<a>" * 11 + "</a>" * 11)
        assert prov.publish("p", "<a>" * 10 + "</a>" * 10) == 1


@pytest.mark.parametrize(
    ("xpath", "reason"),
    [
        ("/robot[", "syntax error"),
        ("/robot/speed[. >> 3]", "syntax error"),
        ("frobnicate(/robot)", "Unregistered function"),
        ("/robot[$limit > 3]", "Undefined variable"),
        ("/robot[frobnicate(.) > 3]", "Unregistered function"),  # the probe never reaches it
        ("/x:robot", "Undefined namespace prefix"),
    ],
)
def test_bad_xpath_rejected_at_subscribe(
    provider: ContextProvider, xpath: str, reason: str
) -> None:
    with pytest.raises(SubscriptionError, match=reason) as info:
        provider.subscribe(print, xpath)
    assert xpath in str(info.value) and info.value.hint
    assert provider.subscriptions() == []
    with pytest.raises(SubscriptionError):
        provider.query(xpath)


def test_bad_subscribe_arguments(provider: ContextProvider) -> None:
    with pytest.raises(SubscriptionError, match="max_rate"):
        provider.subscribe(print, max_rate=0)
    with pytest.raises(SubscriptionError, match="queue_size"):
        provider.subscribe(print, queue_size=0)
    with pytest.raises(SubscriptionError, match="not callable"):
        provider.subscribe("print")
    with pytest.raises(ContextError, match="publisher"):
        provider.publish("", "<a/>")
    with pytest.raises(SubscriptionError, match="exceeds"):
        provider.subscribe(print, "/a" * 3000)


def test_costly_fallback_expression_is_suspended() -> None:
    # every evaluation overruns a 1 ns budget: three strikes, then the subscription stops costing
    # anything (a trusted subscriber: an untrusted one may not use this quadratic expression)
    limits = Limits(max_eval_seconds=1e-9, max_strikes=3, trusted_subscribers=True)
    with ContextProvider(limits) as prov:
        inbox, cheap = Inbox(), Inbox()
        handle = prov.subscribe(inbox, "//*[count(//*) > 0]")
        prov.subscribe(cheap, "/a/b[. > 1]")  # indexed: not timed, never suspended
        for _ in range(5):
            prov.publish("p", "<a><b>2</b></a>")
        assert wait_for(lambda: len(cheap) == 5 and len(inbox) == 3)
        assert handle.stats.suspended
        assert prov.stats()["suspended"] == [repr(handle)]


# -- faulty subscribers ---------------------------------------------------------------------------------
def test_slow_subscriber_blocks_nobody_and_drops_are_counted(provider: ContextProvider) -> None:
    release = threading.Event()
    slow_calls = []

    def slow(note: Notification) -> None:
        slow_calls.append(note.seq)
        release.wait(10)

    fast = Inbox()
    handle = provider.subscribe(slow, queue_size=4)
    provider.subscribe(fast)
    for i in range(20):
        provider.publish("p", f"<n>{i}</n>")  # would hang here if publish waited for ``slow``
    assert wait_for(lambda: len(fast) == 20)
    assert not release.is_set() and handle.stats.dropped >= 15
    release.set()
    assert wait_for(lambda: handle.stats.delivered + handle.stats.dropped == 20)
    assert provider.stats()["dropped"] == handle.stats.dropped
    assert slow_calls[-1] == 20  # drops discard the oldest: the latest context survives


def test_threads_follow_concurrent_callbacks_not_subscriptions(provider: ContextProvider) -> None:
    inboxes = [Inbox() for _ in range(200)]
    for inbox in inboxes:
        provider.subscribe(inbox, "/n[. > 0]")
    for i in range(1, 6):
        provider.publish("p", f"<n>{i}</n>")
    assert wait_for(lambda: all(len(inbox) == 5 for inbox in inboxes))
    assert all([n.seq for n in inbox.notes] == [1, 2, 3, 4, 5] for inbox in inboxes)  # in order
    assert provider._dispatcher.threads < 50


def test_raising_subscriber_keeps_receiving_and_others_unaffected(
    provider: ContextProvider,
) -> None:
    def broken(note: Notification) -> None:
        raise RuntimeError("subscriber bug")

    fine = Inbox()
    handle = provider.subscribe(broken)
    provider.subscribe(fine)
    for _ in range(5):
        provider.publish("p", "<a/>")
    assert wait_for(lambda: len(fine) == 5 and handle.stats.errors == 5)
    assert handle.stats.last_error == "RuntimeError: subscriber bug"
    assert provider.stats()["callback_errors"] == 5


def test_closed_provider_refuses_work() -> None:
    prov = ContextProvider()
    prov.subscribe(print)
    prov.close()
    prov.close()
    assert prov.subscriptions() == []
    with pytest.raises(ContextError, match="closed"):
        prov.publish("p", "<a/>")
