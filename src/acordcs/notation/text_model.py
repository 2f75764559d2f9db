"""An outline read as the neutral UML view (:mod:`acordcs.xmi.uml`), the one every XMI reader
makes, so that everything after reading (the architecture, the checks, the descriptor, the build)
is the same for the text as for XMI.

What the text says becomes what Papyrus writes for it: an element a Class with the stereotype
applied (a port inside an element a UML Port of it), an attribute a Property, a relation a
Dependency from the element stating it to the element it names. An id the text does not give
is derived from the qualified name (:func:`acordcs.notation.outline.derived_id`). Rules and terms
keep where each of their lines is, so that a finding about a rule points at the rule's line and
column in the text.
"""

from __future__ import annotations

from acordcs.diagnostics import diagnostic, suggestion
from acordcs.notation import outline as o
from acordcs.profile import PROFILE_NAME
from acordcs.xmi.uml import (
    Classifier,
    Dependency,
    Element,
    Operation,
    Package,
    Parameter,
    Property,
    StereotypeApplication,
    UmlModel,
)

DIALECT = "acord-text"
EXPORTER = "the text notation"  # what inspect shows as the file's exporter


def uml_of(outline: o.Outline, path: str) -> UmlModel:
    """The UML view of ``outline``, read from the file ``path``."""
    return _Builder(outline, path).build()


