<?xml version="1.0" encoding="UTF-8"?>
<!--
  Target "java" of acordcs-gen: Java sources of the application's components (paper, section 3:
  components inherit from CtxComponent), as a generation gap.

  - java/org/acordcs/runtime/{CtxComponent,Port,RuleEngine}.java: the small Java API the
    generated classes compile against (copied from java-api/ beside this stylesheet);
  - per component (every component, whatever its language tag), in package P (the application's
    name made a Java package name, see j:package):
      java/P/<C>Base.java: always regenerated: the properties as typed fields with the model's
        defaults (protected), getters and setters (except those the model declares as
        operations: abstract like every operation), the ports, the operations as abstract methods, the
        property methods of CtxComponent, the UML comments as Javadoc;
      java/P/<C>.java: the user's subclass, listed with once="true": created when missing,
        never overwritten nor deleted by a build.

  Every string of the model reaches the Java source escaped: in string literals (j:string) quotes,
  backslashes and control characters are escaped and every non-ASCII character is a \uXXXX
  escape; in comments (j:doc) backslashes, '*/', '<', '>', '&', '@' and control characters become
  HTML character references, so no Unicode escape or comment end can come from the model. Names
  become identifiers (j:ident). Generated code names every type fully qualified (java.lang.String,
  org.acordcs.runtime.Port): a component named String or Port changes nothing.
