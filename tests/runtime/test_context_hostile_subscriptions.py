"""Hostile subscribers and publishers of the context provider (issue 14, items 1 and 2; issue 22,
item 1): an untrusted subscription cannot take a quadratic XPath (nor one over the cost limit), a document too costly to evaluate is refused
and counted against its publisher (the subscription stays), a slow evaluation does not hold up
other publishers, strikes decay, and a suspended subscriber is told."""

from __future__ import annotations

import threading
import time

import pytest
from lxml import etree

from acordcs.runtime.context import (
    ContextProvider,
    Limits,
    Notification,
    PublishError,
    SubscriptionError,
)
from tests.support.services import wait_for

ATTACKS = [
    "//*[count(//*[count(//*) > 0]) > 0]",
    "//*[count(//*) > 0]",
    "//a[.//b]",
    "//a[descendant::b]",
    "//a/following::b",
    "//a[preceding-sibling::b]",
    "//a[b[c[d]]]",
    "//a[x > /r/limit]",
    "//*[string-length(..) = 1]",
    "//*[count(../*) > 0]",
    "(//alarm | //fault)[last()]",
    "//*[contains(., 'a') and contains(., 'b') and contains(., 'c') and contains(., 'd')"
    " and contains(., 'e')]",
]
ALLOWED = [
    "//*[contains(., 'fire')]",
    "count(//alarm) > 1",
    "//alarm[level/value > 3 and @zone = 'b']",
    "/site/alarm[not(ack)][2]",
    "(/site | //fault)[last()]",
    "sum(//value) > 10",
    "//alarm[1][1][1][1][1][1][1][1][1]",
    "//*[name(..) = 'site' and count(*) = 1]",
]
SITE = (
    "<site><alarm zone='a'><level><value>2</value></level>fire</alarm>"
    "<alarm zone='b'><level><value>5</value></level>smoke</alarm>"
    "<fault>fire door</fault><value>9</value></site>"
)


@pytest.mark.parametrize("xpath", ATTACKS)
def test_an_untrusted_subscriber_cannot_take_a_superlinear_or_too_costly_xpath(xpath: str) -> None:
    with ContextProvider() as provider:
        with pytest.raises(SubscriptionError, match="too costly for a subscription") as caught:
            provider.subscribe(print, xpath)
        assert caught.value.column is not None
        assert provider.subscriptions() == []


@pytest.mark.parametrize("xpath", ALLOWED)
def test_the_linear_forms_are_allowed_and_match_like_lxml(xpath: str) -> None:
    notes: list[Notification] = []
    with ContextProvider() as provider:
        provider.subscribe(notes.append, xpath)
        provider.publish("site", SITE)
        want = etree.XPath(xpath)(etree.ElementTree(etree.fromstring(SITE)))
        assert wait_for(lambda: len(notes) == 1)
    got = notes[0].value
    if isinstance(want, list):
        assert [etree.tostring(n) for n in got] == [etree.tostring(n) for n in want]
    else:
        assert got == want


def test_a_trusted_subscriber_may_take_any_xpath() -> None:
    with ContextProvider(Limits(trusted_subscribers=True)) as provider:
        handle = provider.subscribe(lambda note: None, ATTACKS[0])
        assert handle.active and handle in provider.subscriptions()


def _deep_document(levels: int = 250, text: int = 3600) -> str:
    return "<r>" + f"<e>{'t' * text}" * levels + "</e>" * levels + "</r>"


def test_a_costly_document_is_refused_not_the_subscription() -> None:
    notes: list[Notification] = []
    with ContextProvider() as provider:
        handle = provider.subscribe(notes.append, "//*[contains(., 'fire')]")
        for _ in range(3):  # three ~900 KB, 250-level documents: each refused
            with pytest.raises(PublishError, match="more than the limit of 4,000,000"):
                provider.publish("attacker", _deep_document())
        assert provider.rejected_by["attacker"] == 3
        provider.publish("robot", "<robot><alarm>fire</alarm></robot>")
        assert wait_for(lambda: len(notes) == 1)
        assert not handle.stats.suspended and notes[0].publisher == "robot"


def test_a_document_within_the_cost_limit_is_accepted() -> None:
    notes: list[Notification] = []
    with ContextProvider() as provider:
        provider.subscribe(notes.append, "//*[contains(., 'fire')]")
        document = _deep_document(levels=100, text=300).replace("t", "fire", 1)
        assert provider.publish("p", document) == 1  # cost about 1.5 million
        assert wait_for(lambda: len(notes) == 1)
        assert provider.rejected_by.get("p", 0) == 0


def test_a_slow_evaluation_does_not_hold_up_another_publisher() -> None:
    order: list[str] = []
    slow_doc = "<r>" + "<a>x</a>" * 3000 + "</r>"  # the quadratic XPath: about 0.2 s on it
    with ContextProvider(Limits(trusted_subscribers=True, max_eval_seconds=60)) as provider:
        provider.subscribe(lambda note: order.append("slow"), "//*[count(//*) > 0]", "slow")
        provider.subscribe(lambda note: order.append("quick"), "/b[. > 1]", "quick")
        started = threading.Event()

        def publish_slow() -> None:
            started.set()
            provider.publish("slow", slow_doc)

        thread = threading.Thread(target=publish_slow)
        thread.start()
        started.wait(5)
        time.sleep(0.05)  # the slow evaluation is under way
        provider.publish("quick", "<b>2</b>")  # waited for the provider lock before the fix
        thread.join(30)
        assert wait_for(lambda: len(order) == 2)
    assert order == ["quick", "slow"]


def test_strikes_decay_and_a_suspended_subscriber_is_told() -> None:
    told: list[tuple[object, str]] = []
    limits = Limits(
        trusted_subscribers=True, max_eval_seconds=1e-9, max_strikes=3, strike_window=0.3
    )
    with ContextProvider(limits) as provider:
        handle = provider.subscribe(
            print, "//*[count(//*) > 0]", on_suspend=lambda h, why: told.append((h, why))
        )
        for _ in range(2):
            provider.publish("p", "<a/>")
        time.sleep(0.5)  # the two strikes are older than the window: forgotten
        for _ in range(2):
            provider.publish("p", "<a/>")
        assert not handle.stats.suspended
        provider.publish("p", "<a/>")  # a third strike within the window
        assert handle.stats.suspended
        assert wait_for(lambda: len(told) == 1)
    assert told[0][0] is handle and "budget 3 times within 0.3 s" in told[0][1]
