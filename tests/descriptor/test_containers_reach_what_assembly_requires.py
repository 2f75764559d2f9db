"""``Container.reaches``, computed once by ``describe`` and carried by the descriptor (the
``shell`` target's start scripts read it to pass ``--remote``): for each container of both
samples, exactly the other containers ``assemble`` requires to build it alone. With them it
assembles; without any one of them it refuses. A ``reaches`` naming no container of the document
does not validate."""

from __future__ import annotations

import pytest

from acordcs.descriptor import DescriptorError, from_xml, to_xml
from acordcs.runtime.api import VirtualClock
from acordcs.runtime.assembly import assemble
from acordcs.runtime.errors import RuntimeFailure


def test_the_weblab_containers_reach_each_other(weblab) -> None:
    assert {c.name: c.reaches for c in weblab.containers} == {
        "UserSide": ("WebLabSide",),
        "WebLabSide": ("UserSide",),
    }


@pytest.mark.parametrize("sample", ["weblab", "smartroom"])
def test_reaches_is_what_assembly_requires(sample: str, request) -> None:
    app = request.getfixturevalue(sample)
    for c in app.containers:
        uris = {n: f"PYRO:acordcs.container.{n}@127.0.0.1:9" for n in c.reaches}
        assert c.name not in uris
        assemble(app, only=[c.name], clock=VirtualClock(0), remote=uris).close()
        for missing in c.reaches:
            fewer = {n: u for n, u in uris.items() if n != missing}
            with pytest.raises(RuntimeFailure):
                assemble(app, only=[c.name], clock=VirtualClock(0), remote=fewer)


def test_reaches_reads_back_and_must_name_a_container(weblab) -> None:
    data = to_xml(weblab)
    assert b'<reaches name="WebLabSide"/>' in data
    assert from_xml(data) == weblab
    forged = data.replace(b'<reaches name="WebLabSide"/>', b'<reaches name="Elsewhere"/>')
    with pytest.raises(DescriptorError, match="reachedContainer"):
        from_xml(forged)
