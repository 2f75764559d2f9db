"""The architecture of an application drawn from its descriptor as SVG, laid out by computation
(nothing placed by hand): each container a box, side by side in the descriptor's order; in it
three lanes, left to right, its monitors, its policy sets and its components, each element a box
as wide as its lane's longest name; a component's ports inside its box, a provided port's square
on its right edge, a required port's on its left. Lines: a monitor reads the components it
samples (grey, dashed, arrow at the monitor), feeds the policy sets it names (blue), a policy set
adapts components (orange), a connection joins a required port to a provided one (black, labelled
with its connector and its ports' kind).

Every element is a ``<g class="element">`` with its kind, name, qualified name and model id in
``data-`` attributes and a ``<title>``: the page shows them when it is clicked. The SVG is built
with ElementTree, so a name is text, never markup, whatever it holds.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from acordcs.descriptor.application import Application, Component, Connection

SVG_NS = "http://www.w3.org/2000/svg"
CHAR = 7.2  # px: the width of a character of the diagram's 12 px sans-serif, about
LINE = 16  # px between two lines of text
PAD = 10  # px inside a box
GAP = 18  # px between two boxes of a lane
LANE_GAP = 70  # px between two lanes (room for the lines between them)
CONTAINER_GAP = 90  # px between two containers
HEADER = 30  # px: a container's name
PORT = 8  # px: a port's square


@dataclass
class Box:
    """An element's box: where it is, what it is, and the lines of text inside it."""

    kind: str
    name: str
    qualified_name: str
    model_id: str
    lines: list[str]
    lane: int = 0  # the lane's number in the whole drawing, left to right
    x: float = 0.0
    y: float = 0.0
    width: float = 0.0
    ports: dict[str, tuple[float, float, str]] = field(default_factory=dict)  # name -> x, y, role

    @property
    def height(self) -> float:
        return PAD * 2 + LINE * len(self.lines)

    def text_width(self) -> float:
        return max(len(line) for line in self.lines) * CHAR + 2 * PAD + PORT


def _component_box(component: Component) -> Box:
    lines = [component.name] + [
        f"{'▸' if p.role == 'provided' else '◂'} {p.name} ({p.kind})" for p in component.ports
    ]
    return Box("component", component.name, component.qualified_name, component.id, lines)


def _layout(app: Application) -> tuple[list[dict], dict[str, Box], float, float]:
    """The containers' frames (name, qualified name, id, x, y, width, height), every element's
    box by name, and the drawing's width and height."""
    components = {c.name: c for c in app.components}
    monitors = {m.name: m for m in app.monitors}
    sets = {s.name: s for s in app.policy_sets}
    boxes: dict[str, Box] = {}
    frames: list[dict] = []
    x = 20.0
    height = 0.0
    for container in app.containers:
        lanes: list[list[Box]] = [[], [], []]
        for name in container.hosted("monitor"):
            m = monitors.get(name)
            if m is not None:
                rate = f"{m.acquisition}" + (f" {m.frequency:g} Hz" if m.frequency else "")
                lines = [name, rate, *(f"{p.name}: {p.type}" for p in m.properties)]
                lanes[0].append(Box("monitor", name, m.qualified_name, m.id, lines))
        for name in container.hosted("policy-set"):
            s = sets.get(name)
            if s is not None:
                lines = [name, f"{s.engine}, {s.trigger}", f"{len(s.rules())} rules"]
                lanes[1].append(Box("policy-set", name, s.qualified_name, s.id, lines))
        for name in container.hosted("component"):
            c = components.get(name)
            if c is not None:
                lanes[2].append(_component_box(c))
        lane_x = x + PAD
        bottom = 0.0
        for number, lane in enumerate(lanes):
            if not lane:
                continue
            width = max(max(b.text_width() for b in lane), 110.0)
            y = 20.0 + HEADER
            for box in lane:
                box.lane = 3 * len(frames) + number
                box.x, box.y, box.width = lane_x, y, width
                y += box.height + GAP
                boxes[box.name] = box
            bottom = max(bottom, y)
            lane_x += width + LANE_GAP
        inner = max(lane_x - LANE_GAP + PAD - x, len(container.name) * CHAR + 2 * PAD, 160.0)
        frame_height = max(bottom - 20.0, HEADER + 40.0)
        frames.append(
            {
                "name": container.name,
                "qname": container.qualified_name,
                "id": container.id,
                "host": container.host,
                "x": x,
                "y": 20.0,
                "width": inner,
                "height": frame_height,
            }
        )
        height = max(height, 20.0 + frame_height)
        x += inner + CONTAINER_GAP
    for name, box in boxes.items():
        component = components.get(name)
        if box.kind != "component" or component is None:
            continue
        for i, port in enumerate(component.ports):
            py = box.y + PAD + LINE * (i + 1) + LINE / 2
            px = box.x + box.width if port.role == "provided" else box.x
            box.ports[port.name] = (px, py, port.role)
    return frames, boxes, x - CONTAINER_GAP + 20, height


