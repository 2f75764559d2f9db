"""The model in the text notation's forms (what ``acordcs-gen convert`` writes), as
:mod:`acordcs.model.ecore_builder` gives it as the metamodel's instance: the outline of a model any
reader read, what the text notation says of it (:func:`outline_of`), and the model in each form
through it (:func:`to_form`: the text, the XMI Papyrus opens, the XMI BOUML reads), so that each
form says the same model.

Only what the profile says is kept: the elements with an ACORD-CS stereotype (with their tags,
attributes, operations, ports and the relations the architecture found between them), and the
packages (or other elements) they sit in, so that every qualified name stays the same. An id is
written only where it is not the one the text would derive.
"""

from __future__ import annotations

from acordcs.errors import AcordError
from acordcs.model.architecture import VARIABLE, Architecture, Role
from acordcs.notation import outline as o
from acordcs.notation.text_form import text_of
from acordcs.notation.text_model import uml_of
from acordcs.notation.xmi_forms import bouml_form, papyrus_form
from acordcs.rules.parser import split_rules
from acordcs.xmi.uml import Classifier, Element
from acordcs.xmi.uml import Operation as UmlOperation
from acordcs.xmi.uml import Property as UmlProperty


def outline_of(arch: Architecture) -> o.Outline:
    """The outline of the model ``arch`` interprets."""
    return _Outliner(arch).outline()


def path_of(element: Element) -> tuple[str, ...]:
    """The names of ``element`` and its owners, the model's excepted: its qualified name."""
    names: list[str] = []
    node: Element | None = element
    while node is not None and node.kind != "Model":
        names.append(node.name)
        node = node.owner
    return tuple(reversed(names))


class _Outliner:
    def __init__(self, arch: Architecture) -> None:
        self.arch = arch
        self.uml = arch.uml
        self.roles = {i: r for i, r in arch.roles.items() if r.kind != VARIABLE}
        self.made: dict[str, o.Element | o.Package] = {}
        self.paths = {path_of(r.element): i for i, r in self.roles.items()}

    def outline(self) -> o.Outline:
        out = o.Outline(name=self.uml.name)
        model = next((e for e in self.uml.elements.values() if e.kind == "Model"), None)
        if model is not None:
            out.doc = _doc(model)
            out.id = None if model.id == o.derived_id(("model",)) else model.id
        for role in self.roles.values():
            self.place(role.element, out)
        return out

    def place(self, element: Element, out: o.Outline) -> o.Element | o.Package:
        """The outline item of ``element`` (made once), inside the item of its owner."""
        made = self.made.get(element.id)
        if made is not None:
            return made
        role = self.roles.get(element.id)
        item = self.element(role) if role is not None else self.package(element)
        self.made[element.id] = item
        owner = element.owner
        if owner is None or owner.kind == "Model":
            out.items.append(item)
        else:
            parent = self.place(owner, out)
            if isinstance(parent, o.Element) and isinstance(item, o.Element):
                parent.nested.append(item)
            elif isinstance(parent, o.Package):
                parent.items.append(item)
            else:  # a package inside an element: written beside it, its names kept
                out.items.append(item)
        return item

    def ident(self, element: Element) -> str | None:
        """``element``'s id, or None when it is the one the text derives."""
        owner = element.owner
        if owner is not None and (owner.kind == "Operation" or owner.id in self.arch.roles):
            derived = o.member_id(owner.id, element.name)
        else:
            derived = o.derived_id(path_of(element))
        return None if element.id == derived else element.id

    def package(self, element: Element) -> o.Package:
        return o.Package(element.name, doc=_doc(element), id=self.ident(element))

    def element(self, role: Role) -> o.Element:
        el = role.element
        item = o.Element(o.KEYWORDS[role.kind], el.name, doc=_doc(el), id=self.ident(el))
        declared = role.stereotype
        for name, value in role.tags.items():
            tag = declared.tag(name)
            if tag is not None and tag.syntax == "rules":
                lines = [(line.text, o.Place()) for line in split_rules(value)]
                for text, _ in lines:
                    _writable(text, f"rule {text!r} of tag {name!r}", el)
                item.rules.append((name, o.Block(lines)))
            elif value.strip():
                item.tags.append(o.Tag(name, value.strip()))
        if isinstance(el, Classifier):
            item.attributes = [self.attribute(p) for p in el.attributes]
            item.operations = [self.operation(op) for op in el.operations]
        for relation, keyword in o.RELATION_KEYWORDS.items():
            targets = [t for t in self.arch.related(role, relation) if t.element.owner is not el]
            if targets:
                item.relations.append(
                    o.Relation(keyword, [(self.short(t), o.Place()) for t in targets])
                )
        return item

    def short(self, target: Role) -> tuple[str, ...]:
        """The shortest end of ``target``'s qualified name that no other element's ends with."""
        full = path_of(target.element)
        for n in range(1, len(full) + 1):
            end = full[-n:]
            if end in self.paths and self.paths[end] != target.id:
                continue  # another element's whole qualified name
            if sum(1 for p in self.paths if p[-n:] == end) == 1:
                return end
        return full

    def attribute(self, prop: UmlProperty) -> o.Attribute:
        attr = o.Attribute(
            prop.name, prop.type_name, prop.default, doc=_doc(prop), id=self.ident(prop)
        )
        var = self.arch.variable(prop)
        if var is not None:
            attr.variable = variable = o.Variable()
            for name, value in var.tags.items():
                if name == o.TERMS_TAG:
                    # a term over lines reads as one (the rule language flattens them)
                    pieces = (" ".join(t.split()) for t in value.split(";"))
                    terms = [t for t in pieces if t]
                    for term in terms:
                        _writable(term, f"term {term!r}", prop)
                    variable.terms = o.Block([(t, o.Place()) for t in terms])
                elif value.strip():
                    variable.tags.append(o.Tag(name, value.strip()))
        return attr

    def operation(self, op: UmlOperation) -> o.Operation:
        return o.Operation(
            op.name,
            [o.Parameter(p.name, p.type_name, p.direction, self.ident(p)) for p in op.inputs],
            op.return_type,
            _doc(op),
            self.ident(op),
        )


class ConversionError(AcordError):
    """What the model says that the text cannot say: nothing is written."""


def _writable(line: str, what: str, element: Element) -> None:
    """A line of a rules or terms block is its text as written: one that starts as the block's
    end or a comment would read as something else."""
    if line.startswith(("}", "/", "#")):
        raise ConversionError(
            f"{what} starts with {line[0]!r}, which a line of a block in the text notation "
            "cannot start with (it is not a rule or a term either): correct it in the model",
            element=f"{element.qualified_name()} ({element.id})",
        )


def _doc(element: Element) -> list[str]:
    text = "\n".join(c for c in element.comments if c)
    return text.split("\n") if text else []


FORMS = ("text", "papyrus", "bouml")
SUFFIXES = {".acord": "text", ".uml": "papyrus", ".xmi": "bouml"}


def to_form(arch: Architecture, form: str) -> bytes:
    """The model ``arch`` interprets, in ``form`` (one of :data:`FORMS`)."""
    outline = outline_of(arch)
    if form == "text":
        return text_of(outline).encode("utf-8")
    uml = uml_of(outline, arch.uml.file)
    return papyrus_form(uml) if form == "papyrus" else bouml_form(uml)
