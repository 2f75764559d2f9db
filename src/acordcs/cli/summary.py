"""What ``acordcs-gen inspect`` reports: UML counts and the ACORD-CS reading of a model."""

from __future__ import annotations

from acordcs.diagnostics import printable
from acordcs.model.architecture import COMPONENT, CONTAINER, POLICY_SET, Architecture
from acordcs.model.queries import policy_rules
from acordcs.model.reading import ModelReading
from acordcs.profile import profile
from acordcs.typed_values import parse_boolean


def summarize(reading: ModelReading) -> dict:
    uml = reading.uml
    data = {
        "file": reading.file,
        "dialect": uml.dialect,
        "exporter": uml.exporter,
        "model": uml.name,
        **uml.counts(),
        "acordcs": _acordcs(reading.architecture) if reading.architecture else {},
        "diagnostics": len(reading.diagnostics),
    }
    return data


def _acordcs(arch: Architecture) -> dict:
    elements = {
        s.name: sorted(r.name for r in arch.of_kind(s.name))
        for s in profile()
        if arch.of_kind(s.name)
    }
    deployment = {
        _key(c, arch): sorted(r.name for r in arch.related(c, "hosts"))
        for c in arch.of_kind(CONTAINER)
    }
    policy_sets = {}
    for ps in arch.of_kind(POLICY_SET):
        policy_sets[_key(ps, arch)] = {
            "engine": ps.tag("engine"),
            "trigger": ps.tag("trigger"),
            "policies": sorted(p.name for p in arch.policies(ps)),
            "rules": sum(len(policy_rules(p)) for p in arch.policies(ps)),
            "adapts": sorted(r.name for r in arch.related(ps, "adapts")),
            "fed_by": sorted(r.name for r in arch.related_to(ps, "feeds")),
        }
    persistent = sorted(
        _key(c, arch) for c in arch.of_kind(COMPONENT) if parse_boolean(c.tag("persistent") or "")
    )
    return {
        "elements": elements,
        "deployment": deployment,
        "policy_sets": policy_sets,
        "persistent": persistent,
    }


def _key(role, arch: Architecture) -> str:
    """The role's name, with its id when another role of its kind has the same name (shown, not lost)."""
    same = [r for r in arch.of_kind(role.kind) if r.name == role.name]
    return role.name if len(same) == 1 else f"{role.name} ({role.id})"


def summary_text(data: dict) -> str:
    """:func:`summarize`'s result as the lines ``inspect`` prints."""
    lines = [
        f"{data['file']}: {data['dialect']} ({data['exporter'] or 'unknown exporter'}), model {data['model']!r}"
    ]
    kinds = ", ".join(f"{n} {k}" for k, n in data["classifiers"].items()) or "none"
    lines.append(f"  classifiers: {kinds}")
    for key in (
        "attributes",
        "operations",
        "associations",
        "generalizations",
        "dependencies",
        "packages",
    ):
        lines.append(f"  {key}: {data[key]}")
    apps = ", ".join(f"{k} x{n}" for k, n in data["stereotype_applications"].items()) or "none"
    lines.append(f"  stereotype applications: {apps}")
    acordcs = data["acordcs"]
    if not acordcs["elements"]:
        lines.append(
            "  ACORD-CS: none (no element has an ACORDCS stereotype; validate says more: T313)"
        )
    else:
        lines.append("  ACORD-CS:")
    for kind, names in acordcs["elements"].items():
        lines.append(f"    {kind} ({len(names)}): {', '.join(names)}")
    for container, hosted in acordcs["deployment"].items():
        lines.append(f"    container {container} hosts: {', '.join(hosted) or 'nothing'}")
    for ps, info in acordcs["policy_sets"].items():
        lines.append(
            f"    policy set {ps}: engine {info['engine']}, {info['rules']} rules, adapts "
            f"{', '.join(info['adapts']) or 'nothing'}, fed by {', '.join(info['fed_by']) or 'nothing'}"
        )
    if acordcs.get("persistent"):
        lines.append(
            f"    persistent (state kept across restarts): {', '.join(acordcs['persistent'])}"
        )
    if data["diagnostics"]:
        lines.append(f"  reader diagnostics: {data['diagnostics']}")
    return "\n".join(printable(line) for line in lines)