class Router:
    """Where the lines go: between boxes of two neighbouring lanes of a container, a curve from
    side to side; any other line (across a lane, across containers, within a lane) down from the
    boxes' bottoms into a channel below the containers, each line at a depth of its own, so that
    no line crosses a box."""

    def __init__(self, top: float) -> None:
        self.top = top
        self.depth = 0

    def route(self, a: Box, b: Box, a_at: tuple[float, float] | None = None,
              b_at: tuple[float, float] | None = None) -> tuple[str, float, float]:  # fmt: skip
        """The path from ``a`` to ``b`` (from ``a_at``, to ``b_at`` when given: a port), and
        where its label goes."""
        neighbours = a.lane // 3 == b.lane // 3 and abs(a.lane - b.lane) == 1
        if neighbours and a_at is None and b_at is None:
            start, end = _anchor(a, b), _anchor(b, a)
            return _curve(start, end), (start[0] + end[0]) / 2, (start[1] + end[1]) / 2 - 6
        self.depth += 1
        channel = self.top + 14 * self.depth
        jog = 8.0 + 5.0 * (self.depth % 6)  # out of the box into the lanes' gap, then down
        start, out_a = self._side(a, b, a_at)
        end, out_b = self._side(b, a, b_at)
        ax, bx = start[0] + out_a * jog, end[0] + out_b * jog
        d = (
            f"M{start[0]:.1f},{start[1]:.1f} H{ax:.1f} V{channel:.1f} H{bx:.1f} "
            f"V{end[1]:.1f} H{end[0]:.1f}"
        )
        return d, (ax + bx) / 2, channel - 3

    @staticmethod
    def _side(
        box: Box, other: Box, at: tuple[float, float] | None
    ) -> tuple[tuple[float, float], float]:
        """Where a line leaves ``box`` (``at``, a port on its edge, or the middle of the side
        facing ``other``), and which way (+1 right, -1 left)."""
        if at is not None:
            return at, (1.0 if at[0] >= box.x + box.width / 2 else -1.0)
        point = _anchor(box, other)
        return point, (1.0 if point[0] > box.x else -1.0)

    @property
    def bottom(self) -> float:
        return self.top + 14 * self.depth + 20


def _anchor(box: Box, toward: Box) -> tuple[float, float]:
    """The middle of ``box``'s side that faces ``toward``."""
    if toward.x + toward.width / 2 >= box.x + box.width / 2:
        return box.x + box.width, box.y + box.height / 2
    return box.x, box.y + box.height / 2


def _curve(a: tuple[float, float], b: tuple[float, float]) -> str:
    bend = max(40.0, abs(b[0] - a[0]) / 2)
    out = bend if b[0] >= a[0] else -bend
    return (
        f"M{a[0]:.1f},{a[1]:.1f} C{a[0] + out:.1f},{a[1]:.1f} "
        f"{b[0] - out:.1f},{b[1]:.1f} {b[0]:.1f},{b[1]:.1f}"
    )


