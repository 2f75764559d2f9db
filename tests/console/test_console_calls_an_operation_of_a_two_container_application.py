"""``acordcs-gen console`` on the two-container Papyrus ventilation, started by its generated
scripts, in Debian's headless chromium (issue 31): the diagram shows both containers and the
remote connection between them with its connector; calling ``Fan.setSpeed`` through the provided
port ``FanPort`` from the form (its parameter typed by the model: a number) returns its result,
and the call went through the port: a watch of the container's own observer interface, naming
the operation, sees it arrive with its argument (an oracle the console does not make)."""

from __future__ import annotations

import pytest

from tests.console.attached_console import TOKEN, attached
from tests.console.test_console_shows_and_drives_the_greenhouse_in_a_browser import names, until
from tests.support.toolchain import SAMPLES

pytestmark = pytest.mark.service

VENTILATION = SAMPLES / "papyrus" / "ventilation.uml"


def test_the_diagram_shows_both_containers_and_a_call_from_the_form_returns_through_the_port(
    tmp_path, chromium
):
    from selenium.webdriver.support.ui import Select

    d = chromium
    with attached(VENTILATION, "ventilation_app", tmp_path) as found:
        d.get(f"{found.url}/#token={TOKEN}")
        until(d, lambda d: names(d, "container"), "the diagram")
        assert names(d, "container") == {"Office", "Plant"}
        assert names(d, "component") == {"Fan", "Panel"}
        assert names(d, "connection") == {"FanLink"}
        label = d.find_element("css selector", "svg.architecture").text
        assert "FanLink: remote, synchronous" in label

        app = found.session.app
        watch = app.observe("Plant", "watch", ["Fan.setSpeed"], False)
        Select(d.find_element("id", "operation")).select_by_visible_text(
            "Fan.FanPort.setSpeed(level: double)"
        )
        level = d.find_element("css selector", '#parameters input[name="level"]')
        assert level.get_attribute("type") == "number"
        level.send_keys("55")
        d.find_element("id", "call").click()
        until(d, lambda d: d.find_element("id", "call-result").text == "→ null", "the result")
        seen = []
        after = watch["after"]
        while not seen:
            reply = app.observe("Plant", "poll", watch["watch"], after, 2.0)
            assert reply["events"] or reply["more"], "the call never reached Fan.setSpeed"
            after = reply["after"]
            seen = [e for e in reply["events"] if e["kind"] == "operation.called"]
        assert [(e["element"], e["attribute"], e["args"]) for e in seen] == [
            ("Fan", "setSpeed", [55.0])
        ]
        app.observe("Plant", "unwatch", watch["watch"])
