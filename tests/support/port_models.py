"""Small ACORD-CS applications written two ways, in the forms the tools save them: as Papyrus saves
a model applying the profile (Eclipse UML2, written here with lxml) and as BOUML exports one
(:mod:`tools.bouml_writer`), with their ports modelled as ``uml:Port`` owned by the component or as
``<<CtxPort>>`` classes related to it (by an association or a dependency).

One application, :class:`Spec`, says what the variants vary: one container or two (on two hosts),
the connection's connector, the port form and the policy set's engine, and the mistakes validate
must refuse (:attr:`Spec.refused_with`). What it holds: a component
``Fan`` (a linguistic variable ``speed``, an operation ``setSpeed``) providing ``FanPort``, a
component ``Panel`` requiring ``PanelPort``, a connection ``FanLink`` joining them, a monitor
``AirSensor`` (``co2``) feeding a policy set ``Airflow`` that adapts ``Fan``; with two containers,
``Panel`` runs in the second one.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

from lxml import etree

from tools.bouml_writer.bouml import BoumlWriter, ctx, ctx_var, stereotype_tags
from tools.bouml_writer.elements import Attr, Cls, Dep, Pkg

PORT_FORMS = ("uml-port", "class-association", "class-dependency")
FILE_FORMS = ("papyrus", "bouml")
CONNECTORS = ("inprocess", "remote", "shaped")
ENGINES = ("fuzzy", "clips")

SPEED_TERMS = "slow := trape 0 0 20 40; medium := trian 30 50 70; fast := trape 60 80 100 100"
CO2_TERMS = "low := trape 0 0 600 900; high := trape 700 1200 2000 2000"
RULES = {
    "fuzzy": "airy: if co2 is high then Fan.speed is fast\ncalm: if co2 is low then Fan.speed is slow",
    "clips": "airy: if AirSensor.co2 > 1000 then Fan.setSpeed(100)\n"
    "calm: if AirSensor.co2 < 600 then Fan.speed = 20",
}


@dataclass(frozen=True)
class Spec:
    file_form: str = "papyrus"
    port_form: str = "uml-port"
    two_containers: bool = False
    connector: str = "inprocess"
    engine: str = "fuzzy"
    # a property of Panel named like its port (the Java target's fields would collide)
    property_named_like_port: bool = False
    # PanelPort owned by no component (a uml:Port of a plain class Housing; a class related to none)
    unowned_port: bool = False

    @property
    def id(self) -> str:
        where = "two-containers" if self.two_containers else "one-container"
        extra = "-property-named-like-port" if self.property_named_like_port else ""
        extra += "-unowned-port" if self.unowned_port else ""
        return f"{self.file_form}-{self.port_form}-{where}-{self.connector}-{self.engine}{extra}"

    @property
    def refused_with(self) -> str | None:
        """The code validate must refuse it with, None when it must validate and build."""
        if self.unowned_port:
            return "A517"
        if self.property_named_like_port:
            return "N603"
        if self.two_containers and self.connector == "inprocess":
            return "A516"
        return None

    @property
    def suffix(self) -> str:
        return ".uml" if self.file_form == "papyrus" else ".xmi"


def variants() -> list[Spec]:
    """Every file form x port form x deployment x connector, each engine once in each file and port
    form; and the variants validate must refuse."""
    found = []
    for n, (file_form, port_form, two, connector) in enumerate(
        itertools.product(FILE_FORMS, PORT_FORMS, (False, True), CONNECTORS)
    ):
        found.append(Spec(file_form, port_form, two, connector, ENGINES[n % 2]))
    for file_form, port_form in itertools.product(FILE_FORMS, PORT_FORMS):
        found.append(Spec(file_form, port_form, property_named_like_port=True))
        found.append(Spec(file_form, port_form, unowned_port=True))
    return found


def document(spec: Spec) -> bytes:
    """The model file of ``spec``, in its file form."""
    if spec.file_form == "papyrus":
        return papyrus(spec)
    return bouml(spec).encode("utf-8")


# ------------------------------------------------------------------------------------- Papyrus
XMI = "http://www.omg.org/spec/XMI/20131001"
UML = "http://www.eclipse.org/uml2/5.0.0/UML"
ECORE = "http://www.eclipse.org/emf/2002/Ecore"
XSI = "http://www.w3.org/2001/XMLSchema-instance"
ACORDCS = "http:///schemas/ACORDCS/1"
PRIMITIVES = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml"
PROFILE_FILE = "ACORDCS.profile.uml"


def _x(name: str) -> str:
    return f"{{{XMI}}}{name}"


class _Papyrus:
    """Writes a model as Papyrus saves one: ``xmi:XMI`` holding ``uml:Model`` then the stereotype
    applications (``<ACORDCS:CtxPort base_Port=".."/>``), references as id attributes, primitive
    types as ``pathmap://`` hrefs, relations as ``uml:Dependency`` or ``uml:Association`` with
    its ends owned, the profile applied by reference to ``ACORDCS.profile.uml``."""

    def __init__(self, name: str) -> None:
        nsmap = {"xmi": XMI, "xsi": XSI, "ACORDCS": ACORDCS, "ecore": ECORE, "uml": UML}
        self.root = etree.Element(_x("XMI"), nsmap=nsmap)
        self.root.set(_x("version"), "20131001")
        self.root.set(
            f"{{{XSI}}}schemaLocation", f"{ACORDCS} {PROFILE_FILE}#_ACORDCS.definition.EPackage"
        )
        self.model = etree.SubElement(self.root, f"{{{UML}}}Model")
        self.model.set(_x("id"), "_model")
        self.model.set("name", name)
        imported = etree.SubElement(self.model, "packageImport")
        self._typed(imported, "uml:PackageImport", "_model.primitives")
        etree.SubElement(
            imported, "importedPackage", {_x("type"): "uml:Model", "href": f"{PRIMITIVES}#_0"}
        )
        self.applications: list[tuple[str, str, str, dict[str, str]]] = []

    @staticmethod
    def _typed(el: etree._Element, xtype: str, ident: str) -> etree._Element:
        el.set(_x("type"), xtype)
        el.set(_x("id"), ident)
        return el

    def cls(self, name: str, stereotype: str | None = None, **tags: str) -> etree._Element:
        el = self._typed(etree.SubElement(self.model, "packagedElement"), "uml:Class", f"_{name}")
        el.set("name", name)
        if stereotype:
            self.apply(stereotype, "Class", el.get(_x("id")), **tags)
        return el

    def attribute(
        self, owner: etree._Element, name: str, type_name: str, default: str | None = None
    ):
        ident = f"{owner.get(_x('id'))}.{name}"
        el = self._typed(etree.SubElement(owner, "ownedAttribute"), "uml:Property", ident)
        el.set("name", name)
        etree.SubElement(
            el, "type", {_x("type"): "uml:PrimitiveType", "href": f"{PRIMITIVES}#{type_name}"}
        )
        if default is not None:
            literal = etree.SubElement(el, "defaultValue")
            self._typed(literal, "uml:LiteralReal", f"{ident}.default").set("value", default)
        return el

    def port(self, owner: etree._Element, name: str, **tags: str) -> etree._Element:
        ident = f"{owner.get(_x('id'))}.port.{name}"
        el = self._typed(etree.SubElement(owner, "ownedAttribute"), "uml:Port", ident)
        el.set("name", name)
        el.set("aggregation", "composite")
        self.apply("CtxPort", "Port", ident, **tags)
        return el

    def operation(self, owner: etree._Element, name: str, *params: tuple[str, str]) -> None:
        ident = f"{owner.get(_x('id'))}.{name}"
        op = etree.SubElement(owner, "ownedOperation", {_x("id"): ident, "name": name})
        for pname, ptype in params:
            p = etree.SubElement(
                op, "ownedParameter", {_x("id"): f"{ident}.{pname}", "name": pname}
            )
            etree.SubElement(
                p, "type", {_x("type"): "uml:PrimitiveType", "href": f"{PRIMITIVES}#{ptype}"}
            )

    def depend(self, client: etree._Element, supplier: etree._Element, name: str) -> None:
        el = self._typed(
            etree.SubElement(self.model, "packagedElement"), "uml:Dependency", f"_dep.{name}"
        )
        el.set("name", name)
        el.set("client", client.get(_x("id")))
        el.set("supplier", supplier.get(_x("id")))

    def associate(self, a: etree._Element, b: etree._Element, name: str) -> None:
        ident = f"_assoc.{name}"
        el = self._typed(etree.SubElement(self.model, "packagedElement"), "uml:Association", ident)
        el.set("name", name)
        el.set("memberEnd", f"{ident}.a {ident}.b")
        for end, typed in (("a", a), ("b", b)):
            owned = self._typed(etree.SubElement(el, "ownedEnd"), "uml:Property", f"{ident}.{end}")
            owned.set("name", typed.get("name").lower())
            owned.set("type", typed.get(_x("id")))
            owned.set("association", ident)

    def apply(self, stereotype: str, metaclass: str, base: str, **tags: str) -> None:
        self.applications.append((stereotype, metaclass, base, tags))

    def variable(self, prop: etree._Element, lo: str, hi: str, terms: str) -> None:
        self.apply("CtxVariable", "Property", prop.get(_x("id")), min=lo, max=hi, terms=terms)

    def write(self) -> bytes:
        application = etree.SubElement(self.model, "profileApplication")
        self._typed(application, "uml:ProfileApplication", "_model.ACORDCS")
        note = etree.SubElement(application, "eAnnotations")
        self._typed(note, "ecore:EAnnotation", "_model.ACORDCS.annotation")
        note.set("source", "http://www.eclipse.org/uml2/2.0.0/UML")
        etree.SubElement(
            note,
            "references",
            {_x("type"): "ecore:EPackage", "href": f"{PROFILE_FILE}#_ACORDCS.definition.EPackage"},
        )
        etree.SubElement(
            application,
            "appliedProfile",
            {_x("type"): "uml:Profile", "href": f"{PROFILE_FILE}#_ACORDCS"},
        )
        for stereotype, metaclass, base, tags in self.applications:
            el = etree.SubElement(self.root, f"{{{ACORDCS}}}{stereotype}")
            el.set(_x("id"), f"{base}.app")
            el.set(f"base_{metaclass}", base)
            for key, value in tags.items():
                el.set(key, value)
        etree.indent(self.root, space="  ")
        return etree.tostring(self.root, xml_declaration=True, encoding="UTF-8") + b"\n"


def papyrus(spec: Spec) -> bytes:
    w = _Papyrus("Ventilation")
    plant = w.cls("Plant", "CtxContainer", host="plant.local")
    office = w.cls("Office", "CtxContainer", host="office.local") if spec.two_containers else plant
    fan = w.cls("Fan", "CtxComponent")
    speed = w.attribute(fan, "speed", "Real", "20.0")
    w.variable(speed, "0", "100", SPEED_TERMS)
    w.operation(fan, "setSpeed", ("level", "Real"))
    panel = w.cls("Panel", "CtxComponent")
    if spec.property_named_like_port:
        w.attribute(panel, "PanelPort", "Real")
    ports = []
    housing = w.cls("Housing") if spec.unowned_port else panel
    for owner, name, role in ((fan, "FanPort", "provided"), (housing, "PanelPort", "required")):
        if spec.port_form == "uml-port":
            ports.append(w.port(owner, name, kind="synchronous", role=role))
            continue
        port = w.cls(name, "CtxPort", kind="synchronous", role=role)
        if spec.unowned_port and owner is housing:
            pass
        elif spec.port_form == "class-association":
            w.associate(owner, port, f"owns{name}")
        else:
            w.depend(owner, port, f"owns{name}")
        ports.append(port)
    link = w.cls("FanLink", "CtxPortConnection", connector=spec.connector)
    for port in ports:
        w.depend(link, port, f"joins{port.get('name')}")
    sensor = w.cls("AirSensor", "CtxMonitor", frequency="1")
    co2 = w.attribute(sensor, "co2", "Real")
    w.variable(co2, "0", "2000", CO2_TERMS)
    airflow = w.cls("Airflow", "CtxPolicySet", engine=spec.engine, trigger="event")
    rules = w.cls("AirRules", "CtxPolicy", Rule=RULES[spec.engine])
    for hosted, where in ((fan, plant), (panel, office), (sensor, plant), (airflow, plant)):
        w.depend(where, hosted, f"hosts{hosted.get('name')}")
    w.depend(airflow, rules, "containsAirRules")
    w.depend(airflow, fan, "adaptsFan")
    w.depend(sensor, airflow, "feedsAirflow")
    return w.write()


# --------------------------------------------------------------------------------------- BOUML
class _BoumlWithPorts(BoumlWriter):
    """BOUML's exporter writing a class's ports too: ``<ownedAttribute xmi:type="uml:Port">``
    after its attributes, with the stereotype in an ``xmi:Extension`` block inside and applied
    after the model, as for any element (see ``shared/reference/bouml-xmi.md``)."""

    def __init__(self, *args, **kw) -> None:
        super().__init__(*args, **kw)
        self.ports: dict[int, list[Attr]] = {}  # id(class) -> its ports

    def port(self, owner: Cls, name: str, **tags: str) -> Attr:
        port = Attr(name, "", visibility="public", stereotype="ACORDCS:CtxPort")
        port.tags = stereotype_tags("CtxPort", **tags)
        self.ports.setdefault(id(owner), []).append(port)
        return port

    def _assign(self, pkg: Pkg, root: bool = False) -> None:
        super()._assign(pkg, root)
        for c in pkg.classes:
            for port in self.ports.get(id(c), ()):
                port.id = self.new_id(1)

    def _class(self, c: Cls, ind: str) -> list[str]:
        lines = super()._class(c, ind)
        extra = []
        for port in self.ports.get(id(c), ()):
            extra.append(
                f'{ind}\t<ownedAttribute xmi:type="uml:Port" name="{port.name}" xmi:id="{port.id}"'
                f' visibility="{port.visibility}" aggregation="composite">'
            )
            extra += self._extension(port.stereotype, port.tags, ind + "\t\t")
            self._apply(port.id, port.stereotype, port.tags)
            extra.append(f"{ind}\t</ownedAttribute>")
        return lines[:-1] + extra + lines[-1:]


def bouml(spec: Spec) -> str:
    writer = _BoumlWithPorts("Ventilation")
    pkg = Pkg("Ventilation")
    plant = ctx(pkg.cls("Plant"), "CtxContainer", host="plant.local")
    office = (
        ctx(pkg.cls("Office"), "CtxContainer", host="office.local")
        if spec.two_containers
        else plant
    )
    fan = ctx(pkg.cls("Fan"), "CtxComponent")
    ctx_var(fan, "speed", "double", 0, 100, SPEED_TERMS, default="20.0")
    fan.op("setSpeed", [("level", "double")])
    panel = ctx(pkg.cls("Panel"), "CtxComponent")
    if spec.property_named_like_port:
        panel.attr("PanelPort", "double")
    ports: list = []
    housing = pkg.cls("Housing") if spec.unowned_port else panel
    for owner, name, role in ((fan, "FanPort", "provided"), (housing, "PanelPort", "required")):
        if spec.port_form == "uml-port":
            ports.append(writer.port(owner, name, kind="synchronous", role=role))
            continue
        port = ctx(pkg.cls(name), "CtxPort", kind="synchronous", role=role)
        if spec.unowned_port and owner is housing:
            pass
        elif spec.port_form == "class-association":
            pkg.associate(owner, port, name[0].lower() + name[1:])
        else:
            pkg.depend(owner, port)
        ports.append(port)
    link = ctx(pkg.cls("FanLink"), "CtxPortConnection", connector=spec.connector)
    for port in ports:
        pkg.deps.append(Dep(link, port))  # a uml:Port is a dependency's supplier by its id
    sensor = ctx(pkg.cls("AirSensor"), "CtxMonitor", frequency=1.0)
    ctx_var(sensor, "co2", "double", 0, 2000, CO2_TERMS)
    airflow = ctx(pkg.cls("Airflow"), "CtxPolicySet", engine=spec.engine, trigger="event")
    rules = ctx(pkg.cls("AirRules"), "CtxPolicy", Rule=RULES[spec.engine])
    for hosted, where in ((fan, plant), (panel, office), (sensor, plant), (airflow, plant)):
        pkg.depend(where, hosted)
    pkg.depend(airflow, rules)
    pkg.depend(airflow, fan)
    pkg.depend(sensor, airflow)
    return writer.write(pkg)


__all__ = ["CONNECTORS", "ENGINES", "FILE_FORMS", "PORT_FORMS", "Spec", "document", "variants"]
