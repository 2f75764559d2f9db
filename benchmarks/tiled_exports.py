"""Large exports of other tools for the validate benchmark, tiled from the real small ones.

No 3.5 MB Umbrello export or 2 MB MagicDraw export is stored (only the real files of
``../shared/reference/xmi-other-tools``, 21 KB and 305 KB). :func:`tiled` repeats a real export's model
content, every id renamed per copy (and every reference to it), until the file reaches a size: the
dialect's shape stays the tool's own (Umbrello's diagram widgets restating class ids in
``XMI.extension``, MagicDraw's extension blocks and root applications), only more of it.
"""

from __future__ import annotations

import re
from pathlib import Path

from lxml import etree

_ATTRIBUTE = re.compile(r"""(\s[\w:.]+\s*=\s*)(["'])([^"'<>]*)\2""")


def _ids(root: etree._Element) -> set[str]:
    return {v for el in root.iter(etree.Element) for k, v in el.items() if k.endswith("id")}


def _renamed(text: str, ids: set[str], suffix: str) -> str:
    def one(match: re.Match) -> str:
        value = match.group(3)
        if value in ids:
            return f"{match.group(1)}{match.group(2)}{value}{suffix}{match.group(2)}"
        if value.startswith("#") and value[1:] in ids:  # MagicDraw's href="#id"
            return f"{match.group(1)}{match.group(2)}{value}{suffix}{match.group(2)}"
        parts = value.split()
        if len(parts) > 1 and all(p in ids for p in parts):
            renamed = " ".join(p + suffix for p in parts)
            return f"{match.group(1)}{match.group(2)}{renamed}{match.group(2)}"
        return match.group(0)

    return _ATTRIBUTE.sub(one, text)


def tiled(source: Path, target_bytes: int) -> bytes:
    """``source`` with its model content repeated (ids renamed) up to about ``target_bytes``."""
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    root = etree.parse(str(source), parser).getroot()
    ids = _ids(root)
    if root.tag == "XMI":  # XMI 1.x (Umbrello): the top model's owned elements
        holder = root.find("XMI.content/*/{*}Namespace.ownedElement")
        blocks = list(holder)
    else:  # XMI 2.x (MagicDraw): the model's members and the applications after it
        model = next(c for c in root if c.tag.endswith("}Model"))
        holder = model
        blocks = [c for c in model if etree.QName(c).localname == "packagedElement"]
    copy_text = "".join(etree.tostring(b, encoding="unicode") for b in blocks)
    if root.tag != "XMI":
        inside = {i for b in blocks for i in _ids(b)}  # applications to copied elements only
        apps = [c for c in root if any(k.startswith("base_") and v in inside for k, v in c.items())]
        apps_text = "".join(etree.tostring(a, encoding="unicode") for a in apps)
    whole = etree.tostring(root, encoding="unicode")
    per_copy = len(copy_text.encode()) + (0 if root.tag == "XMI" else len(apps_text.encode()))
    copies = max(1, (target_bytes - len(whole.encode())) // per_copy)
    extra = "".join(_renamed(copy_text, ids, f"_t{k}") for k in range(copies))
    marker = "<!--tiled-->"
    holder.append(etree.Comment("tiled"))
    whole = etree.tostring(root, encoding="unicode")
    whole = whole.replace(marker, extra, 1)
    if root.tag != "XMI":
        extra_apps = "".join(_renamed(apps_text, ids, f"_t{k}") for k in range(copies))
        end = whole.rindex("</")
        whole = whole[:end] + extra_apps + whole[end:]
    return ('<?xml version="1.0" encoding="UTF-8"?>\n' + whole).encode("utf-8")
