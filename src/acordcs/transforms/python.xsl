<?xml version="1.0" encoding="UTF-8"?>
<!--
  Target "python" of acordcs-gen: a Python package per application (see python.py, which checks the
  model's names before this stylesheet runs: every name that becomes Python code is an identifier,
  no keyword, no name of the component API; string literals come from py:str and py:doc).

    <pkg>/__init__.py              the application: its name, containers, assemble_application()
    <pkg>/descriptor.xml           the descriptor (the document the config target writes)
    <pkg>/registry.py              FACTORIES: component name -> the user's class
    <pkg>/model_types.py           the model's types that are not Python's (aliases of object)
    <pkg>/base/__init__.py
    <pkg>/base/<Component>.py      <Component>Base(CtxComponent): typed properties, ports, operations
    <pkg>/components/__init__.py   created once (the user's)
    <pkg>/components/<Component>.py  <Component>(<Component>Base): created once, never overwritten
    <pkg>/<Container>.py           the container: a few lines handing over to acordcs.runtime.launcher

  The Python types in signatures come from python.py's typing plan (parameter "typing", JSON):
  decided once in Python, looked up here.

  Files listed with once="yes" are written only when absent and never deleted (generation gap).
-->
<xsl:stylesheet version="3.0"
    xmlns:xsl="http://www.w3.org/1999/XSL/Transform"
    xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:d="http://acordcs.org/descriptor/1.0"
    xmlns:py="http://acordcs.org/codegen/python"
    xmlns:map="http://www.w3.org/2005/xpath-functions/map"
    xmlns:array="http://www.w3.org/2005/xpath-functions/array"
    xmlns="http://acordcs.org/codegen/1.0"
    exclude-result-prefixes="xs d py map array"
    expand-text="yes">

  <xsl:param name="source-file" as="xs:string" required="yes"/>
  <xsl:param name="generator" as="xs:string" required="yes"/>
  <xsl:param name="target" as="xs:string" required="yes"/>
  <xsl:param name="descriptor-schema" as="xs:string" required="yes"/>
  <!-- The package's name, from python.py's package_name (an identifier, no keyword, no module of
       the standard library, not acordcs). -->
  <xsl:param name="package" as="xs:string" required="yes"/>
  <!-- python.py's typing_plan as JSON: "types" (UML type -> annotation of a value), "returns"
       (UML return type, '' when none -> annotation), "attributes" (component -> property ->
       annotation, for the properties that become typed attributes), "aliases" (the UML types
       model_types.py declares). -->
  <xsl:param name="typing" as="xs:string" required="yes"/>
  <!-- Which parameters are an operation's arguments and which come back in its result, as the
       runtime maps them (acordcs.vocabularies.ARGUMENT_DIRECTIONS, RESULT_DIRECTIONS). -->
  <xsl:param name="argument-directions" as="xs:string" required="yes"/>
  <xsl:param name="result-directions" as="xs:string" required="yes"/>
  <xsl:variable name="arguments" select="tokenize($argument-directions)"/>
  <xsl:variable name="results" select="tokenize($result-directions)"/>
  <xsl:variable name="plan" as="map(*)" select="parse-json($typing)"/>

  <xsl:output method="xml" encoding="UTF-8" indent="no"/>

  <!-- ===================================================================== string literals -->

  <!-- A Python string literal of $s: "..." with \, ", and every control, format, unassigned,
       private-use, line- and paragraph-separator character escaped (the source stays one line). -->
  <xsl:function name="py:str" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:sequence select="'&quot;' || py:escaped($s, '[\\&quot;\p{C}\p{Zl}\p{Zp}]') || '&quot;'"/>
  </xsl:function>

  <!-- A docstring of $s: """...""" keeping its line breaks (indented by $indent), every other
       character py:str escapes escaped, so that no """ and no backslash sequence comes from $s. -->
  <xsl:function name="py:doc" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:param name="indent" as="xs:string"/>
    <xsl:variable name="lines" select="tokenize(replace($s, '\r\n?', '&#10;'), '&#10;')"/>
    <xsl:variable name="body" select="string-join(for $i in 1 to count($lines) return
        (if ($i gt 1 and normalize-space($lines[$i])) then $indent else '') || py:inline($lines[$i]), '&#10;')"/>
    <xsl:sequence select="'&quot;&quot;&quot;' || $body || '&quot;&quot;&quot;'"/>
  </xsl:function>

  <!-- $s inside a docstring: what py:str escapes, escaped, without quotes around it. -->
  <xsl:function name="py:inline" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:sequence select="py:escaped($s, '[\\&quot;\p{C}\p{Zl}\p{Zp}]')"/>
  </xsl:function>

  <xsl:function name="py:escaped" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:param name="regex" as="xs:string"/>
    <xsl:variable name="parts" as="xs:string*">
      <xsl:analyze-string select="if (matches($s, $regex)) then $s else ''" regex="{$regex}">
        <xsl:matching-substring>
          <xsl:sequence select="py:escape(string-to-codepoints(.))"/>
        </xsl:matching-substring>
        <xsl:non-matching-substring>
          <xsl:sequence select="."/>
        </xsl:non-matching-substring>
      </xsl:analyze-string>
    </xsl:variable>
    <xsl:sequence select="if (matches($s, $regex)) then string-join($parts) else $s"/>
  </xsl:function>

  <xsl:function name="py:escape" as="xs:string">
    <xsl:param name="c" as="xs:integer"/>
    <xsl:choose>
      <xsl:when test="$c = 92">\\</xsl:when>
      <xsl:when test="$c = 34">\"</xsl:when>
      <xsl:when test="$c = 10">\n</xsl:when>
      <xsl:when test="$c = 13">\r</xsl:when>
      <xsl:when test="$c = 9">\t</xsl:when>
      <xsl:when test="$c lt 256">\x{py:hex($c, 2)}</xsl:when>
      <xsl:when test="$c lt 65536">\u{py:hex($c, 4)}</xsl:when>
      <xsl:otherwise>\U{py:hex($c, 8)}</xsl:otherwise>
    </xsl:choose>
  </xsl:function>

  <xsl:function name="py:hex" as="xs:string">
    <xsl:param name="n" as="xs:integer"/>
    <xsl:param name="width" as="xs:integer"/>
    <xsl:variable name="digits" select="py:hex-digits($n)"/>
    <xsl:sequence select="string-join((for $i in 1 to $width - string-length($digits) return '0', $digits))"/>
  </xsl:function>

  <xsl:function name="py:hex-digits" as="xs:string">
    <xsl:param name="n" as="xs:integer"/>
    <xsl:variable name="digit" select="substring('0123456789abcdef', $n mod 16 + 1, 1)"/>
    <xsl:sequence select="if ($n lt 16) then $digit else py:hex-digits($n idiv 16) || $digit"/>
  </xsl:function>

  <!-- A tuple display of the literals $items. -->
  <xsl:function name="py:tuple" as="xs:string">
    <xsl:param name="items" as="xs:string*"/>
    <xsl:sequence select="'(' || string-join($items, ', ') || (if (count($items) eq 1) then ',' else '') || ')'"/>
  </xsl:function>

  <!-- A property's default as a Python literal, typed by its kind (the descriptor's typing). -->
  <xsl:function name="py:value" as="xs:string">
    <xsl:param name="p" as="element()"/>
    <xsl:variable name="v" select="string($p/@default)"/>
    <xsl:choose>
      <xsl:when test="$p/@kind = 'bool'">{if ($v = ('true', '1')) then 'True' else 'False'}</xsl:when>
      <xsl:when test="$p/@kind = 'int'">
        <xsl:if test="not(matches($v, '^-?[0-9]+$'))">
          <xsl:message terminate="yes">property {$p/@qname}: default {$v} is not an int</xsl:message>
        </xsl:if>
        <xsl:sequence select="string(xs:integer($v))"/>
      </xsl:when>
      <xsl:when test="$p/@kind = 'double'">
        <xsl:choose>
          <xsl:when test="lower-case($v) = ('inf', '+inf', 'infinity')">float("inf")</xsl:when>
          <xsl:when test="lower-case($v) = ('-inf', '-infinity')">float("-inf")</xsl:when>
          <xsl:when test="lower-case($v) = 'nan'">float("nan")</xsl:when>
          <xsl:when test="matches($v, '^-?[0-9]+$')">{$v}.0</xsl:when>
          <xsl:when test="matches($v, '^-?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+\-]?[0-9]+)?$')">{$v}</xsl:when>
          <xsl:otherwise>
            <xsl:message terminate="yes">property {$p/@qname}: default {$v} is not a double</xsl:message>
          </xsl:otherwise>
        </xsl:choose>
      </xsl:when>
      <xsl:otherwise>{py:str($v)}</xsl:otherwise>
    </xsl:choose>
  </xsl:function>

  <!-- The header, as acordcs/generator/headers.py writes it for '#' comments (names cleaned). -->
  <xsl:function name="py:header" as="xs:string">
    <xsl:param name="what" as="xs:string"/>
    <xsl:param name="note" as="xs:string"/>
    <xsl:variable name="lines" select="('Generated by ' || $generator || ' (target ' || $target || ') from ' || $what,
        'in model file ' || $source-file || '. ' || $note)"/>
    <xsl:sequence select="string-join(for $l in $lines return '# ' || py:escaped($l, '[\p{C}\p{Zl}\p{Zp}]'), '&#10;') || '&#10;'"/>
  </xsl:function>

  <xsl:variable name="regenerated" select="'Do not edit: rebuild with acordcs-gen build.'"/>
  <xsl:variable name="yours" select="'Written once: yours to edit, never overwritten by a build.'"/>

  <!-- ======================================================================== the package -->

  <xsl:template match="/">
    <xsl:variable name="app" select="d:application"/>
    <xsl:if test="not($app)">
      <xsl:message terminate="yes">the input is not an application descriptor (no d:application element)</xsl:message>
    </xsl:if>
    <xsl:variable name="pkg" select="$package"/>
    <xsl:variable name="components" select="$app/d:components/d:component"/>
    <xsl:variable name="containers" select="$app/d:containers/d:container"/>
    <xsl:variable name="monitors" select="$app/d:monitors/d:monitor"/>
    <xsl:variable name="all-ids" select="string-join(distinct-values($app/*/*/@id), ' ')"/>

    <xsl:result-document href="{$pkg}/__init__.py" method="text" encoding="UTF-8">
      <xsl:call-template name="init">
        <xsl:with-param name="app" select="$app"/>
        <xsl:with-param name="pkg" select="$pkg"/>
      </xsl:call-template>
    </xsl:result-document>
    <xsl:result-document href="{$pkg}/descriptor.xml" method="xml" encoding="UTF-8" indent="no">
      <xsl:text>&#10;</xsl:text>
      <xsl:comment> Generated by {$generator} (target {$target}) from the deployment descriptor of model '{$app/@name}'
     in model file {$source-file}. {$regenerated} </xsl:comment>
      <xsl:text>&#10;</xsl:text>
      <xsl:copy-of select="node()"/>
      <xsl:text>&#10;</xsl:text>
    </xsl:result-document>
    <xsl:result-document href="{$pkg}/registry.py" method="text" encoding="UTF-8">
      <xsl:call-template name="registry">
        <xsl:with-param name="app" select="$app"/>
        <xsl:with-param name="pkg" select="$pkg"/>
      </xsl:call-template>
    </xsl:result-document>
    <xsl:result-document href="{$pkg}/model_types.py" method="text" encoding="UTF-8">
      <xsl:call-template name="model-types">
        <xsl:with-param name="app" select="$app"/>
      </xsl:call-template>
    </xsl:result-document>
    <xsl:result-document href="{$pkg}/base/__init__.py" method="text" encoding="UTF-8">
      <xsl:sequence select="py:header('model ''' || $app/@name || '''', $regenerated)"/>
      <xsl:text>"""The generated base classes of the components and monitors of '{py:inline($app/@name)}': one module each."""&#10;</xsl:text>
    </xsl:result-document>
    <xsl:result-document href="{$pkg}/components/__init__.py" method="text" encoding="UTF-8">
      <xsl:sequence select="py:header('model ''' || $app/@name || '''', $yours)"/>
      <xsl:text>"""The component classes of '{py:inline($app/@name)}': one module each, yours to implement."""&#10;</xsl:text>
    </xsl:result-document>
    <xsl:for-each select="$components">
      <xsl:result-document href="{$pkg}/base/{@name}.py" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="base"/>
      </xsl:result-document>
      <xsl:result-document href="{$pkg}/components/{@name}.py" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="user">
          <xsl:with-param name="pkg" select="$pkg" tunnel="yes"/>
        </xsl:apply-templates>
      </xsl:result-document>
    </xsl:for-each>
    <xsl:result-document href="{$pkg}/monitors/__init__.py" method="text" encoding="UTF-8">
      <xsl:sequence select="py:header('model ''' || $app/@name || '''', $yours)"/>
      <xsl:text>"""The monitor classes of '{py:inline($app/@name)}': one module each, yours to complete."""&#10;</xsl:text>
    </xsl:result-document>
    <xsl:for-each select="$monitors">
      <xsl:result-document href="{$pkg}/base/{@name}.py" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="base"/>
      </xsl:result-document>
      <xsl:result-document href="{$pkg}/monitors/{@name}.py" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="user">
          <xsl:with-param name="pkg" select="$pkg" tunnel="yes"/>
        </xsl:apply-templates>
      </xsl:result-document>
    </xsl:for-each>
    <xsl:for-each select="$containers">
      <xsl:result-document href="{$pkg}/{@name}.py" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="container">
          <xsl:with-param name="pkg" select="$pkg" tunnel="yes"/>
        </xsl:apply-templates>
      </xsl:result-document>
    </xsl:for-each>

    <files>
      <file path="{$pkg}/__init__.py" element="{$app/@name}" ids="{$all-ids}"/>
      <file path="{$pkg}/descriptor.xml" element="{$app/@name}" ids="{$all-ids}"/>
      <file path="{$pkg}/registry.py" element="{$app/@name}" ids="{string-join(($components/@id, $monitors/@id), ' ')}"/>
      <file path="{$pkg}/model_types.py" element="{$app/@name}" ids="{string-join($components/@id, ' ')}"/>
      <file path="{$pkg}/base/__init__.py" element="{$app/@name}" ids=""/>
      <file path="{$pkg}/components/__init__.py" element="{$app/@name}" ids="" once="yes"/>
      <file path="{$pkg}/monitors/__init__.py" element="{$app/@name}" ids="" once="yes"/>
      <xsl:for-each select="$monitors">
        <file path="{$pkg}/base/{@name}.py" element="{@qname}" ids="{string-join((@id, .//@id), ' ')}"/>
        <file path="{$pkg}/monitors/{@name}.py" element="{@qname}" ids="{@id}" once="yes"/>
      </xsl:for-each>
      <xsl:for-each select="$components">
        <file path="{$pkg}/base/{@name}.py" element="{@qname}" ids="{string-join((@id, .//@id), ' ')}"/>
        <file path="{$pkg}/components/{@name}.py" element="{@qname}" ids="{@id}" once="yes"/>
      </xsl:for-each>
      <xsl:for-each select="$containers">
        <file path="{$pkg}/{@name}.py" element="{@qname}" ids="{string-join((@id, d:hosts/@ref), ' ')}"/>
      </xsl:for-each>
    </files>
  </xsl:template>

  <!-- ================================================================== __init__.py -->
  <xsl:template name="init">
    <xsl:param name="app" as="element()"/>
    <xsl:param name="pkg" as="xs:string"/>
    <xsl:sequence select="py:header('model ''' || $app/@name || '''', $regenerated)"/>
    <xsl:text>"""Application '{py:inline($app/@name)}': its containers, each a module run with
``python -m {$pkg}.&lt;container&gt;``; :func:`assemble_application` builds them in one process.

The component classes are in ``{$pkg}.components`` and the monitor classes in
``{$pkg}.monitors`` (yours: written once, never overwritten), derived from the generated ones in
``{$pkg}.base``; ``{$pkg}.registry`` maps each component and monitor to its class.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from {$pkg}.registry import FACTORIES, MONITORS, assemble_application, descriptor

APPLICATION = {py:str($app/@name)}
CONTAINERS = {py:tuple(for $c in $app/d:containers/d:container return py:str($c/@name))}

__all__ = ["APPLICATION", "CONTAINERS", "FACTORIES", "MONITORS", "assemble_application", "descriptor"]
_REGISTRY = frozenset(__all__[2:])


def __getattr__(name: str) -> object:
    # The registry imports your classes: only when asked, so that a container's launcher reports
    # an error in them (file and line) instead of a traceback.
    if name in _REGISTRY:
        from {$pkg} import registry

        return getattr(registry, name)
    raise AttributeError(f"module {{__name__!r}} has no attribute {{name!r}}")
</xsl:text>
  </xsl:template>

  <!-- ================================================================== registry.py -->
  <xsl:template name="registry">
    <xsl:param name="app" as="element()"/>
    <xsl:param name="pkg" as="xs:string"/>
    <xsl:variable name="components" select="$app/d:components/d:component"/>
    <xsl:variable name="monitors" select="$app/d:monitors/d:monitor"/>
    <xsl:sequence select="py:header('model ''' || $app/@name || '''', $regenerated)"/>
    <xsl:text>"""The factory registry of '{py:inline($app/@name)}': each component and monitor of the model and
the class implementing it (``{$pkg}.components``, ``{$pkg}.monitors``), and the application
assembled from the descriptor ``descriptor.xml`` with them (:func:`acordcs.runtime.assembly.assemble`)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from acordcs.descriptor import Application, from_xml
from acordcs.runtime.api import Clock, CtxComponent, Monitor, RunningApplication, assemble
</xsl:text>
    <xsl:for-each select="$components">
      <xsl:text>from {$pkg}.components.{@name} import {@name}&#10;</xsl:text>
    </xsl:for-each>
    <xsl:for-each select="$monitors">
      <xsl:text>from {$pkg}.monitors.{@name} import {@name}&#10;</xsl:text>
    </xsl:for-each>
    <xsl:text>
if TYPE_CHECKING:
    from acordcs.runtime.api import ProviderCore

FACTORIES: dict[str, type[CtxComponent]] = {{
</xsl:text>
    <xsl:for-each select="$components">
      <xsl:text>    {py:str(@name)}: {@name},&#10;</xsl:text>
    </xsl:for-each>
    <xsl:text>}}
"""Component name -> the class the container creates it from."""

MONITORS: dict[str, type[Monitor]] = {{
</xsl:text>
    <xsl:for-each select="$monitors">
      <xsl:text>    {py:str(@name)}: {@name},&#10;</xsl:text>
    </xsl:for-each>
    <xsl:text>}}
"""Monitor name -> its class."""

DESCRIPTOR = Path(__file__).with_name("descriptor.xml")
</xsl:text>
    <xsl:if test="$components[@language = 'java']">
      <xsl:text>JAVA_SOURCES = Path(__file__).resolve().parent.parent / "java"
"""The ``java`` target's sources: the classes of the components tagged language=java
({string-join($components[@language = 'java']/py:inline(@name), ', ')}), which the container compiles and hosts."""
</xsl:text>
    </xsl:if>
    <xsl:text>

def descriptor() -> Application:
    """The application descriptor, read (and validated) from ``descriptor.xml``."""
    return from_xml(DESCRIPTOR.read_bytes(), file=str(DESCRIPTOR))


def assemble_application(
    *,
    only: Iterable[str] | None = None,
    clock: Clock | None = None,
    remote: Mapping[str, str] | None = None,
    remote_timeout: float = 5.0,
    monitors: Mapping[str, type[Monitor]] | None = None,
    application: Application | None = None,
    context: ProviderCore | None = None,
    state_dir: Path | None = None,
) -> RunningApplication:
    """The containers of the application (all, or those in ``only``), with the component classes
    of :data:`FACTORIES` and the monitor classes of :data:`MONITORS` (``monitors`` replaces some);
    ``remote`` gives the URI of each container running elsewhere; ``application``: the
    descriptor, if read already (default: :func:`descriptor`); ``context``: the context provider
    (default: an embedded one; an MQTT one shares context with other processes); ``state_dir``:
    where the state of the components tagged persistent is kept (None: not kept)."""
    return assemble(
        application if application is not None else descriptor(),
        factories=FACTORIES,
        monitors={{**MONITORS, **(monitors or {{}})}},
        clock=clock,
        only=only,
        remote=remote,
        remote_timeout=remote_timeout,
        context=context,
        state_dir=state_dir,
</xsl:text>
    <xsl:if test="$components[@language = 'java']">
      <xsl:text>        java_sources=JAVA_SOURCES,
</xsl:text>
    </xsl:if>
    <xsl:text>    )
</xsl:text>
  </xsl:template>

  <!-- ================================================================ base/<Component>.py -->
  <xsl:template match="d:component" mode="base">
    <xsl:variable name="ops" select="d:operation"/>
    <xsl:variable name="attributes" select="py:attributes(.)"/>
    <xsl:variable name="untyped" select="d:property[not(map:contains($attributes, string(@name)))]"/>
    <xsl:variable name="signatures" as="xs:string*">
      <xsl:for-each-group select="$ops" group-by="@name">
        <xsl:sequence select="py:parameters(current-group()) || py:returns-type(current-group())"/>
      </xsl:for-each-group>
    </xsl:variable>
    <xsl:variable name="uses-types" select="some $a in (map:for-each($attributes, function($k, $v) {string($v)}), $signatures) satisfies contains($a, 'model_types.')"/>
    <xsl:variable name="api" select="('CtxComponent', if (map:size($attributes)) then 'ModelProperty' else (), 'PortSpec', if ($ops) then 'unimplemented' else ())"/>
    <xsl:sequence select="py:header('component ''' || @name || ''' ('|| @qname || ', id ' || @id || ')', $regenerated)"/>
    <xsl:text>"""The generated base of component {@name}; its code is in ``components/{@name}.py``."""

from __future__ import annotations

from acordcs.runtime.api import {string-join($api, ', ')}
</xsl:text>
    <xsl:if test="$ops">
      <xsl:text>from acordcs.runtime.errors import OperationNotImplementedError&#10;</xsl:text>
    </xsl:if>
    <xsl:if test="$uses-types">
      <xsl:text>from {$package} import model_types&#10;</xsl:text>
    </xsl:if>
    <xsl:text>

class {@name}Base(CtxComponent):
    {py:doc(string-join((if (d:documentation) then string(d:documentation) else (), 'Component ' || @name || ' (' || @qname || ').'), '&#10;&#10;'), '    ')}

    properties = {{</xsl:text>
    <xsl:choose>
      <xsl:when test="d:property">
        <xsl:text>&#10;</xsl:text>
        <xsl:for-each select="d:property">
          <xsl:text>        {py:str(@name)}: {py:value(.)},  # {py:escaped(@type, '[\p{C}\p{Zl}\p{Zp}]')}&#10;</xsl:text>
        </xsl:for-each>
        <xsl:text>    }}&#10;</xsl:text>
      </xsl:when>
      <xsl:otherwise>}}&#10;</xsl:otherwise>
    </xsl:choose>
    <xsl:text>    ports = (</xsl:text>
    <xsl:choose>
      <xsl:when test="d:port">
        <xsl:text>&#10;</xsl:text>
        <xsl:for-each select="d:port">
          <xsl:variable name="settings" as="xs:string*">
            <xsl:for-each select="d:property[@name = 'rate' and @kind = ('int', 'double')][1]">rate={number(@default)}{if (contains(string(number(@default)), '.') or contains(string(number(@default)), 'E')) then '' else '.0'}</xsl:for-each>
            <xsl:for-each select="d:property[@name = 'capacity' and @kind = 'int'][1]">capacity={py:value(.)}</xsl:for-each>
            <xsl:for-each select="d:property[@name = 'overflow' and @kind = 'string'][1]">overflow={py:value(.)}</xsl:for-each>
          </xsl:variable>
          <xsl:text>        PortSpec({string-join((py:str(@name), py:str(@kind), py:str(@role), $settings), ', ')}),&#10;</xsl:text>
        </xsl:for-each>
        <xsl:text>    )&#10;</xsl:text>
      </xsl:when>
      <xsl:otherwise>)&#10;</xsl:otherwise>
    </xsl:choose>
    <xsl:if test="map:size($attributes)">
      <xsl:text>
    # The properties as typed attributes: self.x reads self.get("x"), self.x = v is
    # self.set("x", v), through the container (policies and monitors see the change).
</xsl:text>
      <xsl:for-each select="d:property[map:contains($attributes, string(@name))]">
        <xsl:if test="not(preceding-sibling::d:property[@name = current()/@name])">
          <xsl:text>    {@name} = ModelProperty[{$attributes(string(@name))}]({py:str(@name)})&#10;</xsl:text>
        </xsl:if>
      </xsl:for-each>
    </xsl:if>
    <xsl:if test="$untyped">
      <xsl:text>    # Without an attribute (a name that is taken or no identifier): self.get({string-join(distinct-values($untyped/@name) ! py:str(.), '), self.get(')})&#10;</xsl:text>
    </xsl:if>
    <xsl:for-each-group select="$ops" group-by="@name">
      <xsl:variable name="overloads" select="current-group()"/>
      <xsl:variable name="first" select="$overloads[1]"/>
      <xsl:variable name="shown" select="string-join(for $o in $overloads return py:signature($o), ' or ')"/>
      <xsl:variable name="doc" select="string-join((
          for $o in $overloads return string($o/d:documentation)[. ne ''],
          'Operation ' || $shown || '.',
          for $o in $overloads return py:returns($o)), '&#10;&#10;')"/>
      <xsl:text>
    @unimplemented
    def {$first/@name}(self{py:parameters($overloads)}){py:returns-type($overloads)}:
        {py:doc($doc, '        ')}
        raise OperationNotImplementedError(
            {py:str('component ' || ../@name || ' has no code for operation ' || $shown)},
            hint={py:str('implement ' || $first/@name || '() in components/' || ../@name || '.py')},
        )
</xsl:text>
    </xsl:for-each-group>
  </xsl:template>

  <!-- The typed attributes of component $c: property name -> annotation (python.py decides which
       properties get one). -->
  <xsl:function name="py:attributes" as="map(*)">
    <xsl:param name="c" as="element()"/>
    <xsl:sequence select="(map:get(map:get($plan, 'attributes'), string($c/@name)), map{})[1]"/>
  </xsl:function>

  <!-- The annotation of a value of UML type $t. -->
  <xsl:function name="py:type" as="xs:string">
    <xsl:param name="t" as="xs:string?"/>
    <xsl:sequence select="(map:get(map:get($plan, 'types'), string($t)), 'object')[1]"/>
  </xsl:function>

  <!-- " -> T" for an operation (its overloads: object): its return type, or a tuple of it and
       its out and inout parameters (acordcs.runtime.operations' mapping). -->
  <xsl:function name="py:returns-type" as="xs:string">
    <xsl:param name="overloads" as="element()+"/>
    <xsl:variable name="op" select="$overloads[1]"/>
    <xsl:variable name="r" select="(map:get(map:get($plan, 'returns'), string($op/@returns)), 'object')[1]"/>
    <xsl:variable name="outs" select="$op/d:parameter[@direction = $results]"/>
    <xsl:sequence select="' -> ' || (if (count($overloads) gt 1) then 'object'
        else if ($outs) then 'tuple[' || string-join(($r, $outs ! py:type(@type)), ', ') || ']'
        else $r)"/>
  </xsl:function>

  <!-- name(in a: T, out b: U): R, as the model declares it -->
  <xsl:function name="py:signature" as="xs:string">
    <xsl:param name="op" as="element()"/>
    <xsl:sequence select="$op/@name || '(' || string-join(for $p in $op/d:parameter return
        $p/@direction || ' ' || $p/@name || ': ' || $p/@type, ', ') || ')'
        || (if ($op/@returns) then ': ' || $op/@returns else '')"/>
  </xsl:function>

  <!-- What a call returns, by acordcs.runtime.operations' mapping of out parameters. -->
  <xsl:function name="py:returns" as="xs:string">
    <xsl:param name="op" as="element()"/>
    <xsl:variable name="outs" select="$op/d:parameter[@direction = $results]/@name"/>
    <xsl:sequence select="if ($outs) then 'Returns the tuple (return value, ' || string-join($outs, ', ') || ').'
        else if ($op/@returns) then 'Returns a ' || $op/@returns || '.' else 'Returns None.'"/>
  </xsl:function>

  <!-- =========================================================== components/<Component>.py -->
  <xsl:template match="d:component" mode="user">
    <xsl:param name="pkg" tunnel="yes"/>
    <xsl:sequence select="py:header('component ''' || @name || ''' ('|| @qname || ', id ' || @id || ')', $yours)"/>
    <xsl:choose>
      <xsl:when test="@language = 'java'">
        <xsl:text>"""Component {py:inline(@name)} is tagged language=java: its container runs its Java class, whose
code is yours in the java target's java/&lt;package&gt;/ directory; this Python class is not used
while the tag says java (implement its operations here if you tag it python)."""
</xsl:text>
      </xsl:when>
      <xsl:otherwise>
        <xsl:text>"""Component {@name}: implement its operations here (see {@name}Base)."""
</xsl:text>
      </xsl:otherwise>
    </xsl:choose>
    <xsl:text>
from __future__ import annotations

from {$pkg}.base.{@name} import {@name}Base


class {@name}({@name}Base):
</xsl:text>
    <xsl:variable name="attributes" select="py:attributes(.)"/>
    <xsl:variable name="typed" select="d:property[map:contains($attributes, string(@name))][1]"/>
    <xsl:if test="d:operation">
      <xsl:text>    # The model's operations, to implement here (those of {@name}Base raise
    # OperationNotImplementedError):
</xsl:text>
      <xsl:for-each-group select="d:operation" group-by="@name">
        <xsl:text>    #   def {current-grouping-key()}(self{py:parameters(current-group())}){py:returns-type(current-group())}:&#10;</xsl:text>
      </xsl:for-each-group>
    </xsl:if>
    <xsl:if test="$typed">
      <xsl:text>    # Its properties are typed attributes of {@name}Base (self.{$typed/@name}: {$attributes(string($typed/@name))}).&#10;</xsl:text>
    </xsl:if>
    <xsl:if test="some $o in d:operation satisfies contains(py:parameters($o) || py:returns-type($o), 'model_types.')">
      <xsl:text>    # The model's other types: from {$package} import model_types&#10;</xsl:text>
    </xsl:if>
    <xsl:if test="d:port[@role = 'required']">
      <xsl:text>    # Its required ports, and how to use each (self.port(name) is the running port):&#10;</xsl:text>
      <xsl:sequence select="string-join(d:port[@role = 'required'] ! py:port-use(.))"/>
    </xsl:if>
    <xsl:text>    pass&#10;</xsl:text>
  </xsl:template>

  <!-- Comment lines of a user class saying how to use required port $port: for a synchronous one,
       the call of each operation of the component it is connected to (acordcs.runtime.ports:
       Port.call runs the provider's operation, whatever container it is in); for an asynchronous
       or stream one, where what its peers send arrives (a handler on_<port>, else the queue). -->
  <xsl:function name="py:port-use" as="xs:string">
    <xsl:param name="port" as="element(d:port)"/>
    <xsl:variable name="app" select="$port/ancestor::d:application"/>
    <xsl:variable name="links" select="$app/d:connections/d:connection[d:required/@ref = $port/@id]"/>
    <xsl:variable name="peers" select="string-join($links ! (d:provided/@component || '.' || d:provided/@port || ' (connection ' || @name || ')'), ', ')"/>
    <xsl:variable name="at" select="'self.port(' || py:str($port/@name) || ')'"/>
    <xsl:variable name="name" select="py:comment($port/@name) || ' (' || $port/@kind || ')'"/>
    <xsl:variable name="lines" as="xs:string*">
    <xsl:choose>
      <xsl:when test="empty($links)">
        <xsl:sequence select="'    #   ' || $name || ': not connected in the model (using it raises PortError until a connection joins it to a provided port)&#10;'"/>
      </xsl:when>
      <xsl:when test="$port/@kind = 'synchronous'">
        <xsl:variable name="provider" select="$app/d:components/d:component[@name = $links[1]/d:provided/@component]"/>
        <xsl:sequence select="'    #   ' || $name || ', to ' || py:comment($peers) || ':&#10;'"/>
        <xsl:if test="empty($provider/d:operation)">
          <xsl:sequence select="'    #     (' || py:comment($provider/@name) || ' has no operation to call)&#10;'"/>
        </xsl:if>
        <xsl:for-each-group select="$provider/d:operation" group-by="@name">
          <xsl:variable name="overloads" select="current-group()"/>
          <xsl:variable name="returns" select="substring-after(py:returns-type($overloads), ' -> ')"/>
          <xsl:variable name="typed" select="if (count($overloads) gt 1)
              then string-join($overloads ! py:signature(.), ' or ')
              else string-join((string-join($overloads[1]/d:parameter[@direction = $arguments] ! (@name || ': ' || py:type(@type)), ', ')[. ne ''],
                if ($returns ne 'None') then '-> ' || $returns else ()), ' ')"/>
          <xsl:variable name="args" select="if (count($overloads) gt 1) then ', ...'
              else string-join($overloads[1]/d:parameter[@direction = $arguments] ! (', ' || @name))"/>
          <xsl:sequence select="'    #     ' || (if ($returns ne 'None') then 'result = ' else '') || $at
              || '.call(' || py:str(current-grouping-key()) || $args || ')'
              || (if ($typed) then '  # ' || py:comment($typed) else '') || '&#10;'"/>
        </xsl:for-each-group>
      </xsl:when>
      <xsl:otherwise>
        <xsl:variable name="what" select="if ($port/@kind = 'stream') then 'item' else 'message'"/>
        <xsl:sequence select="'    #   ' || $name || ', from ' || py:comment($peers) || ':&#10;'"/>
        <xsl:if test="matches($port/@name, '^[A-Za-z_][A-Za-z0-9_]*$')">
          <xsl:sequence select="'    #     def on_' || $port/@name || '(self, ' || $what || ': object) -&gt; None:  # gets each ' || $what || ' sent, or:&#10;'"/>
        </xsl:if>
        <xsl:sequence select="'    #     ' || $what || ' = ' || $at || '.take()  # the oldest queued, or None&#10;'"/>
      </xsl:otherwise>
    </xsl:choose>
    </xsl:variable>
    <xsl:sequence select="string-join($lines)"/>
  </xsl:function>

  <!-- $s in a '#' comment: on one line (what py:escaped escapes in headers, escaped). -->
  <xsl:function name="py:comment" as="xs:string">
    <xsl:param name="s" as="xs:string?"/>
    <xsl:sequence select="py:escaped(string($s), '[\p{C}\p{Zl}\p{Zp}]')"/>
  </xsl:function>

  <!-- ", a: T, b: U" for the Python parameters of an operation, annotated (its overloads:
       *args: object, **kwargs: object). -->
  <xsl:function name="py:parameters" as="xs:string">
    <xsl:param name="overloads" as="element()+"/>
    <xsl:variable name="params" select="if (count($overloads) gt 1) then '*args: object, **kwargs: object'
        else string-join($overloads[1]/d:parameter[@direction = $arguments] ! (@name || ': ' || py:type(@type)), ', ')"/>
    <xsl:sequence select="if ($params) then ', ' || $params else ''"/>
  </xsl:function>

  <!-- ================================================================ base/<Monitor>.py -->
  <xsl:variable name="monitor-class" as="map(xs:string, xs:string)"
      select="map {'intercept': 'InterceptingMonitor', 'subscribe': 'SubscribingMonitor',
                   'poll': 'PollingMonitor', 'custom': 'Monitor'}"/>

  <!-- What the monitor acquires and how, in words (its classes' docstrings). -->
  <xsl:function name="py:acquires" as="xs:string">
    <xsl:param name="m" as="element()"/>
    <xsl:variable name="sources" select="string-join($m/d:source/@name, ', ')"/>
    <xsl:variable name="hz" select="if ($m/@frequency) then ' at ' || $m/@frequency || ' Hz' else ''"/>
    <xsl:sequence select="
      if ($m/@acquisition = 'intercept') then 'Intercepts the calls through ' || $sources || ' (and its property changes).'
      else if ($m/@acquisition = 'subscribe') then 'Subscribes to the context provider: the documents ' || $m/@xpath || ' selects something in.'
      else if ($m/@acquisition = 'poll') then 'Polls ' || $sources || '.' || $m/@operation || '()' || $hz || '.'
      else 'Acquires context with its own code' || (if ($hz) then ': acquire()' || $hz else '') || '.'"/>
  </xsl:function>

  <xsl:template match="d:monitor" mode="base">
    <xsl:variable name="base" select="$monitor-class(string(@acquisition))"/>
    <xsl:sequence select="py:header('monitor ''' || @name || ''' ('|| @qname || ', id ' || @id || ')', $regenerated)"/>
    <xsl:text>"""The generated base of monitor {@name}; its code is in ``monitors/{@name}.py``."""

from __future__ import annotations

from acordcs.runtime.api import {$base}


class {@name}Base({$base}):
    {py:doc(string-join((if (d:documentation) then string(d:documentation) else (),
        'Monitor ' || @name || ' (' || @qname || '). ' || py:acquires(.),
        'Feeds ' || string-join(d:feeds/@name, ', ') || ' with its attributes: '
        || string-join(for $p in d:property return $p/@name || ' (' || $p/@type || ')', ', ') || '.'),
        '&#10;&#10;'), '    ')}

    acquisition = {py:str(@acquisition)}
    attribute_defaults = {{</xsl:text>
    <xsl:choose>
      <xsl:when test="d:property">
        <xsl:text>&#10;</xsl:text>
        <xsl:for-each select="d:property">
          <xsl:text>        {py:str(@name)}: {py:value(.)},  # {py:escaped(@type, '[\p{C}\p{Zl}\p{Zp}]')}&#10;</xsl:text>
        </xsl:for-each>
        <xsl:text>    }}&#10;</xsl:text>
      </xsl:when>
      <xsl:otherwise>}}&#10;</xsl:otherwise>
    </xsl:choose>
  </xsl:template>

  <!-- ============================================================= monitors/<Monitor>.py -->
  <xsl:template match="d:monitor" mode="user">
    <xsl:param name="pkg" tunnel="yes"/>
    <xsl:variable name="attrs" select="string-join(d:property/@name, ', ')"/>
    <xsl:sequence select="py:header('monitor ''' || @name || ''' ('|| @qname || ', id ' || @id || ')', $yours)"/>
    <xsl:text>"""Monitor {@name}. {py:inline(py:acquires(.))}"""

from __future__ import annotations

from {$pkg}.base.{@name} import {@name}Base


class {@name}({@name}Base):
</xsl:text>
    <xsl:choose>
      <xsl:when test="@acquisition = 'intercept'">
        <xsl:text>    # Each call through its sources, once done, reaches on_call; return the new values of
    # {py:inline($attrs)} (a dict), or None:
    #   def on_call(self, call):  # call.operation, .args, .kwargs, .result, .error, .time
    # A source's property change reaches on_change(self, attribute, value): by default a
    # property named like one of the attributes is taken as it is.
</xsl:text>
      </xsl:when>
      <xsl:when test="@acquisition = 'subscribe'">
        <xsl:text>    # Each document its xpath selects something in reaches on_document; by default each of
    # {py:inline($attrs)} is read from the first selected element's child (or attribute) of
    # that name, converted to its type. To read otherwise:
    #   def on_document(self, note):  # note.nodes, .document, .publisher, .seq
</xsl:text>
      </xsl:when>
      <xsl:when test="@acquisition = 'poll'">
        <xsl:text>    # What the polled operation returns reaches on_reading; by default it is the value of
    # the only attribute, or a dict of some of {py:inline($attrs)}. To read otherwise:
    #   def on_reading(self, value):
</xsl:text>
      </xsl:when>
      <xsl:otherwise>
        <xsl:text>    # Your acquisition: acquire(self) is called at the monitor's frequency (if it has one) and
    # returns new values of {py:inline($attrs)}; on_event(self, event) sees its sources' calls
    # and property changes; self.update(name=value) publishes at any time.
</xsl:text>
      </xsl:otherwise>
    </xsl:choose>
    <xsl:text>    pass&#10;</xsl:text>
  </xsl:template>

  <!-- ============================================================== model_types.py -->
  <xsl:template name="model-types">
    <xsl:param name="app" as="element()"/>
    <xsl:variable name="aliases" select="map:get($plan, 'aliases')"/>
    <xsl:sequence select="py:header('model ''' || $app/@name || '''', $regenerated)"/>
    <xsl:text>"""The model's types that are not Python's, named for the signatures of ``{$package}.base``.

A UML type int, integer, long or short is ``int``; double, float, real or number ``float``; bool
or boolean ``bool``; string ``str``. Any other type is ``object`` (named here when its name can be
a Python name): the runtime passes whatever the caller gives, in-process the object itself,
through a remote connector what Pyro5's serializer makes of it (bytes arrive as a dict:
``serpent.tobytes``), so check it with ``isinstance`` where you use it.
"""

import typing as _typing
</xsl:text>
    <xsl:for-each select="sort(map:keys($aliases))">
      <xsl:text>
{.}: _typing.TypeAlias = object
{py:doc('UML type ' || . || ', in ' || string-join(array:flatten($aliases(.)), ', ') || '.', '')}
</xsl:text>
    </xsl:for-each>
  </xsl:template>

  <!-- ================================================================= <Container>.py -->
  <xsl:template match="d:container" mode="container">
    <xsl:param name="pkg" tunnel="yes"/>
    <xsl:variable name="hosted" select="string-join(for $h in d:hosts return replace($h/@kind, '-', ' ') || ' ' || $h/@name, ', ')"/>
    <xsl:sequence select="py:header('container ''' || @name || ''' ('|| @qname || ', id ' || @id || ')', $regenerated)"/>
    <xsl:text>{py:doc(string-join((
    'Container ' || @name || ' of application ' || /d:application/@name || ', on host ' || @host || '.',
    string(d:documentation)[. ne ''],
    'Hosts: ' || (if ($hosted) then $hosted else 'nothing') || '.',
    'Run it: python -m ' || $pkg || '.' || @name || ' [--clock virtual|real] [--serve PORT] [--remote NAME=URI]...',
    '(--help: every option and the exit status; acordcs.runtime.launcher runs it).'), '&#10;&#10;'), '')}

from __future__ import annotations

import sys

from acordcs.runtime.launcher import Launcher

CONTAINER = {py:str(@name)}
LAUNCHER = Launcher({py:str($pkg)}, CONTAINER)
# The container assembled from the descriptor: assemble_container(clock, remote, remote_timeout).
assemble_container = LAUNCHER.assemble

if __name__ == "__main__":
    sys.exit(LAUNCHER.main())
</xsl:text>
  </xsl:template>
</xsl:stylesheet>
