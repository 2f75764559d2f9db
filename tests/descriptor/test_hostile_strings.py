"""Whatever a model's strings hold (quotes, ``<``, ``&``, ``]]>``, newlines, carriage returns,
non-ASCII), the descriptor is well-formed, valid and reads back unchanged; a character XML 1.0
cannot hold (C0 controls but tab, LF and CR; U+FFFE, U+FFFF; lone surrogates) is refused with a
:class:`DescriptorError` naming the element and field, never written."""

from __future__ import annotations

import dataclasses
import re

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from lxml import etree

from acordcs.descriptor import Application, DescriptorError, from_xml, schema, to_xml

_FORBIDDEN = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")
_NASTY = list("\"'<>&]\n\r\t :;#=/\\{}$é中ß\u2028\u202e\x7f\x85\x00\x01\x0b\x1f\ufffe\uffff\ud800")

hostile = st.one_of(
    st.text(),
    st.text(alphabet=st.sampled_from(_NASTY)),
    st.sampled_from(
        ["]]>", "<![CDATA[x]]>", "&amp;", "&#0;", "\"'<>&", "a\r\nb", " lead", "trail "]
    ),
)

FIELDS = [
    "application name",
    "container host",
    "container documentation",
    "component name",
    "component qualified name",
    "property id",
    "string default",
    "operation return type",
    "parameter type",
    "rule text",
    "rule label",
    "rule tag",
    "term name",
    "variable element",
]


def _put(app: Application, field: str, s: str) -> Application:
    """``app`` with ``s`` in ``field`` (renaming a component renames the references to it)."""
    r = dataclasses.replace
    if field == "application name":
        return r(app, name=s)
    if field.startswith("container"):
        c = app.containers[0]
        c = r(c, host=s) if field.endswith("host") else r(c, documentation=s)
        return r(app, containers=(c, *app.containers[1:]))
    if field == "component name":
        assume(s not in {c.name for c in app.components})
        old = "Vision"
        comps = tuple(r(c, name=s) if c.name == old else c for c in app.components)
        conns = tuple(
            r(k, provided=r(k.provided, component=s)) if k.provided.component == old else k
            for k in app.connections
        )
        return r(app, components=comps, connections=conns)
    comp = next(c for c in app.components if c.name == "PanoramicCamera")
    if field == "component qualified name":
        new = r(comp, qualified_name=s)
    elif field == "property id":
        new = r(comp, properties=(r(comp.properties[0], id=s), *comp.properties[1:]))
    elif field == "string default":
        res = comp.properties[1]
        assert res.kind == "string"
        new = r(comp, properties=(comp.properties[0], r(res, default=s)))
    elif field == "operation return type":
        new = r(comp, operations=(r(comp.operations[0], return_type=s),))
    elif field == "parameter type":
        op = comp.operations[0]
        new = r(comp, operations=(r(op, parameters=(r(op.parameters[0], type=s),)),))
    else:
        return _put_policy(app, field, s)
    comps = tuple(new if c is comp else c for c in app.components)
    return r(app, components=comps)


def _put_policy(app: Application, field: str, s: str) -> Application:
    r = dataclasses.replace
    ps = app.policy_sets[0]
    if field.startswith("rule"):
        pol = ps.policies[0]
        rule = pol.rules[0]
        what = {"rule text": "text", "rule label": "label", "rule tag": "tag"}[field]
        pol = r(pol, rules=(r(rule, **{what: s}), *pol.rules[1:]))
        ps = r(ps, policies=(pol, *ps.policies[1:]))
    else:
        var = ps.variables[0]
        if field == "term name":
            var = r(var, terms=(r(var.terms[0], name=s), *var.terms[1:]))
        else:
            var = r(var, element=s)
        ps = r(ps, variables=(var, *ps.variables[1:]))
    return r(app, policy_sets=(ps, *app.policy_sets[1:]))


@pytest.mark.parametrize("field", FIELDS)
@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(s=hostile)
def test_hostile_string_is_escaped_or_refused(weblab, field, s):
    app = _put(weblab, field, s)
    if _FORBIDDEN.search(s):
        with pytest.raises(DescriptorError) as err:
            to_xml(app)
        assert "XML 1.0 cannot hold" in str(err.value)
        return
    data = to_xml(app)
    doc = etree.fromstring(data)  # well-formed for a plain parser
    schema().assertValid(doc)
    assert from_xml(data) == app


def test_refusal_names_the_element_and_the_field(weblab):
    app = _put(weblab, "rule text", "if a is b\x01 then c is d")
    with pytest.raises(DescriptorError) as err:
        to_xml(app)
    message = str(err.value)
    assert "policy 'FrameRateRules'" in message and "rule" in message and "U+0001" in message
    assert err.value.hint


def test_non_finite_number_is_refused(weblab):
    mon = dataclasses.replace(weblab.monitors[2], frequency=float("nan"))
    app = dataclasses.replace(weblab, monitors=(*weblab.monitors[:2], mon))
    with pytest.raises(DescriptorError, match="finite"):
        to_xml(app)


def test_default_of_the_wrong_python_type_is_refused(weblab):
    comp = weblab.components[0]
    bad = dataclasses.replace(comp.properties[0], default="ten")  # kind int
    app = dataclasses.replace(
        weblab,
        components=(dataclasses.replace(comp, properties=(bad,)), *weblab.components[1:]),
    )
    with pytest.raises(DescriptorError, match="is not of kind int"):
        to_xml(app)
