"""The Java names the ``java`` target gives a model's names (``java.xsl``: ``j:ident``,
``j:package``, ``j:method``), for the host that loads those classes and calls their methods.
The stylesheet is the declaration; tests compare both on hostile names."""

from __future__ import annotations

import re

KEYWORDS = frozenset(
    """abstract assert boolean break byte case catch char class const continue default do double
    else enum extends final finally float for goto if implements import instanceof int interface
    long native new package private protected public return short static strictfp super switch
    synchronized this throw throws transient try void volatile while true false null _ var record
    yield sealed permits exports module open opens provides requires to transitive uses with java
    org""".split()
)
"""``j:keywords``: Java's keywords and literals, its contextual keywords, ``java`` and ``org``."""

TAKEN_METHODS = frozenset(
    """getClass notify notifyAll wait hashCode equals toString clone finalize componentName addPort
    port ports propertyNames propertyType getProperty setProperty asInt asLong asDouble asBoolean
    asString unknownProperty attachHost host hostSet ruleEngine onStart onStop onPropertyChanged
    onMessage""".split()
)
"""``j:taken-methods``: the methods of ``Object`` and ``CtxComponent`` a generated one avoids."""


def identifier(name: str) -> str:
    """``j:ident``: a Java identifier for ``name``."""
    text = re.sub(r"[^A-Za-z0-9_]", "_", name) or "_"
    if text[0].isdigit():
        text = "_" + text
    return text + "_" if text in KEYWORDS else text


def package(application: str) -> str:
    """``j:package``: the Java package of the application's classes."""
    return identifier(application.lower())


def method(name: str) -> str:
    """``j:method``: the Java method of an operation named ``name``."""
    text = identifier(name)
    return text + "_" if text in TAKEN_METHODS else text
