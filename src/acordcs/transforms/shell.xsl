<?xml version="1.0" encoding="UTF-8"?>
<!--
  Target "shell" of acordcs-gen: POSIX sh scripts running the python target's package, one process
  per container (see shell.py, which checks the model's names before this stylesheet runs: the
  application's and containers' names are ASCII identifiers, so they are written as they are).

    bin/env.sh             sourced by every script: the settings (the user's lines in protected
                           regions), then the functions the scripts share and the checks of the
                           settings, the run directory and the token
    bin/<C>-start          starts container C in the background, waits until it serves
    bin/<C>-stop           stops it (only a process that runs it)
    bin/<C>-status         says whether it runs, and how it ended when it does not
    bin/start-all, bin/stop-all
    bin/start-host HOST, bin/stop-host HOST   the containers of one host (shell-hosts.xsl)
    bin/console            the browser console attached to the running application
                           (python -m acordcs.cli console: acordcs-gen console)

  Every model string that reaches shell code goes through sh:quote; comments go through
  sh:comment (line breaks and other control characters escaped, so a model string cannot start a
  line). The shell text is in CDATA sections: what is between them comes from the descriptor.
  The functions the scripts share are in shell-functions.xsl (included).
-->
<xsl:stylesheet version="3.0"
    xmlns:xsl="http://www.w3.org/1999/XSL/Transform"
    xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:d="http://acordcs.org/descriptor/1.0"
    xmlns:sh="http://acordcs.org/codegen/sh"
    xmlns="http://acordcs.org/codegen/1.0"
    exclude-result-prefixes="xs d sh">

  <xsl:param name="source-file" as="xs:string" required="yes"/>
  <xsl:param name="generator" as="xs:string" required="yes"/>
  <xsl:param name="target" as="xs:string" required="yes"/>
  <xsl:param name="descriptor-schema" as="xs:string" required="yes"/>
  <!-- The python target's package (python.py's package_name). -->
  <xsl:param name="package" as="xs:string" required="yes"/>
  <!-- The interpreter that ran the build (sys.executable): the scripts' default PYTHON. -->
  <xsl:param name="python" as="xs:string" required="yes"/>
  <!-- The protected region key of each container (acordcs/generator/regions.py's key of its id),
       blank-separated, in the descriptor's order. -->
  <xsl:param name="region-keys" as="xs:string" required="yes"/>

  <xsl:output method="xml" encoding="UTF-8" indent="no"/>

  <!-- The sh functions the scripts share, written into env.sh: the named template "functions". -->
  <xsl:include href="shell-functions.xsl"/>
  <!-- bin/start-host and bin/stop-host: the named template "host-script". -->
  <xsl:include href="shell-hosts.xsl"/>

  <!-- The default of ACORDCS_PORT_BASE: container number i (1, 2, ... in the descriptor's order)
       serves at ACORDCS_PORT_BASE + i unless the model gives it a port (tag port). -->
  <xsl:variable name="port-base" select="47010"/>
  <xsl:variable name="nl" select="'&#10;'"/>

  <!-- ====================================================================== quoting -->

  <!-- $s as one sh word that is exactly $s: in single quotes, each ' written '\''. A line break
       (any character that ends a line for a reader: control characters, U+2028, U+2029) is
       followed by '' (the quotes closed and opened again: the same word), so that no line of a
       script starts with text from the model: a model string cannot forge a region marker.
       A NUL, which no shell word can hold, never arrives: an XPath string holds XML characters
       only, and the descriptor's writer refuses a NUL in the model (to_xml). -->
  <xsl:function name="sh:quote" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:variable name="quoted" select="replace($s, '''', '''\\''''')"/>
    <xsl:sequence select="'''' || replace($quoted, '([\p{Cc}\p{Zl}\p{Zp}])', '$1''''') || ''''"/>
  </xsl:function>

  <!-- $s on one line, as acordcs/generator/headers.py's clean: control, format and line-separator
       characters written \uXXXX. -->
  <xsl:function name="sh:clean" as="xs:string">
    <xsl:param name="s" as="xs:string"/>
    <xsl:variable name="parts" as="xs:string*">
      <xsl:analyze-string select="$s" regex="[\p{{Cc}}\p{{Cf}}\p{{Zl}}\p{{Zp}}]">
        <xsl:matching-substring>
          <xsl:sequence select="'\u' || sh:hex(string-to-codepoints(.))"/>
        </xsl:matching-substring>
        <xsl:non-matching-substring>
          <xsl:sequence select="."/>
        </xsl:non-matching-substring>
      </xsl:analyze-string>
    </xsl:variable>
    <xsl:sequence select="string-join($parts)"/>
  </xsl:function>

  <!-- $n in lower-case hexadecimal, at least 4 digits. -->
  <xsl:function name="sh:hex" as="xs:string">
    <xsl:param name="n" as="xs:integer"/>
    <xsl:variable name="digits" select="sh:hex-digits($n)"/>
    <xsl:sequence select="string-join((for $i in 1 to 4 - string-length($digits) return '0', $digits))"/>
  </xsl:function>

  <xsl:function name="sh:hex-digits" as="xs:string">
    <xsl:param name="n" as="xs:integer"/>
    <xsl:variable name="digit" select="substring('0123456789abcdef', $n mod 16 + 1, 1)"/>
    <xsl:sequence select="if ($n lt 16) then $digit else sh:hex-digits($n idiv 16) || $digit"/>
  </xsl:function>

  <!-- $lines as '#' comment lines, each cleaned. -->
  <xsl:function name="sh:comment" as="xs:string">
    <xsl:param name="lines" as="xs:string*"/>
    <xsl:sequence select="string-join(for $l in $lines return '# ' || sh:clean($l), $nl) || $nl"/>
  </xsl:function>

  <!-- The header of a file, as acordcs/generator/headers.py's header_lines writes it. -->
  <xsl:function name="sh:header" as="xs:string">
    <xsl:param name="what" as="xs:string"/>
    <xsl:param name="notes" as="xs:string*"/>
    <xsl:sequence select="sh:comment((
        'Generated by ' || $generator || ' (target ' || $target || ') from ' || $what,
        'in model file ' || $source-file || '. Do not edit: rebuild with acordcs-gen build.',
        $notes))"/>
  </xsl:function>

  <xsl:function name="sh:what" as="xs:string">
    <xsl:param name="c" as="element(d:container)"/>
    <xsl:sequence select="'container ''' || $c/@name || ''' (' || $c/@qname || ', id ' || $c/@id || ')'"/>
  </xsl:function>

  <!-- ======================================================================== the files -->

  <xsl:template match="/">
    <xsl:variable name="app" select="d:application"/>
    <xsl:if test="not($app)">
      <xsl:message terminate="yes">the input is not an application descriptor (no d:application element)</xsl:message>
    </xsl:if>
    <xsl:variable name="containers" select="$app/d:containers/d:container"/>
    <xsl:variable name="keys" select="tokenize($region-keys)"/>
    <xsl:if test="count($keys) ne count($containers)">
      <xsl:message terminate="yes" select="'region-keys has ' || count($keys) || ' keys for ' || count($containers) || ' containers'"/>
    </xsl:if>
    <xsl:variable name="all-ids" select="string-join($containers/@id, ' ')"/>

    <xsl:result-document href="bin/env.sh" method="text" encoding="UTF-8">
      <xsl:call-template name="env">
        <xsl:with-param name="app" select="$app"/>
        <xsl:with-param name="keys" select="$keys"/>
      </xsl:call-template>
    </xsl:result-document>
    <xsl:for-each select="$containers">
      <xsl:result-document href="bin/{@name}-start" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="start"/>
      </xsl:result-document>
      <xsl:result-document href="bin/{@name}-stop" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="stop"/>
      </xsl:result-document>
      <xsl:result-document href="bin/{@name}-status" method="text" encoding="UTF-8">
        <xsl:apply-templates select="." mode="status"/>
      </xsl:result-document>
    </xsl:for-each>
    <xsl:for-each select="('start', 'stop')">
      <xsl:variable name="verb" select="."/>
      <xsl:result-document href="bin/{$verb}-all" method="text" encoding="UTF-8">
        <xsl:call-template name="all">
          <xsl:with-param name="app" select="$app"/>
          <xsl:with-param name="verb" select="$verb"/>
        </xsl:call-template>
      </xsl:result-document>
      <xsl:result-document href="bin/{$verb}-host" method="text" encoding="UTF-8">
        <xsl:call-template name="host-script">
          <xsl:with-param name="app" select="$app"/>
          <xsl:with-param name="verb" select="$verb"/>
        </xsl:call-template>
      </xsl:result-document>
    </xsl:for-each>

    <xsl:result-document href="bin/console" method="text" encoding="UTF-8">
      <xsl:call-template name="console">
        <xsl:with-param name="app" select="$app"/>
      </xsl:call-template>
    </xsl:result-document>

    <files>
      <file path="bin/env.sh" element="{$app/@name}" ids="{$all-ids}" regions="hash"/>
      <xsl:for-each select="$containers">
        <file path="bin/{@name}-start" element="{@qname}" ids="{@id}" executable="yes"/>
        <file path="bin/{@name}-stop" element="{@qname}" ids="{@id}" executable="yes"/>
        <file path="bin/{@name}-status" element="{@qname}" ids="{@id}" executable="yes"/>
      </xsl:for-each>
      <file path="bin/start-all" element="{$app/@name}" ids="{$all-ids}" executable="yes"/>
      <file path="bin/stop-all" element="{$app/@name}" ids="{$all-ids}" executable="yes"/>
      <file path="bin/start-host" element="{$app/@name}" ids="{$all-ids}" executable="yes"/>
      <file path="bin/stop-host" element="{$app/@name}" ids="{$all-ids}" executable="yes"/>
      <file path="bin/console" element="{$app/@name}" ids="{$all-ids}" executable="yes"/>
    </files>
  </xsl:template>

  <!-- ========================================================================= env.sh -->

  <xsl:template name="env">
    <xsl:param name="app" as="element(d:application)"/>
    <xsl:param name="keys" as="xs:string*"/>
    <xsl:variable name="containers" select="$app/d:containers/d:container"/>
    <xsl:value-of select="sh:header('application ''' || $app/@name || '''', (
        'Sourced by the scripts of this directory. Your lines go between BEGIN USER and END USER: kept by every build.',
        'The scripts run the interpreter named in the application region below: the one that ran the first build (PYTHON overrides it).'))"/>
    <xsl:text><![CDATA[# A variable already set in the environment wins over the defaults below
# (ACORDCS_PORT_BASE=48000 bin/start-all); set one in a region to change its default.
# shellcheck disable=SC2034,SC2154  # used by the scripts sourcing it, which set $bin

# BEGIN USER application
# The interpreter the scripts run unless PYTHON is set: the one that ran the first build, kept
# here as your line (a build by another interpreter, or on another machine, leaves it as it is).
[ -n "${PYTHON-}" ] || PYTHON=]]></xsl:text>
    <xsl:value-of select="sh:quote($python)"/>
    <xsl:text><![CDATA[
# END USER application

[ -n "${PYTHON-}" ] || PYTHON=python3
# The directory holding the package ]]></xsl:text>
    <xsl:value-of select="$package"/>
    <xsl:text><![CDATA[/ (this file's parent directory).
ACORDCS_HOME=$(CDPATH='' cd -- "$bin/.." && pwd) || exit 1
PYTHONPATH=$ACORDCS_HOME${PYTHONPATH:+:$PYTHONPATH}
export PYTHONPATH
ACORDCS_PACKAGE=]]></xsl:text>
    <xsl:value-of select="$package"/>
    <xsl:text><![CDATA[
# The run directory: pid files, logs, exit files and the token. Empty: $XDG_RUNTIME_DIR (else
# $TMPDIR, else /tmp)/acordcs-<your user id>/$ACORDCS_PACKAGE. Made mode 0700 when missing;
# refused unless it is a directory of yours (not a symbolic link) that no one else can write.
ACORDCS_RUN_DIR=${ACORDCS_RUN_DIR-}
# python -m $ACORDCS_PACKAGE.<Container> options: --clock virtual|real, --duration SECONDS
# (empty: until stopped), --timeout SECONDS (remote calls).
[ -n "${ACORDCS_CLOCK-}" ] || ACORDCS_CLOCK=real
ACORDCS_DURATION=${ACORDCS_DURATION-}
[ -n "${ACORDCS_TIMEOUT-}" ] || ACORDCS_TIMEOUT=5
# Whole seconds a start waits for the container to serve, and a stop after TERM before KILL.
[ -n "${ACORDCS_START_TIMEOUT-}" ] || ACORDCS_START_TIMEOUT=30
[ -n "${ACORDCS_STOP_TIMEOUT-}" ] || ACORDCS_STOP_TIMEOUT=10
[ -n "${ACORDCS_PORT_BASE-}" ] || ACORDCS_PORT_BASE=]]></xsl:text>
    <xsl:value-of select="$port-base"/>
    <xsl:text>&#10;</xsl:text>
    <xsl:for-each select="$containers">
      <xsl:variable name="n" select="position()"/>
      <xsl:variable name="v" select="'ACORDCS_' || @name"/>
      <xsl:text>&#10;</xsl:text>
      <xsl:value-of select="sh:comment('Container ' || @name || ' (' || @qname || ', id ' || @id || ')')"/>
      <xsl:value-of select="'# BEGIN USER ' || $keys[$n] || $nl || '# END USER ' || $keys[$n] || $nl"/>
      <xsl:value-of select="'[ -n &quot;${' || $v || '_HOST-}&quot; ] || ' || $v || '_HOST=' || sh:quote(@host) || $nl"/>
      <xsl:choose>
        <xsl:when test="d:endpoint/@port">
          <xsl:value-of select="'[ -n &quot;${' || $v || '_PORT-}&quot; ] || ' || $v || '_PORT=' || xs:integer(d:endpoint/@port) || '  # the model''s tag port' || $nl"/>
        </xsl:when>
        <xsl:otherwise>
          <xsl:value-of select="'# Its port (empty: ACORDCS_PORT_BASE + ' || $n || ').' || $nl || $v || '_PORT=${' || $v || '_PORT-}' || $nl"/>
        </xsl:otherwise>
      </xsl:choose>
      <xsl:text># Operations to call once it serves, COMPONENT.OPERATION or COMPONENT.OPERATION(ARGUMENTS),&#10;# blank-separated (--run; no blank inside the arguments: Display.show('hi',2)).&#10;</xsl:text>
      <xsl:value-of select="$v || '_RUN=${' || $v || '_RUN-}' || $nl"/>
    </xsl:for-each>
    <xsl:call-template name="functions"/>
    <xsl:text><![CDATA[
# The settings, checked: a refused one stops the script, saying what to do (exit 2; -status: 4).
case $ACORDCS_CLOCK in real | virtual) ;; *) acordcs_refuse "ACORDCS_CLOCK is '$ACORDCS_CLOCK': set it to real or virtual" ;; esac
[ -z "$ACORDCS_DURATION" ] || acordcs_seconds ACORDCS_DURATION "$ACORDCS_DURATION"
acordcs_seconds ACORDCS_TIMEOUT "$ACORDCS_TIMEOUT"
acordcs_whole ACORDCS_START_TIMEOUT "$ACORDCS_START_TIMEOUT" 1 86400
acordcs_whole ACORDCS_STOP_TIMEOUT "$ACORDCS_STOP_TIMEOUT" 0 86400
acordcs_whole ACORDCS_PORT_BASE "$ACORDCS_PORT_BASE" 0 65535
]]></xsl:text>
    <xsl:for-each select="$containers">
      <xsl:variable name="v" select="'ACORDCS_' || @name || '_PORT'"/>
      <xsl:if test="not(d:endpoint/@port)">
        <xsl:value-of select="'[ -n &quot;$' || $v || '&quot; ] || ' || $v || '=$((ACORDCS_PORT_BASE + ' || position() || '))' || $nl"/>
      </xsl:if>
      <xsl:value-of select="'acordcs_whole ' || $v || ' &quot;$' || $v || '&quot; 1 65535' || $nl"/>
    </xsl:for-each>
    <xsl:text><![CDATA[acordcs_run_dir
acordcs_token
export ACORDCS_TOKEN
]]></xsl:text>
  </xsl:template>

  <!-- ======================================================================== scripts -->

  <!-- The lines every script starts with after its header: $bin, env.sh sourced. -->
  <xsl:template name="prologue">
    <xsl:param name="usage" as="xs:string" select="''"/>
    <xsl:text>set -u&#10;</xsl:text>
    <xsl:if test="$usage">
      <xsl:value-of select="'acordcs_usage=' || $usage || $nl"/>
    </xsl:if>
    <xsl:text><![CDATA[bin=$(CDPATH='' cd -- "$(dirname -- "$0")" && pwd) || exit 1
# shellcheck source=env.sh
. "$bin/env.sh"
]]></xsl:text>
  </xsl:template>

  <xsl:template match="d:container" mode="start">
    <xsl:text>#!/bin/sh&#10;</xsl:text>
    <xsl:value-of select="sh:header(sh:what(.),
        'Starts it in the background: python -m ' || $package || '.' || @name || ', its pid in $ACORDCS_RUN_DIR/' || @name
        || '.pid, its output in $ACORDCS_RUN_DIR/' || @name || '.log, how it ended in $ACORDCS_RUN_DIR/' || @name
        || '.exit; waits until it serves (at most $ACORDCS_START_TIMEOUT s). Arguments are added to the module''s options. '
        || 'Exit: 0 started and serving, 1 it stopped during its start-up (the end of its log is shown) or did not serve in time, '
        || '2 already running or a setting refused.')"/>
    <xsl:call-template name="prologue"/>
    <!-- @C@ stands for the container's name (an identifier) in these texts. -->
    <xsl:variable name="checked" as="xs:string">
      <xsl:text><![CDATA[if acordcs_pid @C@ clean; then
    echo "@C@: already running (pid $pid, $ACORDCS_RUN_DIR/@C@.pid): not started; stop it first with $bin/@C@-stop" >&2
    exit 2
fi
set -- --clock "$ACORDCS_CLOCK" --serve "$ACORDCS_@C@_PORT" --host "$ACORDCS_@C@_HOST" \
]]></xsl:text>
    </xsl:variable>
    <xsl:value-of select="replace($checked, '@C@', @name)"/>
    <xsl:variable name="all" select="../d:container"/>
    <xsl:for-each select="d:reaches">
      <xsl:variable name="o" select="$all[@name = current()/@name]"/>
      <xsl:variable name="object" select="($o/d:endpoint/@object, 'acordcs.container.' || @name)[1]"/>
      <xsl:value-of select="'    --remote ' || sh:quote(@name || '=PYRO:' || $object || '@') || '&quot;$ACORDCS_' || @name || '_HOST:$ACORDCS_' || @name || '_PORT&quot; \' || $nl"/>
    </xsl:for-each>
    <xsl:variable name="started" as="xs:string">
      <xsl:text><![CDATA[    --timeout "$ACORDCS_TIMEOUT" "$@"
if [ -n "$ACORDCS_DURATION" ]; then set -- --duration "$ACORDCS_DURATION" "$@"; fi
# ACORDCS_@C@_RUN: operations to call once it serves (--run), blank-separated (not globbed).
set -f
for op in $ACORDCS_@C@_RUN; do set -- "$@" --run "$op"; done
set +f
acordcs_start @C@ "$@"
]]></xsl:text>
    </xsl:variable>
    <xsl:value-of select="replace($started, '@C@', @name)"/>
  </xsl:template>

  <xsl:template match="d:container" mode="stop">
    <xsl:text>#!/bin/sh&#10;</xsl:text>
    <xsl:value-of select="sh:header(sh:what(.),
        'Stops it: TERM, then KILL after $ACORDCS_STOP_TIMEOUT seconds, to the process its pid file names only when that '
        || 'process runs it (its command line has -m ' || $package || '.' || @name || ' --exit-file $ACORDCS_RUN_DIR/' || @name
        || '.exit); a pid file naming anything else is reported and removed, never signalled. '
        || 'Exit: 0 stopped or not running, 1 still running after KILL, 2 a setting refused.')"/>
    <xsl:call-template name="prologue"/>
    <xsl:value-of select="'acordcs_stop ' || @name || $nl"/>
  </xsl:template>

  <xsl:template match="d:container" mode="status">
    <xsl:text>#!/bin/sh&#10;</xsl:text>
    <xsl:value-of select="sh:header(sh:what(.),
        'Says whether it runs and, when not, how it ended ($ACORDCS_RUN_DIR/' || @name || '.exit). Exit (LSB): 0 running; '
        || '3 not running (never started, or it stopped with exit 0 and no fault); 1 not running after a failure (another '
        || 'exit code, faults, killed, or gone without saying how); 4 unknown (an unreadable exit file, a setting refused).')"/>
    <xsl:call-template name="prologue">
      <xsl:with-param name="usage" select="'4'"/>
    </xsl:call-template>
    <xsl:value-of select="'acordcs_status ' || @name || $nl"/>
  </xsl:template>

  <!-- ===================================================================== start-all, stop-all -->

  <xsl:template name="all">
    <xsl:param name="app" as="element(d:application)"/>
    <xsl:param name="verb" as="xs:string"/>
    <xsl:variable name="containers" select="$app/d:containers/d:container"/>
    <xsl:text>#!/bin/sh&#10;</xsl:text>
    <xsl:value-of select="sh:header('application ''' || $app/@name || '''',
        if ($verb = 'start') then 'Starts every container (arguments go to each). Exit 0 when all started.'
        else 'Stops every container. Exit 0 when all stopped.')"/>
    <xsl:text><![CDATA[set -u
bin=$(CDPATH='' cd -- "$(dirname -- "$0")" && pwd) || exit 1
status=0
]]></xsl:text>
    <xsl:for-each select="if ($verb = 'start') then $containers else reverse($containers)">
      <xsl:value-of select="'sh &quot;$bin/' || @name || '-' || $verb || '&quot;' || (if ($verb = 'start') then ' &quot;$@&quot;' else '') || ' || status=1' || $nl"/>
    </xsl:for-each>
    <xsl:text>exit $status&#10;</xsl:text>
  </xsl:template>

  <!-- ========================================================================== console -->

  <xsl:template name="console">
    <xsl:param name="app" as="element(d:application)"/>
    <xsl:text>#!/bin/sh&#10;</xsl:text>
    <xsl:value-of select="sh:header('application ''' || $app/@name || '''',
        'Serves the browser console of the running application on 127.0.0.1 (acordcs-gen console, run by $PYTHON: '
        || 'python -m acordcs.cli console), found as these scripts find it; prints its link, runs until Ctrl-C. '
        || 'Arguments go to it (--model FILE, --port N: acordcs-gen console --help). '
        || 'Exit: 0 stopped by Ctrl-C, 2 a container does not answer or a setting refused.')"/>
    <xsl:call-template name="prologue"/>
    <xsl:text><![CDATA[exec "$PYTHON" -m acordcs.cli console "$ACORDCS_HOME" "$@"
]]></xsl:text>
  </xsl:template>
</xsl:stylesheet>
