"""The subscription index: which subscriptions does a document match, and with which nodes?

YFilter's idea on a small scale. Subscriptions are first selected by publisher (a dict lookup), then
grouped by location path: every distinct path is evaluated once per document, however many
subscriptions share it (plain ``/a/b/c`` paths by one walk of the document along a trie of all such
paths, others by one compiled XPath each). The predicates of the recognised forms are kept per
(path, value) entry as sorted thresholds, so ``. > c`` for all c is one bisection, and
``= c`` one dict lookup. Anything else is a compiled lxml XPath evaluated per document (outside the
provider's lock: :meth:`SubscriptionIndex.fallbacks` then :meth:`SubscriptionIndex.evaluate`),
timed, and suspended after repeated overruns within a window. The results are, by construction and by test, the node lists lxml
returns when evaluating each subscription on its own.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any

from lxml import etree

from acordcs.runtime.context.entries import ValueEntry
from acordcs.runtime.context.xpathexpr import IndexedForm
from acordcs.runtime.context.xpathnum import xpath_number

log = logging.getLogger(__name__)

Entry = Any  # the index stores any hashable subscription object


class Fallback:
    """A subscription matched by its own compiled XPath: the expression, and when it overran.

    An lxml ``XPath`` object evaluates one document at a time (it holds a lock while it runs), so
    one compiled object shared by the publishing threads would make a publisher whose small
    document matches wait for another publisher's large one. Each thread gets its own copy."""

    __slots__ = ("compiled", "per_thread", "strikes", "suspended")

    def __init__(self, compiled: Callable[[etree._ElementTree], object]) -> None:
        self.compiled = compiled
        self.per_thread = threading.local()
        self.strikes: deque[float] = deque()  # monotonic times of recent overruns
        self.suspended = False

    def evaluator(self) -> Callable[[etree._ElementTree], object]:
        """This thread's compiled expression (a copy of ``compiled`` when it is an lxml XPath)."""
        own = getattr(self.per_thread, "compiled", None)
        if own is None:
            compiled = self.compiled
            own = etree.XPath(compiled.path) if isinstance(compiled, etree.XPath) else compiled
            self.per_thread.compiled = own
        return own


class _PublisherIndex:
    __slots__ = ("by_path", "entries", "everything", "fallback")

    def __init__(self) -> None:
        self.entries: dict[tuple, ValueEntry] = {}  # (path, value kind, value name) -> entry
        self.by_path: dict[str, list[tuple]] = {}  # path -> [(value kind, value name, entry)]
        self.fallback: dict[Entry, Fallback] = {}  # in subscription order
        self.everything: dict[Entry, None] = {}  # ordered set

    def empty(self) -> bool:
        return not (self.entries or self.fallback or self.everything)


class _Trie:
    __slots__ = ("children", "count", "path")

    def __init__(self) -> None:
        self.children: dict[str, _Trie] = {}
        self.path: str | None = None
        self.count = 0


def _string_value(node: object) -> str:
    if isinstance(node, str):
        return str(node)
    if len(node) == 0:  # type: ignore[arg-type]
        return node.text or ""  # type: ignore[attr-defined]
    return "".join(node.itertext())  # type: ignore[attr-defined]


