"""Members read on first use: what lets the XMI 2 reader skip most of a large model's classes.

``acordcs-gen validate`` on a model of 2,000 classes looks inside the few hundred that play an
ACORD-CS role; building the attributes, operations and parameters of the others was half the
reading time. The reader (:mod:`acordcs.generator.readers.xmi2`) defers a class's plain attributes
and operations when reading them later gives exactly what reading them at once would:

- they can raise no diagnostic: every member and parameter has an xmi:id, and every id they
  refer to exists;
- they hold nothing read elsewhere: their children are only types, default values,
  multiplicities and parameters (no stereotype block, no comment);
- no id is defined twice (which element an id names would depend on reading order).

The reader checks the ids after its walk: a file where a deferred member refers to a missing id,
or where an id is defined twice, is read again without deferring. Reading the
members of one class happens when its ``attributes`` or ``operations`` are first asked for, or
when :class:`LazyElements` is asked for one of their ids.
"""

from __future__ import annotations

from collections.abc import Callable

from lxml import etree

from acordcs.generator.uml import Classifier, Element, Operation, Property, UmlModel

# What a deferred member's children may be (plain tags, as BOUML and Papyrus write them). XML
# comments and processing instructions are allowed: the reader skips them too.
_ATTRIBUTE_CHILDREN = frozenset(("type", "defaultValue", "lowerValue", "upperValue"))


def _typed_refs(
    el: etree._Element, xmi_id: str, xmi_idref: str, allowed: frozenset[str] | None, ids: list[str]
) -> list[str] | None:
    """Every id ``el`` may name as its type, a superset of the one the reader keeps: its ``type``
    attribute (Eclipse) and the ``xmi:idref`` of its plain ``type`` children (BOUML; the reader
    ignores it beside an ``href``, and then keeps the attribute's). None if a child's tag is not in
    ``allowed`` (None: any child; the reader ignores all but the type). Adds the xmi:ids of its
    other children (default values, multiplicities) to ``ids``."""
    types = el.get("type")
    refs = types.split() if types else []
    for child in el:
        tag = child.tag
        if tag == "type":
            ref = child.get(xmi_idref)
            if ref is not None:
                refs.append(ref)
        elif allowed is not None and tag not in allowed and isinstance(tag, str):
            return None
        else:
            ident = child.get(xmi_id)
            if ident is not None:
                ids.append(ident)
    return refs


