"""Enterprise Architect's XMI 1.1 writes a package twice: as ``UML:Package`` (``EAPK_<guid>``) and as a
``UML:ClassifierRole`` of its parent's ``Collaborations`` (``package2="EAID_<guid>"``, ``ea_stype`` =
``Package``). The qualified name of the package's stereotype (``FQName=MIM::Domein``) may stand only on
the twin: the stereotype is then the profile's, not a free one."""

from __future__ import annotations

from pathlib import Path

from acordcs.xmi.readers import read_uml

XREF = (
    "$XREFPROP=$XID={X1}$XID;$NAM=Stereotypes$NAM;$TYP=element property$TYP;$VIS=Public$VIS;"
    "$PAR=0$PAR;$DES=@STEREO;Name=Domein;GUID={G1};FQName=MIM::Domein;@ENDSTEREO;$DES;"
    "$CLT={C1}$CLT;$SUP=&lt;none&gt;$SUP;$ENDXREF;"
)
EA_TWINS = """<?xml version="1.0" encoding="windows-1252"?>
<XMI xmi.version="1.1" xmlns:UML="omg.org/UML1.3">
 <XMI.header><XMI.documentation><XMI.exporter>Enterprise Architect</XMI.exporter>
 <XMI.exporterVersion>2.5</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <UML:Model name="EA Model" xmi.id="MX_EAID_1"><UML:Namespace.ownedElement>
   <UML:Package name="Model" xmi.id="EAPK_A" isRoot="true"><UML:Namespace.ownedElement>
    <UML:Collaboration xmi.id="EAID_A_Collaboration" name="Collaborations"><UML:Namespace.ownedElement>
{twins}
    </UML:Namespace.ownedElement></UML:Collaboration>
{packages}
   </UML:Namespace.ownedElement></UML:Package>
  </UML:Namespace.ownedElement></UML:Model>
 </XMI.content>
</XMI>
"""
TWIN = """     <UML:ClassifierRole name="{name}" xmi.id="EAID_{n}" visibility="public" base="EAID_11111111">
      <UML:ModelElement.stereotype><UML:Stereotype name="Domein"/></UML:ModelElement.stereotype>
      <UML:ModelElement.taggedValue>
       <UML:TaggedValue tag="ea_stype" value="Package"/>
       <UML:TaggedValue tag="package" value="EAPK_A"/>
       <UML:TaggedValue tag="package2" value="EAID_{n}"/>
       <UML:TaggedValue tag="package_name" value="Model"/>
       <UML:TaggedValue tag="$ea_xref_property" value="{xref}"/>
      </UML:ModelElement.taggedValue>
     </UML:ClassifierRole>"""
PACKAGE = """    <UML:Package name="{name}" xmi.id="EAPK_{n}" visibility="public">
     <UML:ModelElement.stereotype><UML:Stereotype name="Domein"/></UML:ModelElement.stereotype>
     <UML:ModelElement.taggedValue><UML:TaggedValue tag="parent" value="EAPK_A"/></UML:ModelElement.taggedValue>
    </UML:Package>"""
NAMES = {"B": "Kadaster", "C": "Gebouwen", "D": "Adressen"}


def _model(tmp_path: Path, xref: str = XREF) -> Path:
    text = EA_TWINS.format(
        twins="\n".join(TWIN.format(name=m, n=n, xref=xref) for n, m in NAMES.items()),
        packages="\n".join(PACKAGE.format(name=m, n=n) for n, m in NAMES.items()),
    )
    path = tmp_path / "mim.xmi"
    path.write_bytes(text.encode("cp1252"))
    return path


def test_the_twins_fqname_gives_the_packages_stereotype_its_profile(tmp_path: Path) -> None:
    uml = read_uml(str(_model(tmp_path)))
    applied = sorted((uml.elements[a.base].name, a.key) for a in uml.applications.values())
    assert applied == [(name, "MIM:Domein") for name in sorted(NAMES.values())]
    # the twins are read, not reported as skipped; the packages are packages
    assert [d.code for d in uml.diagnostics] == []
    assert sorted(p.name for p in uml.packages) == sorted(["Model", *NAMES.values()])


def test_without_an_fqname_the_stereotype_stays_free(tmp_path: Path) -> None:
    uml = read_uml(str(_model(tmp_path, XREF.replace("FQName=MIM::Domein;", ""))))
    assert sorted(a.key for a in uml.applications.values()) == ["Domein"] * 3
