"""A synthetic large ACORD-CS model in BOUML XMI, for benchmarks and tests.

``synthetic_model(classes=2000, seed=1)`` builds a model of ``classes`` classes, about a quarter
of them with ACORD-CS stereotypes (containers, components, ports, connections, monitors, 100
policy sets of 12 rules each, their policies), that follows the README's section on modelling and should
validate clean: every rule variable is an attribute in the set's scope, every term is defined,
every component, monitor and set is deployed, every monitor feeds a set. The rest are plain
classes with attributes, operations, comments, associations and generalizations, as in a real
large model (about 4.5 MB for 2,000 classes).


CLI: ``python -m tools.bouml_writer.synthetic --classes 2000 --out /tmp/syn.xmi [--seed 1]``.
"""

from __future__ import annotations

import argparse
import random
import sys
from pathlib import Path

from tools.bouml_writer.bouml import BoumlWriter, ctx, ctx_var
from tools.bouml_writer.elements import Cls, Pkg

WORDS = (
    "account",
    "order",
    "invoice",
    "customer",
    "product",
    "stock",
    "shipment",
    "carrier",
    "route",
    "sensor",
    "reading",
    "alarm",
    "session",
    "user",
    "role",
    "grant",
    "ledger",
    "entry",
    "batch",
    "job",
    "queue",
    "worker",
    "cache",
    "index",
    "report",
    "chart",
    "schedule",
    "slot",
    "booking",
    "room",
    "device",
    "firmware",
    "config",
    "profile",
    "address",
    "contact",
    "payment",
    "refund",
    "coupon",
    "tariff",
    "meter",
    "zone",
    "floor",
    "badge",
    "visit",
    "ticket",
    "issue",
    "comment",
    "review",
    "rating",
    "channel",
    "topic",
)
TYPES = ("int", "double", "bool", "string", "long", "float", "char", "list<string>", "varchar(40)")
LOAD_TERMS = (
    "idle := trape 0 0 10 30; light := trian 10 35 60; busy := trian 40 65 90;"
    " full := trape 70 90 100 100"
)
RATE_TERMS = "low := trape 0 0 20 50; normal := trian 20 50 80; high := trape 50 80 100 100"
LEVEL_TERMS = "small := trape 0 0 2 4; medium := trian 2 5 8; large := trape 6 8 10 10"
LEVELS = ("small", "medium", "large")


def _camel(words: list[str]) -> str:
    return "".join(w.capitalize() for w in words)