def _port_end(box: Box, port: str) -> tuple[float, float] | None:
    found = box.ports.get(port)
    return (found[0], found[1]) if found else None


def architecture_svg(app: Application) -> str:
    """The diagram of ``app`` (see the module docstring), as an SVG document."""
    ET.register_namespace("", SVG_NS)
    frames, boxes, width, height = _layout(app)
    router = Router(height + 10)
    drawn: list[tuple[str, str, str, float, float, Connection | None]] = []  # kind, owner, d, x, y
    for m in app.monitors:
        mbox = boxes.get(m.name)
        for ref in m.sources if mbox else ():
            owner, _, port = ref.name.partition(".")  # a component, or a port: Component.Port
            source = boxes.get(owner)
            if source is not None:
                at = _port_end(source, port) if port else None
                drawn.append(("reads", m.name, *router.route(source, mbox, at), None))
        for ref in m.feeds if mbox else ():
            if ref.name in boxes:
                drawn.append(("feeds", m.name, *router.route(mbox, boxes[ref.name]), None))
    for s in app.policy_sets:
        sbox = boxes.get(s.name)
        for ref in s.adapts if sbox else ():
            if ref.name in boxes:
                drawn.append(("adapts", s.name, *router.route(sbox, boxes[ref.name]), None))
    for conn in app.connections:
        req, prov = boxes.get(conn.required.component), boxes.get(conn.provided.component)
        if req is not None and prov is not None:
            a_at = _port_end(req, conn.required.port) or (req.x, req.y + req.height / 2)
            b_at = _port_end(prov, conn.provided.port) or (prov.x, prov.y + prov.height / 2)
            drawn.append(("connection", conn.name, *router.route(req, prov, a_at, b_at), conn))
    height = router.bottom + 40
    svg = ET.Element(
        "svg",
        {
            "xmlns": SVG_NS,
            "viewBox": f"0 0 {width:.0f} {height:.0f}",
            "width": f"{width:.0f}",
            "height": f"{height:.0f}",
            "class": "architecture",
            "role": "img",
        },
    )
    ET.SubElement(svg, "title").text = f"The architecture of {app.name}"
    defs = ET.SubElement(svg, "defs")
    for kind in ("reads", "feeds", "adapts", "connection"):
        marker = ET.SubElement(
            defs,
            "marker",
            {
                "id": f"arrow-{kind}",
                "viewBox": "0 0 10 10",
                "refX": "9",
                "refY": "5",
                "markerWidth": "7",
                "markerHeight": "7",
                "orient": "auto-start-reverse",
            },
        )
        ET.SubElement(marker, "path", {"d": "M0,0 L10,5 L0,10 z", "class": f"head {kind}"})
    for frame in frames:
        group = _element_group(svg, "container", frame["name"], frame["qname"], frame["id"])
        ET.SubElement(
            group,
            "rect",
            {
                "x": f"{frame['x']:.1f}",
                "y": f"{frame['y']:.1f}",
                "width": f"{frame['width']:.1f}",
                "height": f"{frame['height']:.1f}",
                "rx": "8",
                "class": "frame",
            },
        )
        label = ET.SubElement(
            group,
            "text",
            {"x": f"{frame['x'] + PAD:.1f}", "y": f"{frame['y'] + 20:.1f}", "class": "frame-name"},
        )
        label.text = f"{frame['name']}  ({frame['host']})"
    lines = ET.SubElement(svg, "g", {"class": "lines"})
    labels: list[tuple[float, float, str, Connection]] = []
    for kind, owner, d, lx, ly, conn in drawn:
        if conn is None:
            path = ET.SubElement(
                lines,
                "path",
                {"d": d, "class": f"line {kind}", "marker-end": f"url(#arrow-{kind})"},
            )
            ET.SubElement(path, "title").text = f"{owner} {kind}"
            continue
        group = _element_group(lines, "connection", conn.name, conn.qualified_name, conn.id)
        ET.SubElement(group, "path", {"d": d, "class": "line connection",
                                      "marker-end": "url(#arrow-connection)"})  # fmt: skip
        kind_of = _port_kind(app, conn.required.component, conn.required.port)
        labels.append((lx, ly, f"{conn.name}: {conn.connector}, {kind_of or 'port'}", conn))
    for box in boxes.values():
        group = _element_group(svg, box.kind, box.name, box.qualified_name, box.model_id)
        ET.SubElement(
            group,
            "rect",
            {
                "x": f"{box.x:.1f}",
                "y": f"{box.y:.1f}",
                "width": f"{box.width:.1f}",
                "height": f"{box.height:.1f}",
                "rx": "4",
                "class": f"box {box.kind}",
            },
        )
        for i, text in enumerate(box.lines):
            t = ET.SubElement(
                group,
                "text",
                {
                    "x": f"{box.x + PAD + (PORT if i and box.ports else 0):.1f}",
                    "y": f"{box.y + PAD + LINE * i + 12:.1f}",
                    "class": "name" if i == 0 else "detail",
                },
            )
            t.text = text
        for port, (px, py, role) in box.ports.items():
            square = ET.SubElement(
                group,
                "rect",
                {
                    "x": f"{px - PORT / 2:.1f}",
                    "y": f"{py - PORT / 2:.1f}",
                    "width": str(PORT),
                    "height": str(PORT),
                    "class": f"port {role}",
                },
            )
            ET.SubElement(square, "title").text = f"{box.name}.{port} ({role})"
    for lx, ly, text, conn in labels:  # over the boxes and lines; a click on it shows the line's
        group = _element_group(svg, "connection", conn.name, conn.qualified_name, conn.id)
        label = ET.SubElement(group, "text", {"x": f"{lx:.1f}", "y": f"{ly:.1f}",
                                              "class": "line-label"})  # fmt: skip
        label.text = text
    _legend(svg, height - 20)
    return ET.tostring(svg, encoding="unicode")


