"""Names that become identifiers in generated Python, Java and shell: valid, not reserved, unique."""

from __future__ import annotations

import keyword
from collections import defaultdict
from collections.abc import Iterator

from acordcs.diagnostics import Diagnostic, diagnostic
from acordcs.model.architecture import (
    COMPONENT,
    CONNECTION,
    CONTAINER,
    MONITOR,
    POLICY,
    POLICY_SET,
    PORT,
    VARIABLE,
    Role,
)
from acordcs.model.checks.check_context import Context
from acordcs.model.generated_names import (
    COMPONENT_API,
    IDENTIFIER,
    Named,
    file_name_problem,
    python_name_problem,
)
from acordcs.xmi.uml import Classifier, Element

# Java's reserved keywords and literals (JLS 3.9). Contextual keywords (module, open, to, ...) are
# legal member names; the restricted identifiers cannot name a type (JAVA_RESTRICTED_TYPE_NAMES).
JAVA_RESERVED = frozenset(
    """abstract assert boolean break byte case catch char class const continue default do double else
    enum extends final finally float for goto if implements import instanceof int interface long native
    new package private protected public return short static strictfp super switch synchronized this
    throw throws transient try void volatile while true false null _""".split()
)
JAVA_RESTRICTED_TYPE_NAMES = frozenset("var yield record sealed permits".split())
# Soft keywords (match, case, type) stay usable as Python identifiers, so they are not refused.
PYTHON_RESERVED = frozenset(keyword.kwlist)
RESERVED = JAVA_RESERVED | PYTHON_RESERVED
# Also refused: names of the rule language's keywords would make rules unreadable.
RULE_KEYWORDS = frozenset(["if", "then", "and", "or", "not", "is", "with", "very", "somewhat"])


def name_problem(name: str, *, type_name: bool = False) -> tuple[str, str] | None:
    """(code, reason) when ``name`` cannot become an identifier (a class name with ``type_name``)."""
    if (  # the common case first: a model has thousands of names
        IDENTIFIER.match(name)
        and name not in RESERVED
        and name.lower() not in RULE_KEYWORDS
        and not (type_name and name in JAVA_RESTRICTED_TYPE_NAMES)
    ):
        return None
    if not IDENTIFIER.match(name):
        return (
            "N601",
            f"{name!r} is not an identifier (letters, digits and _, not starting with a digit)",
        )
    langs = [
        lang
        for lang, reserved in (
            ("Python", name in PYTHON_RESERVED),
            ("Java", name in JAVA_RESERVED or (type_name and name in JAVA_RESTRICTED_TYPE_NAMES)),
            ("the rule language", name.lower() in RULE_KEYWORDS),
        )
        if reserved
    ]
    if langs:
        return "N602", f"{name!r} is a reserved word in {' and '.join(langs)}"
    return None


def _named(role: Role) -> Iterator[tuple[Element, str]]:
    yield role.element, "element"
    element = role.element
    if isinstance(element, Classifier) and role.kind != VARIABLE:
        for attr in element.attributes:
            yield attr, "attribute"
        for op in element.operations:
            yield op, "operation"
            for param in op.inputs:
                yield param, "parameter"


def identifiers(ctx: Context) -> Iterator[Diagnostic]:
    for role in ctx.arch.roles.values():
        if role.kind == VARIABLE:
            continue  # checked as an attribute of its owner
        for element, what in _named(role):
            problem = name_problem(element.name, type_name=what == "element")
            if problem:
                code, reason = problem
                yield ctx.diag(code, f"{what} name {reason}; rename it", element)


def unique_names(ctx: Context) -> Iterator[Diagnostic]:
    by_name: dict[str, list[Role]] = defaultdict(list)
    for role in ctx.arch.roles.values():
        if role.kind != VARIABLE:
            by_name[role.name].append(role)
    for name, roles in by_name.items():
        if len(roles) > 1 and name:
            others = ", ".join(f"{r.kind} {r.element.qualified_name()}" for r in roles)
            for role in roles[1:]:
                yield ctx.diag(
                    "N603",
                    f"{name!r} names {len(roles)} ACORD-CS elements ({others}); generated modules and "
                    "rule variables need each name once",
                    role,
                )
    for role in ctx.arch.roles.values():
        element = role.element
        if not isinstance(element, Classifier) or role.kind == VARIABLE:
            continue
        for members, what in ((element.attributes, "attribute"), (element.operations, "operation")):
            seen: dict[str, Element] = {}
            for member in members:
                if member.name in seen:
                    yield ctx.diag(
                        "N603",
                        f"{role.name} has two {what}s named {member.name!r} (generated Python has no "
                        "overloading); rename one",
                        member,
                    )
                seen.setdefault(member.name, member)
    for role in ctx.arch.of_kind(COMPONENT):
        element = role.element
        if not isinstance(element, Classifier):
            continue
        attributes = {a.name for a in element.attributes}
        for port in ctx.arch.related(role, "owns_port"):
            if port.name in attributes:
                yield ctx.diag(
                    "N603",
                    f"{role.name} has a port and an attribute both named {port.name!r} (the "
                    "generated Java class would have two fields of that name); rename one",
                    port,
                )