class DeferringReader:
    """What the XMI 2 reader does with plain attributes and operations when it defers them.

    A class's members keep file order: once one member of a class must be read now, those
    deferred so far are read first and the rest as they come.
    """

    # The reader's: its model, walk state and readers of one member.
    XID: str
    XIDREF: str
    model: UmlModel
    deferred: dict[str, Classifier]  # member and parameter ids -> their class
    deferred_refs: list[str]  # the ids deferred members refer to: must all exist
    pending_ids: dict[int, list[str]]  # id(class) -> every xmi:id in its deferred members
    now: set[int]  # ids of classes whose members are read as they come
    type_refs: list[Element]
    walked: bool
    _property: Callable[[etree._Element, Element], Property]
    _operation: Callable[[etree._Element, Classifier], Operation]

    def _lazy_attribute(self, child: etree._Element, owner: Element) -> None:
        if not isinstance(owner, Classifier):
            return
        if id(owner) not in self.now and child.tag == "ownedAttribute":
            ident = child.get(self.XID)
            if ident is not None:
                ids = [ident]
                refs = _typed_refs(child, self.XID, self.XIDREF, _ATTRIBUTE_CHILDREN, ids)
                if refs is not None:
                    association = child.get("association")
                    if association:  # an end: its association must exist too
                        refs.append(association)
                    self.deferred_refs += refs
                    self.deferred[ident] = owner
                    self._pend(child, owner, ids)
                    return
        self._read_now(owner)
        prop = self._property(child, owner)
        (owner._ends if prop.association else owner._attributes).append(prop)

    def _lazy_operation(self, child: etree._Element, owner: Element) -> None:
        if not isinstance(owner, Classifier):
            return
        if id(owner) not in self.now and child.tag == "ownedOperation":
            found = self._operation_ids(child)
            if found is not None:
                elements, ids, refs = found
                self.deferred_refs += refs
                for ident in elements:
                    self.deferred[ident] = owner
                self._pend(child, owner, ids)
                return
        self._read_now(owner)
        owner._operations.append(self._operation(child, owner))

    def _operation_ids(self, el: etree._Element) -> tuple[list[str], list[str], list[str]] | None:
        """If an operation can be read later: the ids of it and its parameters (elements), every
        xmi:id in it, and the ids they refer to; else None."""
        ident = el.get(self.XID)
        if ident is None:
            return None
        elements = [ident]
        ids = [ident]
        refs: list[str] = []
        for child in el:
            tag = child.tag
            if tag == "ownedParameter":
                param = child.get(self.XID)
                if not param:
                    return None
                elements.append(param)
                ids.append(param)
                refs += _typed_refs(child, self.XID, self.XIDREF, None, ids)
            elif isinstance(tag, str):
                return None
        return elements, ids, refs

    def _pend(self, child: etree._Element, owner: Classifier, ids: list[str]) -> None:
        if owner._pending is None:
            owner._pending = []
            owner._load = self._load
            self.pending_ids[id(owner)] = ids
        else:
            self.pending_ids[id(owner)] += ids
        owner._pending.append(child)

    def _read_now(self, owner: Classifier) -> None:
        """From here on, ``owner``'s members are read as they come, after those deferred so far:
        its lists keep file order."""
        self.now.add(id(owner))
        if owner._pending is not None:
            self._load(owner)

    def _load(self, owner: Classifier) -> None:
        pending, owner._pending = owner._pending, None
        if not self.walked:  # asked for during the walk: the rest of the class as it comes
            self.now.add(id(owner))
            self.pending_ids.pop(id(owner), None)  # its elements are seen as they are read
        first = len(self.type_refs)
        for child in pending:
            if child.tag == "ownedAttribute":
                prop = self._property(child, owner)
                (owner._ends if prop.association else owner._attributes).append(prop)
            else:
                owner._operations.append(self._operation(child, owner))
        if self.walked:  # resolved now; none dangles (see the module's docstring)
            loaded = self.type_refs[first:]
            del self.type_refs[first:]
            elements = self.model.elements
            for obj in loaded:
                target = elements.get(obj.type_ref)
                if target is not None:
                    obj.type_name = target.name


class LazyElements(dict):
    """The model's elements by id, reading deferred members when one of their ids is asked for.

    Lookups of ids that are present cost what a dict's do; enumerating reads everything first.
    """

    __slots__ = ("_owners",)

    def __init__(self, owners: dict[str, Classifier]) -> None:
        super().__init__()
        self._owners = owners  # id of a deferred member or parameter -> its class

    def __missing__(self, key: str) -> Element:
        owner = self._owners.get(key)
        if owner is not None and owner._pending is not None:
            owner._load(owner)
            if dict.__contains__(self, key):
                return dict.__getitem__(self, key)
        raise KeyError(key)

    def get(self, key: str, default: Element | None = None) -> Element | None:
        try:
            return self[key]
        except KeyError:
            return default

    def __contains__(self, key: object) -> bool:
        return dict.__contains__(self, key) or self.get(key) is not None

    def load_all(self) -> None:
        for owner in dict.fromkeys(self._owners.values()):
            if owner._pending is not None:
                owner._load(owner)
        self._owners = {}

    def __iter__(self):
        self.load_all()
        return dict.__iter__(self)

    def __len__(self) -> int:
        self.load_all()
        return dict.__len__(self)

    def keys(self):
        self.load_all()
        return dict.keys(self)

    def values(self):
        self.load_all()
        return dict.values(self)

    def items(self):
        self.load_all()
        return dict.items(self)

    def __repr__(self) -> str:
        self.load_all()
        return dict.__repr__(self)