def _port_kind(app: Application, component: str, port: str) -> str:
    for c in app.components:
        if c.name == component:
            found = c.port(port)
            return found.kind if found is not None else ""
    return ""


def _element_group(
    parent: ET.Element, kind: str, name: str, qname: str, model_id: str
) -> ET.Element:
    group = ET.SubElement(
        parent,
        "g",
        {
            "class": f"element {kind}",
            "data-kind": kind,
            "data-name": name,
            "data-qname": qname,
            "data-id": model_id,
            "tabindex": "0",
        },
    )
    ET.SubElement(group, "title").text = f"{kind} {qname} (id {model_id})"
    return group


def _line(parent: ET.Element, a: tuple[float, float], b: tuple[float, float], kind: str,
          owner: str) -> None:  # fmt: skip
    path = ET.SubElement(
        parent,
        "path",
        {"d": _curve(a, b), "class": f"line {kind}", "marker-end": f"url(#arrow-{kind})"},
    )
    ET.SubElement(path, "title").text = f"{owner} {kind}"


def _legend(svg: ET.Element, y: float) -> None:
    legend = ET.SubElement(svg, "g", {"class": "legend"})
    x = 20.0
    for kind, said in (
        ("reads", "a monitor reads"),
        ("feeds", "feeds a policy set"),
        ("adapts", "a policy set adapts"),
        ("connection", "a connection (required ▸ provided)"),
    ):
        _line(legend, (x, y), (x + 40, y), kind, "legend")
        t = ET.SubElement(legend, "text", {"x": f"{x + 48:.1f}", "y": f"{y + 4:.1f}",
                                           "class": "detail"})  # fmt: skip
        t.text = said
        x += 48 + len(said) * CHAR + 24
