"""Features read when first asked for: the XMI 2 reader's classifiers whose attributes and operations
nobody needs at once.

``validate`` looks at the features of the classes that play an ACORD-CS role (their names, the
attributes and operations their rules name), ``inspect`` at all of them, and the reader itself at
any feature that has something to say while the file is read: a stereotype (an ``xmi:Extension``
block, or an application whose ``base_*`` names it), a comment, a missing ``xmi:id``, a type or
association it could not resolve. A classifier whose features have none of that keeps them as
elements of the parsed file, and reads them (the same code, :meth:`xmi2._Reader._members`' handlers)
when its ``attributes``, ``ends`` or ``operations`` are first asked for, or when
:class:`~acordcs.xmi.uml.Elements` is asked for one of their ids. On the 2,000-class synthetic model of
``benchmarks/bench_validate.py``, 500 classes play a role: the features of the other 1,500 are never
built by ``validate``, nor the owned ends of the associations that join no two roles. An
association's owned ends wait the same way.
"""

from __future__ import annotations

from collections.abc import Callable

from lxml import etree

from acordcs.xmi.uml import Association, Classifier, UmlModel

FEATURE_TAGS = frozenset(("ownedAttribute", "ownedOperation", "ownedPort"))
END_TAGS = frozenset(("ownedEnd",))  # of an association


def application_bases(root: etree._Element) -> set[str]:
    """Every id a stereotype application names (``base_Class=".."``), where the tools write them:
    after the model at the document root (BOUML, Eclipse, MagicDraw, Visual Paradigm) or as the
    last children of ``uml:Model`` (Enterprise Architect)."""
    return set(
        root.xpath(
            "/*/*/@*[starts-with(local-name(), 'base_')] | /*/*/*/@*[starts-with(local-name(), 'base_')]",
            smart_strings=False,
        )
    )


class DeferredFeatures:
    """Decides, classifier by classifier, whether its features can wait (:meth:`offer`), and keeps
    what :meth:`check` needs to make them read at once after all when a reference is unresolved."""

    def __init__(
        self,
        model: UmlModel,
        xid: str,
        xidref: str,
        extension: str,
        bases: set[str],
        read: Callable[[Classifier | Association, list[etree._Element]], None],
    ) -> None:
        self.model = model
        self.XID, self.XIDREF, self.EXTENSION = xid, xidref, extension
        self.bases = bases
        self._read = read
        # (classifier or association, ids its features name)
        self.waiting: list[tuple[Classifier | Association, list[str]]] = []

    def offer(self, cls: Classifier | Association, features: list[etree._Element]) -> bool:
        """Whether ``cls``'s ``features`` (an association's: its owned ends) wait (True) or must
        be read now (False)."""
        refs: list[str] = []
        ids: list[str] = []
        types: dict[str, str | None] = {}
        plain = self._plain
        for feature in features:
            if not plain(feature, refs, ids, None if feature.tag == "ownedOperation" else types):
                return False
        cls.features_pending = lambda owner: self._read(owner, features)
        self.waiting.append((cls, refs))
        elements = self.model.elements
        pending = elements.pending
        for ident in ids:
            pending[ident] = cls
        elements.pending_types.update(types)
        return True

    def _plain(
        self,
        el: etree._Element,
        refs: list[str],
        ids: list[str],
        types: dict[str, str | None] | None,
    ) -> bool:
        """Whether feature (or parameter) ``el`` has nothing to say at reading time; its
        references go to ``refs``, its id to ``ids`` and, for a property (``types`` given), the id
        of its type to ``types``, as the reader would set it (the last ``<type xmi:idref>``, else
        the first id of ``type=``). Called for every feature of every classifier: kept lean."""
        get = el.get
        ident = get(self.XID)
        if ident is None or ident in self.bases:
            return False
        ids.append(ident)
        type_ref = None
        value = get("type")
        if value and (first := value.split(None, 1)):  # a blank one names nothing
            type_ref = first[0]
            refs.append(type_ref)
        value = get("association")
        if value and (first := value.split(None, 1)):
            refs.append(first[0])
        if len(el):
            xidref = self.XIDREF
            for child in el:
                tag = child.tag
                if tag == "type":
                    ref = child.get(xidref)
                    if ref:
                        refs.append(ref)
                        type_ref = ref
                elif tag == "ownedParameter":
                    if not self._plain(child, refs, ids, None):
                        return False
                elif tag.__class__ is not str:
                    continue  # an XML comment
                elif tag[0] == "{" or tag == "ownedComment":  # an xmi:Extension, a comment, ...
                    return False
        if types is not None:
            types[ident] = type_ref
        return True

    def check(self) -> None:
        """Read now the features of every classifier that names an element the reading did not
        build (a dangling id, a type only Enterprise Architect's extension defines): what the
        reader says about them must be said with the rest."""
        elements = self.model.elements
        built, waiting = dict.__contains__, elements.pending  # another's waiting feature: found
        for cls, refs in self.waiting:
            if cls.features_pending is not None and any(
                not built(elements, r) and r not in waiting for r in refs
            ):
                cls.read_pending()