def component_api_names(ctx: Context) -> Iterator[Diagnostic]:
    for role in ctx.arch.of_kind(COMPONENT):
        element = role.element
        if not isinstance(element, Classifier):
            continue
        ports = {p.name for p in ctx.arch.related(role, "owns_port")}
        for op in element.operations:
            if op.name in COMPONENT_API:
                yield ctx.diag(
                    "N604",
                    f"operation {op.name!r} of {role.name} is also a member of every component "
                    f"(the runtime's CtxComponent and ComponentRef: {', '.join(sorted(COMPONENT_API))}); "
                    "the generated code would hide it: rename the operation",
                    op,
                )
            elif op.name.startswith("on_") and op.name[3:] in ports:
                yield ctx.diag(
                    "N605",
                    f"operation {op.name!r} of {role.name} becomes the handler of port "
                    f"{op.name[3:]!r}'s notifications and stream items (the runtime's convention); "
                    "rename it unless that is what it is for",
                    op,
                )


def case_insensitive_names(ctx: Context) -> Iterator[Diagnostic]:
    """Generated files and Java classes are named after elements: on a case-insensitive file
    system (macOS, Windows) two names that differ only in case are one file."""
    roles = [r for r in ctx.arch.roles.values() if r.kind not in (VARIABLE, PORT) and r.name]
    yield from _case_clashes(ctx, [(r.name, r.element) for r in roles], "ACORD-CS elements")
    for role in ctx.arch.of_kind(COMPONENT):
        element = role.element
        if isinstance(element, Classifier):
            ports = [(p.name, p.element) for p in ctx.arch.related(role, "owns_port")]
            yield from _case_clashes(ctx, ports, f"ports of {role.name}")
            members = [(m.name, m) for m in (*element.attributes, *element.operations)]
            yield from _case_clashes(ctx, members, f"members of {role.name}")


def _case_clashes(
    ctx: Context, named: list[tuple[str, Element]], what: str
) -> Iterator[Diagnostic]:
    by_folded: dict[str, dict[str, Element]] = defaultdict(dict)
    for name, element in named:
        by_folded[name.casefold()].setdefault(name, element)
    for spellings in by_folded.values():
        if len(spellings) > 1:
            names = sorted(spellings)
            for name in names[1:]:
                yield ctx.diag(
                    "N606",
                    f"{what} {', '.join(repr(n) for n in names)} differ only in letter case: "
                    "generated files and classes named after them would collide on a "
                    "case-insensitive file system; rename one",
                    spellings[name],
                )


_FILE_KIND = {
    CONTAINER: "container",
    COMPONENT: "component",
    CONNECTION: "connection",
    MONITOR: "monitor",
    POLICY_SET: "policy set",
    PORT: "port",
    POLICY: "policy",
}


def _generated(ctx: Context) -> Iterator[tuple[Named, Role | None]]:
    """The names the generated files and code take, with the role they belong to (None: the
    model's own name)."""
    model = ctx.uml.name or "application"  # what the descriptor names the application
    yield Named("model", model, "", model), None
    for role in ctx.arch.roles.values():
        kind = _FILE_KIND.get(role.kind)
        if kind is None:
            continue
        element = role.element
        yield Named(kind, role.name, role.id, element.qualified_name()), role
        if role.kind == COMPONENT and isinstance(element, Classifier):
            for op in element.operations:
                yield Named("operation", op.name, op.id, op.qualified_name()), role
                for param in op.inputs:
                    yield Named("parameter", param.name, param.id, op.qualified_name()), role


def generated_names(ctx: Context) -> Iterator[Diagnostic]:
    """What ``build`` refuses in names (G701, G703; :mod:`acordcs.model.generated_names`), found
    by ``validate`` too. Names that are no identifier, keywords and the component API's names are
    N601, N602 and N604 here: not reported twice."""
    for named, role in _generated(ctx):
        # a role's name that is no identifier is N601's: its file name is then no news
        as_file = file_name_problem(named) if role is None or IDENTIFIER.match(named.name) else None
        for problem in (as_file, python_name_problem(named, identifiers=False)):
            if problem is None:
                continue
            if role is None:
                yield diagnostic(
                    problem.code, problem.message, file=ctx.uml.file, element=named.qualified
                )
            else:
                where = ctx.uml.elements.get(named.id) or role.element
                yield ctx.diag(problem.code, problem.message, where)


CHECKS = (identifiers, unique_names, component_api_names, case_insensitive_names, generated_names)
"""This module's checks, in the order they run."""