class SubscriptionIndex:
    """Not thread-safe: the provider serialises ``add``/``remove``/``match`` under its lock."""

    def __init__(
        self, max_eval_seconds: float = 0.05, max_strikes: int = 3, strike_window: float = 60.0
    ) -> None:
        self._by_publisher: dict[str | None, _PublisherIndex] = {}
        self._trie = _Trie()
        self._paths: dict[str, list] = {}  # non-trie path -> [compiled XPath, refcount]
        # Publisher selection by one lookup: a publisher with subscriptions of its own gets a view
        # merging them with the publisher-independent ones, so a document visits each (path, value)
        # entry once. Costs memory: the shared subscriptions are repeated in every view.
        self._views: dict[str, _PublisherIndex] = {}
        self._forms: dict[Entry, IndexedForm] = {}
        self._max_eval = max_eval_seconds
        self._max_strikes = max_strikes
        self._strike_window = strike_window
        self.on_suspend: Callable[[Entry, float], None] | None = None

    def __len__(self) -> int:
        return sum(
            len(p.fallback) + len(p.everything) + sum(len(e.members) for e in p.entries.values())
            for p in self._by_publisher.values()
        )

    # -- maintenance ------------------------------------------------------------------------------
    def add(
        self,
        sub: Entry,
        publisher: str | None,
        form: IndexedForm | None,
        compiled: Callable[[etree._ElementTree], object] | None,
    ) -> None:
        """Index ``sub``; ``form`` None with ``compiled`` None means "every document"."""
        pindex = self._by_publisher.setdefault(publisher, _PublisherIndex())
        if form is None:
            if compiled is not None:
                pindex.fallback[sub] = Fallback(compiled)
            else:
                pindex.everything[sub] = None
            return
        _add_entry(pindex, sub, form)
        self._ref_path(form, +1)
        self._forms[sub] = form
        if publisher is None:
            for view in self._views.values():
                _add_entry(view, sub, form)
        else:
            view = self._views.get(publisher)
            if view is None:
                view = self._views[publisher] = self._new_view()
            _add_entry(view, sub, form)

    def _new_view(self) -> _PublisherIndex:
        view = _PublisherIndex()
        shared = self._by_publisher.get(None)
        if shared is not None:
            for entry in shared.entries.values():
                for member in entry.members:
                    _add_entry(view, member, self._forms[member])
        return view

    def remove(self, sub: Entry, publisher: str | None, form: IndexedForm | None) -> None:
        pindex = self._by_publisher.get(publisher)
        if pindex is None:
            return
        if form is None:
            pindex.fallback.pop(sub, None)
            pindex.everything.pop(sub, None)
        else:
            if not _remove_entry(pindex, sub, form):
                return
            self._ref_path(form, -1)
            del self._forms[sub]
            if publisher is None:
                for view in self._views.values():
                    _remove_entry(view, sub, form)
            else:
                _remove_entry(self._views[publisher], sub, form)
                if not pindex.entries:  # no subscription of its own left: the shared index will do
                    del self._views[publisher]
        if pindex.empty():
            del self._by_publisher[publisher]

    def _ref_path(self, form: IndexedForm, delta: int) -> None:
        if form.child_steps is None:
            entry = self._paths.get(form.path)
            if entry is None:
                entry = self._paths[form.path] = [etree.XPath(form.path), 0]
            entry[1] += delta
            if entry[1] == 0:
                del self._paths[form.path]
            return
        node, trail = self._trie, []
        for step in form.child_steps:
            trail.append((node, step))
            node = node.children.setdefault(step, _Trie())
        node.path = form.path
        node.count += delta
        if node.count == 0:
            node.path = None
            for parent, step in reversed(trail):  # prune branches no path uses any more
                child = parent.children[step]
                if child.children or child.path is not None:
                    break
                del parent.children[step]

    # -- matching ---------------------------------------------------------------------------------
    def _walk(self, root: etree._Element) -> dict[str, list]:
        found: dict[str, list] = {}
        top = self._trie.children.get(root.tag)
        if top is None:
            return found
        if top.path is not None:
            found[top.path] = [root]
        # preorder (children pushed in reverse): all nodes of one path have the same depth, so
        # visiting parents in document order appends each path's nodes in document order
        stack = [(root, top)]
        while stack:
            elem, node = stack.pop()
            children = node.children
            deeper = []
            for child in elem:
                sub = children.get(child.tag)
                if sub is None:
                    continue
                if sub.path is not None:
                    found.setdefault(sub.path, []).append(child)
                if sub.children:
                    deeper.append((child, sub))
            if deeper:
                deeper.reverse()
                stack.extend(deeper)
        return found

    def match(self, tree: etree._ElementTree, publisher: str) -> list[tuple[list, list, object]]:
        """Chunks ``(subscriptions, selected nodes, raw XPath result)``: each matching subscription
        appears in exactly one chunk, with its nodes. Chunks spare a tuple per matching subscription
        when many share a result (every ``> c`` subscription below the value gets the same node)."""
        results = self.match_indexed(tree, publisher)
        results += self.evaluate(self.fallbacks(publisher), tree)
        return results

    def fallbacks(self, publisher: str) -> list[tuple[Entry, Fallback]]:
        """The subscriptions matched by their own XPath on ``publisher``'s documents: taken under
        the provider's lock, evaluated (:meth:`evaluate`) without it."""
        found: list[tuple[Entry, Fallback]] = []
        for key in (None, publisher):
            pindex = self._by_publisher.get(key)
            if pindex is not None and pindex.fallback:
                found += pindex.fallback.items()
        return found

    def match_indexed(
        self, tree: etree._ElementTree, publisher: str
    ) -> list[tuple[list, list, object]]:
        """:meth:`match` without the fallback subscriptions (the cheap part)."""
        root = tree.getroot()
        results: list[tuple[list, list, object]] = []
        walked: dict[str, list] | None = None
        evaluated: dict[str, list] = {}
        indexed = self._views.get(publisher) or self._by_publisher.get(None)
        if indexed is not None:
            for path, entries in indexed.by_path.items():
                nodes = evaluated.get(path)
                if nodes is None:
                    compiled = self._paths.get(path)
                    if compiled is None:
                        if walked is None:
                            walked = self._walk(root)
                        nodes = walked.get(path, [])
                    else:
                        nodes = compiled[0](tree)
                    evaluated[path] = nodes
                if nodes:
                    for value_kind, value_name, entry in entries:
                        _match_entry(value_kind, value_name, entry, nodes, results)
        for key in (None, publisher):
            pindex = self._by_publisher.get(key)
            if pindex is not None and pindex.everything:
                whole = [root]
                results.append((list(pindex.everything), whole, whole))
        return results

    def evaluate(
        self, fallbacks: list[tuple[Entry, Fallback]], tree: etree._ElementTree
    ) -> list[tuple[list, list, object]]:
        """Evaluate :meth:`fallbacks` on ``tree``; needs no lock (lxml releases the GIL while it
        evaluates, so other publishers go on meanwhile). An evaluation using more than
        ``max_eval_seconds`` of CPU time is a strike (CPU time: what the expression costs, not
        how busy the host is); ``max_strikes`` strikes within ``strike_window`` seconds suspend
        the subscription (:meth:`suspend`, then ``on_suspend``)."""
        results: list[tuple[list, list, object]] = []
        for sub, state in fallbacks:
            if state.suspended:
                continue
            started = time.thread_time()
            try:
                value = state.evaluator()(tree)
            except etree.XPathError as err:
                log.warning("subscription %s: XPath evaluation failed: %s", sub, err)
                continue
            elapsed = time.thread_time() - started
            suspends = elapsed > self._max_eval and self._strike(state, time.monotonic())
            if suspends and self.on_suspend is not None:
                self.on_suspend(sub, elapsed)
            if isinstance(value, list):
                if value:
                    results.append(([sub], value, value))
            # XPath boolean(): true, a number neither 0 nor NaN, a non-empty string
            elif value and value == value:
                results.append(([sub], [], value))
        return results

    def _strike(self, state: Fallback, now: float) -> bool:
        """Count an overrun; True when it suspends (once). Strikes older than the window decay."""
        strikes = state.strikes
        strikes.append(now)
        while strikes and strikes[0] < now - self._strike_window:
            strikes.popleft()
        if len(strikes) < self._max_strikes or state.suspended:
            return False
        state.suspended = True
        return True

    def suspend(self, sub: Entry, publisher: str | None) -> None:
        """Stop evaluating ``sub`` (after :meth:`evaluate` suspended it), under the provider's lock."""
        pindex = self._by_publisher.get(publisher)
        if pindex is not None:
            pindex.fallback.pop(sub, None)
            if pindex.empty():
                del self._by_publisher[publisher]