-->
<xsl:stylesheet version="3.0"
    xmlns:xsl="http://www.w3.org/1999/XSL/Transform"
    xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:d="http://acordcs.org/descriptor/1.0"
    xmlns:j="http://acordcs.org/codegen/java"
    xmlns="http://acordcs.org/codegen/1.0"
    exclude-result-prefixes="xs d j"
    expand-text="yes">

  <xsl:param name="source-file" as="xs:string" required="yes"/>
  <xsl:param name="generator" as="xs:string" required="yes"/>
  <xsl:param name="target" as="xs:string" required="yes"/>
  <xsl:param name="descriptor-schema" as="xs:string" required="yes"/>

  <xsl:output method="xml" encoding="UTF-8" indent="no"/>

  <xsl:variable name="j:nl" select="'&#10;'"/>
  <xsl:variable name="j:api" select="('CtxComponent', 'Port', 'RuleEngine')"/>

  <!-- Java's keywords and literals, its contextual keywords, and 'java' and 'org' (an identifier
       named so would obscure the packages of the fully qualified names the code uses). -->
  <xsl:variable name="j:keywords" as="xs:string*" select="(
    'abstract', 'assert', 'boolean', 'break', 'byte', 'case', 'catch', 'char', 'class', 'const',
    'continue', 'default', 'do', 'double', 'else', 'enum', 'extends', 'final', 'finally', 'float',
    'for', 'goto', 'if', 'implements', 'import', 'instanceof', 'int', 'interface', 'long', 'native',
    'new', 'package', 'private', 'protected', 'public', 'return', 'short', 'static', 'strictfp',
    'super', 'switch', 'synchronized', 'this', 'throw', 'throws', 'transient', 'try', 'void',
    'volatile', 'while', 'true', 'false', 'null', '_', 'var', 'record', 'yield', 'sealed',
    'permits', 'exports', 'module', 'open', 'opens', 'provides', 'requires', 'to', 'transitive',
    'uses', 'with', 'java', 'org')"/>

  <!-- Methods a generated method must not be named: Object's, and CtxComponent's. -->
  <xsl:variable name="j:taken-methods" as="xs:string*" select="(
    'getClass', 'notify', 'notifyAll', 'wait', 'hashCode', 'equals', 'toString', 'clone',
    'finalize', 'componentName', 'addPort', 'port', 'ports', 'propertyNames', 'propertyType',
    'getProperty', 'setProperty', 'asInt', 'asLong', 'asDouble', 'asBoolean', 'asString',
    'unknownProperty', 'attachHost', 'host', 'hostSet', 'ruleEngine', 'onStart', 'onStop',
    'onPropertyChanged', 'onMessage')"/>

  <!-- ============================================================ names -->

  <!-- A Java identifier: every character but ASCII letters, digits and '_' becomes '_'; '_' before
       a leading digit; '_' after a keyword (j:keywords). -->
  <xsl:function name="j:ident" as="xs:string">
    <xsl:param name="name" as="xs:string"/>
    <xsl:variable name="a" select="replace($name, '[^A-Za-z0-9_]', '_')"/>
    <xsl:variable name="b" select="if ($a = '') then '_' else if (matches($a, '^[0-9]')) then '_' || $a else $a"/>
    <xsl:sequence select="if ($b = $j:keywords) then $b || '_' else $b"/>
  </xsl:function>

  <!-- The application's package: its name in lower case made an identifier (one segment). -->
  <xsl:function name="j:package" as="xs:string">
    <xsl:param name="name" as="xs:string"/>
    <xsl:sequence select="j:ident(lower-case($name))"/>
  </xsl:function>

  <!-- A method name: an identifier, with '_' after a name Object or CtxComponent has. -->
  <xsl:function name="j:method" as="xs:string">
    <xsl:param name="name" as="xs:string"/>
    <xsl:variable name="i" select="j:ident($name)"/>
    <xsl:sequence select="if ($i = $j:taken-methods) then $i || '_' else $i"/>
  </xsl:function>

  <xsl:function name="j:accessor" as="xs:string">
    <xsl:param name="prefix" as="xs:string"/>
    <xsl:param name="name" as="xs:string"/>
    <xsl:variable name="i" select="j:ident($name)"/>
    <xsl:sequence select="j:method($prefix || upper-case(substring($i, 1, 1)) || substring($i, 2))"/>
  </xsl:function>

  <!-- ============================================================ types and values -->

  <!-- A property's Java type: by its kind; an int property is a long when its UML type is long
       or its default does not fit an int. -->
  <xsl:function name="j:property-type" as="xs:string">
    <xsl:param name="p" as="element()"/>
    <xsl:sequence select="
      if ($p/@kind = 'int')
        then (if (lower-case($p/@type) = 'long') then 'long'
              else if (not(matches($p/@default, '^-?[0-9]+$'))) then 'int'
              else if (xs:decimal($p/@default) gt 2147483647 or xs:decimal($p/@default) lt -2147483648) then 'long'
              else 'int')
      else if ($p/@kind = 'double') then 'double'
      else if ($p/@kind = 'bool') then 'boolean'
      else 'java.lang.String'"/>
  </xsl:function>

  <xsl:function name="j:boxed" as="xs:string">
    <xsl:param name="type" as="xs:string"/>
    <xsl:sequence select="
      if ($type = 'int') then 'java.lang.Integer' else if ($type = 'long') then 'java.lang.Long'
      else if ($type = 'double') then 'java.lang.Double' else if ($type = 'boolean') then 'java.lang.Boolean'
      else $type"/>
  </xsl:function>

  <xsl:function name="j:converter" as="xs:string">
    <xsl:param name="type" as="xs:string"/>
    <xsl:sequence select="
      if ($type = 'int') then 'asInt' else if ($type = 'long') then 'asLong'
      else if ($type = 'double') then 'asDouble' else if ($type = 'boolean') then 'asBoolean'
      else 'asString'"/>
  </xsl:function>

  <!-- An operation's parameter or return type: a UML type name mapped as the descriptor maps
       defaults (int/integer/short, long, double/float/real/number, bool/boolean, string); no type
       or void is void for a return; any other type is java.lang.Object. -->
  <xsl:function name="j:type" as="xs:string">
    <xsl:param name="uml" as="xs:string?"/>
    <xsl:param name="return" as="xs:boolean"/>
    <xsl:variable name="t" select="lower-case(normalize-space($uml))"/>
    <xsl:sequence select="
      if ($return and $t = ('', 'void')) then 'void'
      else if ($t = ('int', 'integer', 'short')) then 'int'
      else if ($t = 'long') then 'long'
      else if ($t = ('double', 'float', 'real', 'number')) then 'double'
      else if ($t = ('bool', 'boolean')) then 'boolean'
      else if ($t = 'string') then 'java.lang.String'
      else 'java.lang.Object'"/>
  </xsl:function>

  <!-- A property's default as a Java literal of its type. -->
  <xsl:function name="j:literal" as="xs:string">
    <xsl:param name="p" as="element()"/>
    <xsl:variable name="type" select="j:property-type($p)"/>
    <xsl:variable name="v" select="string($p/@default)"/>
    <xsl:choose>
      <xsl:when test="$type = ('int', 'long')">
        <xsl:if test="if (matches($v, '^-?[0-9]+$')) then abs(xs:decimal($v)) gt 9223372036854775807 else true()">
          <xsl:message terminate="yes">property {$p/@qname}: default {$v} is not a Java long</xsl:message>
        </xsl:if>
        <xsl:sequence select="if ($type = 'long') then $v || 'L' else $v"/>
      </xsl:when>
      <xsl:when test="$type = 'double'">
        <xsl:if test="not(matches($v, '^-?[0-9]+(\.[0-9]+)?([eE][+-]?[0-9]+)?$'))">
          <xsl:message terminate="yes">property {$p/@qname}: default {$v} is not a finite number</xsl:message>
        </xsl:if>
        <xsl:sequence select="if (matches($v, '[.eE]')) then $v else $v || '.0'"/>
      </xsl:when>
      <xsl:when test="$type = 'boolean'">
        <xsl:sequence select="if ($v = ('true', '1')) then 'true' else 'false'"/>
      </xsl:when>
      <xsl:otherwise>
        <xsl:sequence select="j:string($v)"/>
      </xsl:otherwise>
    </xsl:choose>
  </xsl:function>

  <!-- ============================================================ escaping -->

  <xsl:function name="j:hex4" as="xs:string">
    <xsl:param name="c" as="xs:integer"/>
    <xsl:sequence select="string-join(for $d in (4096, 256, 16, 1) return substring('0123456789abcdef', ($c idiv $d) mod 16 + 1, 1))"/>
  </xsl:function>

  <!-- A Unicode escape of $c (a surrogate pair above U+FFFF). -->
  <xsl:function name="j:uescape" as="xs:string">
    <xsl:param name="c" as="xs:integer"/>
    <xsl:sequence select="
      if ($c lt 65536) then '\u' || j:hex4($c)
      else '\u' || j:hex4(55296 + ($c - 65536) idiv 1024) || '\u' || j:hex4(56320 + ($c - 65536) mod 1024)"/>
  </xsl:function>

  <!-- A Java string literal holding $s: \\ \" \n \r \t, other controls as octal escapes (a
       Unicode escape of a line break would end the literal: javac reads those escapes first),
       every character above '~' as \uXXXX. The file stays ASCII. -->
  <!-- Strings needing no escape (the usual case, and the fast path): in a string literal,
       printable ASCII but '"' and '\'; in a comment, tab and printable ASCII but '\&<>@'. -->
  <xsl:variable name="j:plain-literal" as="xs:string">^[ !#-\[\]-~]*$</xsl:variable>
  <xsl:variable name="j:plain-comment" as="xs:string">^[\t -%'-;=?A-\[\]-~]*$</xsl:variable>

  <xsl:function name="j:string" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:sequence select="if (matches($s, $j:plain-literal)) then '&quot;' || $s || '&quot;' else
      '&quot;' || string-join(for $c in string-to-codepoints($s) return
      if ($c = 92) then '\\'
      else if ($c = 34) then '\&quot;'
      else if ($c = 10) then '\n'
      else if ($c = 13) then '\r'
      else if ($c = 9) then '\t'
      else if ($c lt 32 or $c = 127) then '\' || string-join(for $d in (64, 8, 1) return string(($c idiv $d) mod 8))
      else if ($c lt 127) then codepoints-to-string($c)
      else j:uescape($c)) || '&quot;'"/>
  </xsl:function>

  <!-- Text of one comment line: '\' '&' '<' '>' '@' and controls as HTML character references
       ('\' so that no Unicode escape reaches javac from the model), '*/' broken as '*&#47;',
       characters above '~' as \uXXXX (javac reads them as the character; none is a line break). -->
  <xsl:function name="j:doc" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:variable name="escaped" select="if (matches($s, $j:plain-comment)) then $s else string-join(for $c in string-to-codepoints($s) return
      if ($c = (92, 38, 60, 62, 64) or ($c lt 32 and $c ne 9) or $c = 127) then '&amp;#' || $c || ';'
      else if ($c lt 127) then codepoints-to-string($c)
      else j:uescape($c))"/>
    <xsl:sequence select="replace($escaped, '\*/', '*&amp;#47;')"/>
  </xsl:function>

  <!-- A Javadoc block: the lines of $text (documentation, then $notes), indented by $indent. -->
  <xsl:function name="j:javadoc" as="xs:string*">
    <xsl:param name="indent" as="xs:string"/>
    <xsl:param name="text" as="xs:string?"/>
    <xsl:param name="notes" as="xs:string*"/>
    <xsl:variable name="doc" select="if (normalize-space($text)) then tokenize($text, '\r\n|\r|\n') else ()"/>
    <xsl:variable name="lines" select="($doc ! j:doc(.), if (exists($doc) and exists($notes)) then '' else (), $notes)"/>
    <xsl:sequence select="
      if (empty($lines)) then ()
      else ($indent || '/**', $lines ! ($indent || (if (. = '') then ' *' else ' * ' || .)), $indent || ' */')"/>
  </xsl:function>

  <!-- {@code name} for Javadoc. -->
  <xsl:function name="j:code" as="xs:string">
    <xsl:param name="s" as="xs:string?"/>
    <xsl:sequence select="'{@code ' || j:doc(string($s)) || '}'"/>
  </xsl:function>

  <!-- ============================================================ files -->

  <xsl:template match="/">
    <xsl:variable name="app" select="d:application"/>
    <xsl:if test="not($app)">
      <xsl:message terminate="yes">the input is not an application descriptor (no d:application element)</xsl:message>
    </xsl:if>
    <xsl:variable name="package" select="j:package($app/@name)"/>
    <xsl:variable name="components" select="$app/d:components/d:component"/>
    <xsl:variable name="classes" select="$components ! (j:ident(@name), j:ident(@name) || 'Base')"/>
    <xsl:variable name="clashes" select="distinct-values($classes[index-of($classes ! lower-case(.), lower-case(.))[2]])"/>
    <xsl:if test="exists($clashes)">
      <xsl:message terminate="yes">Java class names of components would collide: {string-join($clashes, ', ')} (names differing only in case or in characters that are not letters, digits or _, or a component C beside one named CBase); rename the components</xsl:message>
    </xsl:if>

    <xsl:for-each select="$j:api">
      <xsl:result-document href="java/org/acordcs/runtime/{.}.java" method="text" encoding="US-ASCII">
        <xsl:value-of select="string-join(j:header('the ACORD-CS Java API (acordcs/transforms/java-api/' || . || '.java)', true()), $j:nl) || $j:nl"/>
        <xsl:value-of select="unparsed-text(resolve-uri('java-api/' || . || '.java', static-base-uri()), 'UTF-8')"/>
      </xsl:result-document>
    </xsl:for-each>

    <xsl:for-each select="$components">
      <xsl:variable name="class" select="j:ident(@name)"/>
      <xsl:result-document href="java/{$package}/{$class}Base.java" method="text" encoding="US-ASCII">
        <xsl:value-of select="string-join(j:base(., $package), $j:nl) || $j:nl"/>
      </xsl:result-document>
      <xsl:result-document href="java/{$package}/{$class}.java" method="text" encoding="US-ASCII">
        <xsl:value-of select="string-join(j:user(., $package), $j:nl) || $j:nl"/>
      </xsl:result-document>
    </xsl:for-each>

    <files>
      <xsl:for-each select="$j:api">
        <file path="java/org/acordcs/runtime/{.}.java" element="{$app/@name}" ids=""/>
      </xsl:for-each>
      <xsl:for-each select="$components">
        <xsl:variable name="class" select="j:ident(@name)"/>
        <xsl:variable name="ids" select="string-join(distinct-values(descendant-or-self::*/@id), ' ')"/>
        <file path="java/{$package}/{$class}Base.java" element="{@qname}" ids="{$ids}"/>
        <file path="java/{$package}/{$class}.java" element="{@qname}" ids="{@id}" once="true"/>
      </xsl:for-each>
    </files>
  </xsl:template>

  <!-- The header lines of a file: generated (do not edit), or the user's (created once). -->
  <xsl:function name="j:header" as="xs:string*">
    <xsl:param name="what" as="xs:string"/>
    <xsl:param name="generated" as="xs:boolean"/>
    <xsl:sequence select="
      '// ' || j:doc((if ($generated) then 'Generated' else 'Created') || ' by ' || $generator || ' (target ' || $target || ') from ' || $what),
      if ($generated) then '// in model file ' || j:doc($source-file) || '. Do not edit: rebuild with acordcs-gen build.'
      else '// in model file ' || j:doc($source-file) || '. Written once: yours to edit, never overwritten by a build.'"/>
  </xsl:function>

  <xsl:function name="j:what" as="xs:string">
    <xsl:param name="c" as="element(d:component)"/>
    <xsl:sequence select="'component ''' || $c/@name || ''' (' || $c/@qname || ', id ' || $c/@id || ')'"/>
  </xsl:function>

  <xsl:function name="j:parameters" as="xs:string">
    <xsl:param name="op" as="element(d:operation)"/>
    <xsl:sequence select="string-join($op/d:parameter ! (j:type(@type, false()) || ' ' || j:ident(@name)), ', ')"/>
  </xsl:function>

  <xsl:function name="j:signature" as="xs:string">
    <xsl:param name="op" as="element(d:operation)"/>
    <xsl:sequence select="j:type($op/@returns, true()) || ' ' || j:method($op/@name) || '(' || j:parameters($op) || ')'"/>
  </xsl:function>

  <!-- The generated base class of component $c. -->
  <xsl:function name="j:base" as="xs:string*">
    <xsl:param name="c" as="element(d:component)"/>
    <xsl:param name="package" as="xs:string"/>
    <xsl:variable name="class" select="j:ident($c/@name)"/>
    <xsl:variable name="props" select="$c/d:property"/>
    <xsl:variable name="ops" select="$c/d:operation"/>
    <xsl:variable name="ports" select="$c/d:port"/>
    <!-- collisions: fields, methods (name and parameter types), parameters of an operation -->
    <xsl:variable name="fields" select="($props, $ports) ! j:ident(@name)"/>
    <xsl:variable name="declared" select="$ops ! (j:method(@name) || '(' || string-join(d:parameter ! j:type(@type, false()), ',') || ')')"/>
    <xsl:variable name="getters" select="$props[not(j:accessor('get', @name) || '()' = $declared)]"/>
    <xsl:variable name="setters" select="$props[not(j:accessor('set', @name) || '(' || j:property-type(.) || ')' = $declared)]"/>
    <xsl:variable name="methods" select="(
      $getters ! (j:accessor('get', @name) || '()'),
      $setters ! (j:accessor('set', @name) || '(' || j:property-type(.) || ')'),
      $declared)"/>
    <xsl:variable name="clashes" select="(
      $fields[index-of($fields, .)[2]], $methods[index-of($methods, .)[2]],
      $ops ! (let $ps := d:parameter ! j:ident(@name) return $ps[index-of($ps, .)[2]]))"/>
    <xsl:if test="exists($clashes)">
      <xsl:message terminate="yes">component {$c/@qname}: Java names would collide: {string-join(distinct-values($clashes), ', ')} (names differing only in characters that are not letters, digits or _, a keyword and its name with _, or a property X beside an operation getX/setX); rename them</xsl:message>
    </xsl:if>
    <xsl:variable name="runtime" select="'org.acordcs.runtime.'"/>
    <xsl:sequence select="
      j:header(j:what($c), true()),
      '// Your code goes in ' || $class || '.java (the subclass: created once, never overwritten).',
      'package ' || $package || ';',
      '',
      j:javadoc('', $c/d:documentation, (
        'Generated base class of ' || j:code($c/@name) || ' (' || j:code($c/@qname) || ', id ' || j:code($c/@id) || ', language ' || j:code($c/@language) || ').',
        'Implement the operations in {@link ' || $class || '}.')),
      'public abstract class ' || $class || 'Base extends ' || $runtime || 'CtxComponent {',
      $ports ! (
        j:javadoc('    ', d:documentation, 'Port ' || j:code(@name) || ': ' || @kind || ', ' || @role || '.'),
        '    protected final ' || $runtime || 'Port ' || j:ident(@name) || ';',
        ''),
      $props ! (
        j:javadoc('    ', d:documentation, 'Property ' || j:code(@name) || ' (UML type ' || j:code(@type) || '), default ' || j:code(@default) || '.'),
        '    protected ' || j:property-type(.) || ' ' || j:ident(@name) || ' = ' || j:literal(.) || ';',
        ''),
      '    protected ' || $class || 'Base() {',
      '        super(' || j:string($c/@name) || ');',
      $ports ! ('        this.' || j:ident(@name) || ' = addPort(new ' || $runtime || 'Port(' || j:string(@name) || ', '
        || $runtime || 'Port.Kind.' || upper-case(@kind) || ', ' || $runtime || 'Port.Role.' || upper-case(@role) || '));'),
      '    }',
      $getters ! (
        '',
        '    /** The value of property ' || j:code(@name) || '. */',
        '    public ' || j:property-type(.) || ' ' || j:accessor('get', @name) || '() {',
        '        return this.' || j:ident(@name) || ';',
        '    }'),
      $setters ! (
        '',
        '    /** Sets property ' || j:code(@name) || ' (through the container when hosted: policies and monitors see it). */',
        '    public void ' || j:accessor('set', @name) || '(' || j:property-type(.) || ' value) {',
        '        if (!hostSet(' || j:string(@name) || ', value)) {',
        '            this.' || j:ident(@name) || ' = value;',
        '        }',
        '    }'),
      $ops ! (
        '',
        j:javadoc('    ', d:documentation, (
          'Operation ' || j:code(@qname) || '.',
          d:parameter ! ('@param ' || j:ident(@name) || ' ' || @direction || ', UML type ' || j:code(@type)),
          if (@returns) then '@return UML type ' || j:code(@returns) else ())),
        '    public abstract ' || j:signature(.) || ';'),
      '',
      '    @java.lang.Override',
      '    public final java.util.List&lt;java.lang.String&gt; propertyNames() {',
      '        return java.util.List.of(' || string-join($props ! j:string(@name), ', ') || ');',
      '    }',
      '',
      '    @java.lang.Override',
      '    public final java.lang.Class&lt;?&gt; propertyType(java.lang.String property) {',
      '        switch (property) {',
      $props ! ('            case ' || j:string(@name) || ': return ' || j:boxed(j:property-type(.)) || '.class;'),
      '            default: throw unknownProperty(componentName(), property);',
      '        }',
      '    }',
      '',
      '    @java.lang.Override',
      '    public final java.lang.Object getProperty(java.lang.String property) {',
      '        switch (property) {',
      $props ! ('            case ' || j:string(@name) || ': return this.' || j:ident(@name) || ';'),
      '            default: throw unknownProperty(componentName(), property);',
      '        }',
      '    }',
      '',
      '    @java.lang.Override',
      '    public final void setProperty(java.lang.String property, java.lang.Object value) {',
      '        switch (property) {',
      $props ! ('            case ' || j:string(@name) || ': this.' || j:ident(@name) || ' = '
        || j:converter(j:property-type(.)) || '(property, value); return;'),
      '            default: throw unknownProperty(componentName(), property);',
      '        }',
      '    }',
      '}'"/>
  </xsl:function>

  <!-- The user's subclass of component $c, created once: every operation a stub to fill in. -->
  <xsl:function name="j:user" as="xs:string*">
    <xsl:param name="c" as="element(d:component)"/>
    <xsl:param name="package" as="xs:string"/>
    <xsl:variable name="class" select="j:ident($c/@name)"/>
    <xsl:sequence select="
      j:header(j:what($c), false()),
      'package ' || $package || ';',
      '',
      '/** Component ' || j:code($c/@name) || ': its operations. Properties and ports are in {@link ' || $class || 'Base}. */',
      'public class ' || $class || ' extends ' || $class || 'Base {',
      j:required-ports($c),
      '    public ' || $class || '() {',
      '        super();',
      '    }',
      $c/d:operation ! (
        '',
        '    @java.lang.Override',
        '    public ' || j:signature(.) || ' {',
        '        throw new java.lang.UnsupportedOperationException(' || j:string($c/@name || '.' || @name) || ');',
        '    }'),
      '}'"/>
  </xsl:function>

  <!-- Comment lines of the user's subclass of component $c: its required ports, and what each
       reaches (the operations a call through a synchronous one runs, from the component it is
       connected to); none without required ports. The Java API makes no calls: the lines say so,
       and how the Python class calls them (acordcs.runtime.ports: Port.call). -->
  <xsl:function name="j:required-ports" as="xs:string*">
    <xsl:param name="c" as="element(d:component)"/>
    <xsl:variable name="app" select="$c/ancestor::d:application"/>
    <xsl:variable name="required" select="$c/d:port[@role = 'required']"/>
    <xsl:if test="$required">
      <xsl:sequence select="
        '    // Its required ports: a synchronous one calls as port(name).call(operation, arguments...)',
        '    // (the result boxed: a Double, Long, Boolean or String), an asynchronous one sends with',
        '    // port(name).notify(message), a stream one with push(item). What each reaches:'"/>
      <xsl:for-each select="$required">
        <xsl:variable name="port" select="."/>
        <xsl:variable name="links" select="$app/d:connections/d:connection[d:required/@ref = $port/@id]"/>
        <xsl:variable name="peers" select="string-join($links ! (d:provided/@component || '.' || d:provided/@port || ' (connection ' || @name || ')'), ', ')"/>
        <xsl:variable name="name" select="j:doc($port/@name || ' (' || $port/@kind || ')')"/>
        <xsl:choose>
          <xsl:when test="empty($links)">
            <xsl:sequence select="'    //   ' || $name || ': not connected in the model'"/>
          </xsl:when>
          <xsl:when test="$port/@kind = 'synchronous'">
            <xsl:variable name="provider" select="$app/d:components/d:component[@name = $links[1]/d:provided/@component]"/>
            <xsl:sequence select="'    //   ' || $name || ', to ' || j:doc($peers) || ':',
              if (empty($provider/d:operation)) then '    //     (no operation to call)' else (),
              $provider/d:operation ! ('    //     ' || j:signature(.))"/>
          </xsl:when>
          <xsl:otherwise>
            <xsl:sequence select="'    //   ' || $name || ', from ' || j:doc($peers) || ': receives what it sends'"/>
          </xsl:otherwise>
        </xsl:choose>
      </xsl:for-each>
      <xsl:sequence select="''"/>
    </xsl:if>
  </xsl:function>
</xsl:stylesheet>