def synthetic_model(classes: int = 2000, seed: int = 1, policy_sets: int = 100) -> Pkg:
    """The synthetic model as a package tree (deterministic for ``seed``)."""
    rng = random.Random(seed)
    root = Pkg("Synthetic")
    ctxpkg = root.package("ContextAware")
    n_ctx = classes // 4
    n_sets = min(policy_sets, max(1, n_ctx // 5))
    n_containers = max(1, min(10, n_ctx // 50))
    # quarter budget: containers + sets + policies + monitors + components + ports + connections
    rest = max(0, n_ctx - n_containers - 3 * n_sets)
    n_components = max(n_sets, rest // 2) if rest else n_sets
    n_pairs = max(0, (n_ctx - n_containers - 3 * n_sets - n_components) // 3)

    dep_pkg = ctxpkg.package("Deployment")
    containers = [
        ctx(dep_pkg.cls(f"Node{i}"), "CtxContainer", host=f"node{i}.example.org")
        for i in range(n_containers)
    ]

    comp_pkg = ctxpkg.package("Components")
    components = []
    for i in range(n_components):
        c = ctx(comp_pkg.cls(f"Service{i}"), "CtxComponent", language="python")
        ctx_var(c, "level", "double", 0, 10, LEVEL_TERMS, default="5")
        c.attr("enabled", "bool", default="true")
        c.attr("threshold", "int", default="3")
        c.op("reset")
        c.op("configure", [("key", "string"), ("value", "string")], "bool")
        c.comment = f"Synthetic component {i}."
        components.append(c)
        comp_pkg.associate(containers[i % n_containers], c, f"service{i}", aggregation="composite")

    ports: list[Cls] = []
    for j in range(n_pairs):
        kind = ("synchronous", "asynchronous", "stream")[j % 3]
        prov_c = components[(2 * j) % n_components]
        req_c = components[(2 * j + 1) % n_components]
        p = ctx(comp_pkg.cls(f"Port{j}P"), "CtxPort", kind=kind, role="provided")
        r = ctx(comp_pkg.cls(f"Port{j}R"), "CtxPort", kind=kind, role="required")
        p.attr("calls", "long")
        conn = ctx(comp_pkg.cls(f"Link{j}"), "CtxPortConnection", connector="remote")
        conn.attr("latency", "double", default="0")
        conn.attr("bandwidth", "double", default="0")
        comp_pkg.associate(prov_c, p, f"port{j}p", aggregation="composite")
        comp_pkg.associate(req_c, r, f"port{j}r", aggregation="composite")
        comp_pkg.associate(conn, p, "provider")
        comp_pkg.associate(conn, r, "consumer")
        ports += [p, r]

    adapt_pkg = ctxpkg.package("Adaptation")
    for i in range(n_sets):
        crisp = i % 10 == 9
        comp = components[i % n_components]
        mon = ctx(
            adapt_pkg.cls(f"Monitor{i}"),
            "CtxMonitor",
            frequency=float(rng.choice((0.5, 1, 2, 5, 10))),
        )
        ctx_var(mon, "load", "double", 0, 100, LOAD_TERMS)
        ctx_var(mon, "rate", "double", 0, 100, RATE_TERMS)
        mon.attr("samples", "int", default="0")
        if crisp:
            pset = ctx(
                adapt_pkg.cls(f"PolicySet{i}"), "CtxPolicySet", engine="clips", trigger="event"
            )
            rules = []
            for k in range(12):
                lim = 10 + 7 * k
                rules.append(
                    f"r{k}: if Monitor{i}.load > {lim} and Service{i % n_components}.level < "
                    f"{1 + k % 9} then Service{i % n_components}.level = "
                    f"Service{i % n_components}.level + 1"
                    + (f" and Service{i % n_components}.reset()" if k % 4 == 0 else "")
                )
        else:
            pset = ctx(
                adapt_pkg.cls(f"PolicySet{i}"),
                "CtxPolicySet",
                engine="fuzzy",
                trigger="periodic",
                frequency=1.0,
            )
            rules = []
            k = 0
            for load in ("idle", "light", "busy", "full"):
                for rate in ("low", "normal", "high"):
                    out = LEVELS[min(2, (k * 7 + i) % 3)]
                    hedge = "very " if k % 5 == 0 else ""
                    rules.append(
                        f"r{k}: if Monitor{i}.load is {hedge}{load} and rate is {rate} "
                        f"then Service{i % n_components}.level is {out}"
                    )
                    k += 1
        pol = ctx(adapt_pkg.cls(f"Policy{i}"), "CtxPolicy", Rule="\n".join(rules))
        pol.comment = f"Twelve rules of policy set {i}."
        adapt_pkg.associate(pset, pol, "policy", aggregation="composite")
        adapt_pkg.associate(mon, pset, "feeds")
        adapt_pkg.depend(pset, comp)
        adapt_pkg.associate(containers[i % n_containers], mon, f"monitor{i}")
        adapt_pkg.associate(containers[i % n_containers], pset, f"policySet{i}")
        adapt_pkg.depend(mon, components[(i + 1) % n_components])

    made = sum(len(p.classes) for p in _walk(root))
    plain_total = max(0, classes - made)
    domain = root.package("Domain")
    plain: list[Cls] = []
    pkgs = [domain.package(f"module{m}") for m in range(max(1, plain_total // 100))]
    for n in range(plain_total):
        pkg = pkgs[n % len(pkgs)]
        w = rng.sample(WORDS, 2)
        c = pkg.cls(f"{_camel(w)}{n}")
        if n % 7 == 0:
            c.stereotype = rng.choice(("entity", "boundary", "control"))
        for a in range(rng.randint(1, 4)):
            c.attr(
                f"{rng.choice(WORDS)}{a}",
                rng.choice(TYPES),
                visibility=rng.choice(("private", "protected", "public")),
                default=str(rng.randint(0, 99)) if a % 3 == 0 else None,
                is_static=a == 3 and n % 5 == 0,
            )
        for o in range(rng.randint(1, 2)):
            params = [
                (f"{rng.choice(WORDS)}{p}", rng.choice(TYPES)) for p in range(rng.randint(0, 2))
            ]
            c.op(f"do{_camel([rng.choice(WORDS)])}{o}", params, rng.choice((*TYPES, None)))
        if n % 3 == 0:
            c.comment = (
                f"The {w[0]} {w[1]} of the domain model.\n"
                f"Synthetic class {n}, generated with seed {seed}; no ACORD-CS stereotype."
            )
        if plain and n % 9 == 0:
            c.general = rng.choice(plain[-50:])
        if plain and n % 2 == 0:
            other = rng.choice(plain[-200:])
            pkg.associate(
                c,
                other,
                f"{w[1]}s",
                back=f"{w[0]}" if n % 2 else None,
                aggregation=rng.choice(("none", "shared", "composite")),
                multiplicity=rng.choice(("*", "1", "0..1", "1..*", None, None)),
            )
        if plain and n % 11 == 0:
            pkg.depend(c, rng.choice(plain))
        plain.append(c)
    return root


def _walk(pkg: Pkg):
    yield pkg
    for p in pkg.packages:
        yield from _walk(p)


def generate(classes: int = 2000, seed: int = 1) -> str:
    """The synthetic model as BOUML XMI text."""
    root = synthetic_model(classes, seed)
    return BoumlWriter("Synthetic", gxmi_path="/home/modeller/synthetic.xmi").write(root)


def write(path: str | Path, classes: int = 2000, seed: int = 1) -> Path:
    """Write the synthetic model to ``path`` (UTF-8) and return the path."""
    path = Path(path)
    path.write_text(generate(classes, seed), encoding="utf-8")
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--classes", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    if args.classes < 20:
        ap.error("--classes must be at least 20")
    path = write(args.out, args.classes, args.seed)
    print(f"{path}: {path.stat().st_size} bytes, {args.classes} classes", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