def _add_entry(pindex: _PublisherIndex, sub: Entry, form: IndexedForm) -> None:
    key = (form.path, form.value_kind, form.value_name)
    entry = pindex.entries.get(key)
    if entry is None:
        entry = pindex.entries[key] = ValueEntry()
        pindex.by_path.setdefault(form.path, []).append((form.value_kind, form.value_name, entry))
    entry.add(sub, form.op, form.const_kind, form.const)


def _remove_entry(pindex: _PublisherIndex, sub: Entry, form: IndexedForm) -> bool:
    key = (form.path, form.value_kind, form.value_name)
    entry = pindex.entries.get(key)
    if entry is None or sub not in entry.members:
        return False
    entry.remove(sub)
    if not entry.members:
        del pindex.entries[key]
        pindex.by_path[form.path].remove((form.value_kind, form.value_name, entry))
        if not pindex.by_path[form.path]:
            del pindex.by_path[form.path]
    return True


def _match_entry(
    kind: str | None, name: str | None, entry: ValueEntry, nodes: list, results: list
) -> None:
    # each (path, value) entry of a view is visited once per document: nothing to cache
    if kind is None:
        if entry.exists:
            results.append((entry.exists, nodes, nodes))
        return
    numeric = entry.numeric
    if len(nodes) == 1:
        strings = _strings(nodes[0], kind, name)
        if strings:
            numbers = [xpath_number(s) for s in strings] if numeric else None
            matched = entry.matching(numbers, strings)
            if matched:
                results.append((matched, nodes, nodes))
        return
    per_sub: dict[Entry, list] = {}
    for node in nodes:
        strings = _strings(node, kind, name)
        if strings:
            numbers = [xpath_number(s) for s in strings] if numeric else None
            for sub in entry.matching(numbers, strings):
                per_sub.setdefault(sub, []).append(node)
    results.extend(([sub], selected, selected) for sub, selected in per_sub.items())


def _strings(node: object, kind: str, name: str | None) -> list[str]:
    """String values of the node itself, of its children called ``name``, or of its attribute."""
    if isinstance(node, str):  # an attribute selected by the path has no children or attributes
        return [str(node)] if kind == "self" else []
    if kind == "self":
        return [(node.text or "") if len(node) == 0 else "".join(node.itertext())]  # type: ignore[arg-type]
    if kind == "attr":
        attr = node.get(name)  # type: ignore[attr-defined]
        return [] if attr is None else [attr]
    return [_string_value(child) for child in node.iterchildren(name)]  # type: ignore[attr-defined]
