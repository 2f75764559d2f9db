"""XMI 1.0's long element names, rewritten into the XMI 1.1 form that :mod:`.xmi12` reads.

XMI 1.0 (the Novosoft UML library of ArgoUML up to 0.14, Enterprise Architect 3.x) names every
element by its metamodel path and writes every property as a child element::

    <Foundation.Core.Class xmi.id="xmi.8">
      <Foundation.Core.ModelElement.name>Name</Foundation.Core.ModelElement.name>
      <Foundation.Core.ModelElement.visibility xmi.value="public"/>
      <Foundation.Core.Classifier.feature> ... </Foundation.Core.Classifier.feature>

XMI 1.1 writes the same UML 1.3 model as ``<UML:Class xmi.id="xmi.8" name="Name"
visibility="public"><UML:Classifier.feature>``. :func:`normalise` renames in place (so that every
line number stays the file's): a metaclass element keeps its last segment (``Class``), a property
with elements inside keeps its last two (``Classifier.feature``, references and containment alike),
and a property holding a value (text, or ``xmi.value``) becomes an attribute of its element. The
result has unqualified names, as Rational Rose's XMI 1.1 does, which :mod:`.xmi12` reads.
"""

from __future__ import annotations

from lxml import etree

# The top-level packages of the UML 1.x metamodel, as XMI 1.0 prefixes them.
_PACKAGES = ("Foundation.", "Behavioral_Elements.", "Model_Management.")


def long_names(root: etree._Element) -> bool:
    """Whether the model content of an XMI 1.x ``root`` is written with XMI 1.0's long names."""
    content = root.find("XMI.content")
    return content is not None and any(
        isinstance(child.tag, str) and child.tag.startswith(_PACKAGES) for child in content
    )


def normalise(root: etree._Element) -> None:
    """Rewrite ``root``'s XMI 1.0 content in place into XMI 1.1's unqualified form, in one pass
    that holds no list of the elements (a large file stays a tree, not a tree and a list). A value
    element stays where it is, under its long name, once its value is its element's attribute:
    the reader looks for no such child."""
    content = root.find("XMI.content")
    if content is None:
        return
    for el in content.iter(etree.Element):
        tag = el.tag
        if not tag.startswith(_PACKAGES):
            continue
        parts = tag.split(".")
        last = parts[-1]
        try:
            if last[:1].isupper():  # a metaclass: Foundation.Core.Class
                el.tag = last
            elif len(el):  # references or owned elements: Foundation.Core.Classifier.feature
                el.tag = f"{parts[-2]}.{last}"
            else:  # a value: Foundation.Core.ModelElement.name
                parent = el.getparent()
                if parent is not None and parent.get(last) is None:
                    value = el.get("xmi.value")
                    parent.set(last, value if value is not None else el.text or "")
        except ValueError:
            # Not a name XML allows once shortened ("Foundation.Core.Class.-x"): left as written,
            # so the reader skips it and says so.
            continue