class _Builder:
    def __init__(self, outline: o.Outline, path: str) -> None:
        self.outline = outline
        self.model = UmlModel(
            file=path, dialect=DIALECT, name=outline.name, exporter=EXPORTER, tool="acordcs"
        )
        self.ids: dict[str, int] = {}  # id -> line where first given
        self.paths: dict[tuple[str, ...], str] = {}  # qualified names of elements -> id
        self.pending: list[tuple[o.Relation, str, tuple[str, ...], Element | None]] = []

    def build(self) -> UmlModel:
        out = self.outline
        root = Package(
            self.identify(out.id, o.derived_id(("model",)), out.place),
            "Model",
            out.name,
            out.place.line,
        )
        root.comments = _comment(out.doc)
        self.model.elements[root.id] = root
        for item in out.items:
            self.item(item, root, ())
        for relation, source, path, owner in self.pending:
            self.relation(relation, source, path, owner)
        return self.model

    # ------------------------------------------------------------------------------- ids
    def identify(self, given: str | None, derived: str, place: o.Place) -> str:
        ident = given if given is not None else derived
        if ident in self.ids:
            how = "given" if given is not None else "derived from its qualified name"
            self.model.diagnostics.append(
                diagnostic(
                    "M104",
                    f"id {ident!r} ({how}) is also the id of the element at line "
                    f'{self.ids[ident]}: give one of them another id (id "..." after its name)',
                    file=self.model.file,
                    line=place.line,
                    column=place.column,
                    xmi_id=ident,
                )
            )
            ident = f"{ident}#{place.line}.{place.column}"
        self.ids[ident] = place.line
        return ident

    # ------------------------------------------------------------------------------- structure
    def item(self, item: o.Package | o.Element, owner: Element, path: tuple[str, ...]) -> None:
        path = (*path, item.name)
        if isinstance(item, o.Package):
            ident = self.identify(item.id, o.derived_id(path), item.place)
            pkg = Package(ident, "Package", item.name)
            pkg.line, pkg.owner, pkg.comments = item.place.line, owner, _comment(item.doc)
            self.model.elements[pkg.id] = pkg
            self.model.packages.append(pkg)
            if isinstance(owner, Package):
                owner.members.append(pkg)
            for sub in item.items:
                self.item(sub, pkg, path)
            return
        self.element(item, owner, path)

    def element(self, item: o.Element, owner: Element, path: tuple[str, ...]) -> None:
        inside = isinstance(owner, Classifier | Property)
        derived = o.member_id(owner.id, item.name) if inside else o.derived_id(path)
        ident = self.identify(item.id, derived, item.place)
        line = item.place.line
        if item.keyword == "port" and isinstance(owner, Classifier):
            port = Property(ident, "Port", item.name, line, owner, aggregation="composite")
            owner.ports.append(port)
            element: Element = port
        else:
            cls = Classifier(ident, "Class", item.name, line, owner)
            self.model.classifiers.append(cls)
            if isinstance(owner, Classifier):
                owner.nested.append(cls)
            elif isinstance(owner, Package):
                owner.members.append(cls)
            element = cls
        element.comments = _comment(item.doc)
        self.model.elements[ident] = element
        self.paths[path] = ident
        app = self.apply(item.stereotype, ident, item.place, item.tags)
        for tag, block in item.rules:
            offset, places = 0, []
            for text, place in block.lines:  # one rule a line, each where the text has it
                places.append((offset, place.line, place.column))
                offset += len(text) + 1
            app.tags[tag] = "\n".join(text for text, _ in block.lines)
            app.tag_lines[tag] = block.lines[0][1].line if block.lines else block.place.line
            app.tag_places[tag] = tuple(places)
        if isinstance(element, Classifier):
            for attr in item.attributes:
                self.attribute(attr, element)
            for op in item.operations:
                self.operation(op, element)
        for relation in item.relations:
            self.pending.append((relation, ident, path, owner))
        for nested in item.nested:
            self.element(nested, element, (*path, nested.name))

    def apply(
        self, stereotype: str, base: str, place: o.Place, tags: list[o.Tag]
    ) -> StereotypeApplication:
        app = StereotypeApplication(
            profile=PROFILE_NAME, name=stereotype, base=base, line=place.line, id=f"{base}.app"
        )
        app.places.add("text")
        for tag in tags:
            app.tags[tag.name] = tag.value
            app.tag_lines[tag.name] = tag.place.line
            app.tag_columns[tag.name] = tag.place.column
        self.model.applications[(base, f"{PROFILE_NAME}:{stereotype}")] = app
        return app

    def attribute(self, attr: o.Attribute, owner: Classifier) -> None:
        ident = self.identify(attr.id, o.member_id(owner.id, attr.name), attr.place)
        prop = Property(ident, "Property", attr.name, attr.place.line, owner)
        prop.type_name, prop.default, prop.comments = attr.type, attr.default, _comment(attr.doc)
        owner.attributes.append(prop)
        self.model.elements[ident] = prop
        var = attr.variable
        if var is not None:
            app = self.apply(o.VARIABLE, ident, var.place, var.tags)
            if var.id is not None:
                app.id = var.id
            if var.terms is not None:
                value, places = terms_value(var.terms.lines)
                app.tags[o.TERMS_TAG] = value
                app.tag_lines[o.TERMS_TAG] = var.terms.place.line
                app.tag_places[o.TERMS_TAG] = places

    def operation(self, op: o.Operation, owner: Classifier) -> None:
        ident = self.identify(op.id, o.member_id(owner.id, op.name), op.place)
        operation = Operation(ident, "Operation", op.name, op.place.line, owner)
        operation.comments = _comment(op.doc)
        for p in op.parameters:
            p_id = self.identify(p.id, o.member_id(ident, p.name), p.place)
            param = Parameter(p_id, "Parameter", p.name, p.place.line, operation)
            param.type_name, param.direction = p.type, p.direction
            operation.parameters.append(param)
            self.model.elements[p_id] = param
        if op.returns is not None:
            ret = Parameter(f"{ident}.return", "Parameter", "return", op.place.line, operation)
            ret.type_name, ret.direction = op.returns, "return"
            operation.parameters.append(ret)
        owner.operations.append(operation)
        self.model.elements[ident] = operation

    # ------------------------------------------------------------------------------- relations
    def resolve(self, wanted: tuple[str, ...]) -> tuple[str | None, list[tuple[str, ...]]]:
        """The id of the element ``wanted`` names (its qualified name, or the end of one that
        only it has), and the candidates when it names several."""
        found = self.paths.get(wanted)
        if found is not None:
            return found, []
        n = len(wanted)
        matches = [path for path in self.paths if path[-n:] == wanted]
        if len(matches) == 1:
            return self.paths[matches[0]], []
        return None, matches

    def relation(
        self, relation: o.Relation, source: str, path: tuple[str, ...], owner: Element | None
    ) -> None:
        while owner is not None and not isinstance(owner, Package):
            owner = owner.owner  # a dependency belongs to the package of its client
        for wanted, place in relation.targets:
            target, candidates = self.resolve(wanted)
            shown = ".".join(wanted)
            if target is None:
                if candidates:
                    which = ", ".join("::".join(c) for c in candidates[:5])
                    why = f"names {len(candidates)} elements ({which}): write more of its qualified name"
                else:
                    names = [p[-1] for p in self.paths]
                    why = f"names no element of the model{suggestion(wanted[-1], names)}"
                self.model.diagnostics.append(
                    diagnostic(
                        "M103",
                        f"{relation.keyword} {shown!r} {why}",
                        file=self.model.file,
                        line=place.line,
                        column=place.column,
                        element="::".join(path),
                    )
                )
                continue
            derived = o.derived_id((relation.keyword, *path, "to", *wanted))
            ident = self.identify(None, derived, place).replace("#", ".")
            dep = Dependency(ident, "Dependency", f"{relation.keyword}{wanted[-1]}", place.line)
            dep.owner, dep.clients, dep.suppliers = owner, [source], [target]
            self.model.dependencies.append(dep)
            self.model.elements[ident] = dep


def terms_value(
    lines: list[tuple[str, o.Place]],
) -> tuple[str, tuple[tuple[int, int, int], ...]]:
    """A terms block's lines as the tag's value, the terms joined by ``; ``, and where each term
    is in the text (:attr:`acordcs.xmi.uml.StereotypeApplication.tag_places`)."""
    parts: list[str] = []
    places: list[tuple[int, int, int]] = []
    offset = 0
    for text, place in lines:
        at = 0
        for piece in text.split(";"):
            term = piece.strip()
            if term:
                column = place.column + at + (len(piece) - len(piece.lstrip()))
                places.append((offset, place.line, column))
                parts.append(term)
                offset += len(term) + 2
            at += len(piece) + 1
    return "; ".join(parts), tuple(places)


def _comment(doc: list[str]) -> list[str]:
    return ["\n".join(doc)] if doc else []
