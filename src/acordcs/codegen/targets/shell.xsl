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

  Every model string that reaches shell code goes through sh:quote; comments go through
  sh:comment (line breaks and other control characters escaped, so a model string cannot start a
  line). The shell text is in CDATA sections: what is between them comes from the descriptor.
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
  <!-- The protected region key of each container (acordcs/codegen/regions.py's key of its id),
       blank-separated, in the descriptor's order. -->
  <xsl:param name="region-keys" as="xs:string" required="yes"/>

  <xsl:output method="xml" encoding="UTF-8" indent="no"/>

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

  <!-- $s on one line, as acordcs/codegen/headers.py's clean: control, format and line-separator
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

  <!-- The header of a file, as acordcs/codegen/headers.py's header_lines writes it. -->
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
    </xsl:for-each>

    <files>
      <file path="bin/env.sh" element="{$app/@name}" ids="{$all-ids}"/>
      <xsl:for-each select="$containers">
        <file path="bin/{@name}-start" element="{@qname}" ids="{@id}"/>
        <file path="bin/{@name}-stop" element="{@qname}" ids="{@id}"/>
        <file path="bin/{@name}-status" element="{@qname}" ids="{@id}"/>
      </xsl:for-each>
      <file path="bin/start-all" element="{$app/@name}" ids="{$all-ids}"/>
      <file path="bin/stop-all" element="{$app/@name}" ids="{$all-ids}"/>
    </files>
  </xsl:template>

  <!-- ========================================================================= env.sh -->

  <xsl:template name="env">
    <xsl:param name="app" as="element(d:application)"/>
    <xsl:param name="keys" as="xs:string*"/>
    <xsl:variable name="containers" select="$app/d:containers/d:container"/>
    <xsl:value-of select="sh:header('application ''' || $app/@name || '''', (
        'Sourced by the scripts of this directory. Your lines go between BEGIN USER and END USER: kept by every build.',
        'Interpreter: ' || $python || ', the one that ran the build (PYTHON overrides it).'))"/>
    <xsl:text><![CDATA[# A variable already set in the environment wins over the defaults below
# (ACORDCS_PORT_BASE=48000 bin/start-all); set one in a region to change its default.
# shellcheck disable=SC2034,SC2154  # used by the scripts sourcing it, which set $bin

# BEGIN USER application
# END USER application

[ -n "${PYTHON-}" ] || PYTHON=]]></xsl:text>
    <xsl:value-of select="sh:quote($python)"/>
    <xsl:text><![CDATA[
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
      <xsl:text># Operations to call once it serves, COMPONENT.OPERATION blank-separated (--run).&#10;</xsl:text>
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

  <!-- The functions the scripts share (in env.sh, after the settings). -->
  <xsl:template name="functions">
    <xsl:text><![CDATA[
# ------------------------------------------------------------------------------------------------
# What the scripts do with these settings: not yours to edit (your lines go in the regions above).
acordcs_uid=$(id -u) || exit 1
acordcs_nl='
'

# acordcs_refuse MESSAGE: MESSAGE on standard error, and the script stops: exit 2, or the code
# the script set in acordcs_usage (-status: 4, LSB's "status unknown").
acordcs_refuse() {
    printf '%s: %s\n' "${0##*/}" "$1" >&2
    exit "${acordcs_usage:-2}"
}

# acordcs_whole NAME VALUE MIN MAX: refused unless VALUE, the setting NAME, is a whole number from
# MIN to MAX in decimal digits, without sign or leading zero (sh reads 010 as octal).
acordcs_whole() {
    case $2 in
        '' | *[!0-9]* | 0?*)
            acordcs_refuse "$1 is '$2', not a whole number (decimal digits, no sign, no leading zero): set it to one from $3 to $4" ;;
    esac
    if [ "${#2}" -gt "${#4}" ] || [ "$2" -lt "$3" ] || [ "$2" -gt "$4" ]; then
        acordcs_refuse "$1 is $2, out of range: set it to a whole number from $3 to $4"
    fi
}

# acordcs_seconds NAME VALUE: refused unless VALUE, the setting NAME, is a positive number of
# seconds: digits, with a fraction or not (5, 2.5).
acordcs_seconds() {
    case $2 in
        '' | . | *[!0-9.]* | *.*.*)
            acordcs_refuse "$1 is '$2', not a number of seconds: set it to digits, with a fraction or not (5, 2.5)" ;;
        *[1-9]*) ;;
        *) acordcs_refuse "$1 is $2: set it to a number of seconds above 0" ;;
    esac
}

# acordcs_mode PATH: acordcs_perm and acordcs_owner, the permissions of PATH itself (a symbolic
# link is not followed) as ls -l writes them, and the user id of its owner; empty when PATH is
# not there.
acordcs_mode() {
    acordcs_perm='' acordcs_owner=''
    [ -e "$1" ] || [ -L "$1" ] || return 0
    read -r acordcs_perm _ acordcs_owner _ <<EOF
$(ls -ldn -- "$1" 2>/dev/null)
EOF
}

# acordcs_private DIR: DIR, made with mode 0700 when missing, must be a directory (not a symbolic
# link) that you own and no one else can write: a directory others can write lets them plant a
# token or forge pid files. Refused otherwise, saying what to do.
acordcs_private() {
    if [ ! -e "$1" ] && [ ! -L "$1" ]; then
        (umask 077 && mkdir -p -- "$1") ||
            acordcs_refuse "cannot make the run directory $1: set ACORDCS_RUN_DIR to a directory of yours"
    fi
    acordcs_mode "$1"
    case $acordcs_perm in
        d*) ;;
        l*) acordcs_refuse "the run directory $1 is a symbolic link: not used; set ACORDCS_RUN_DIR to the directory it names, if it is yours" ;;
        *) acordcs_refuse "the run directory $1 is not a directory: set ACORDCS_RUN_DIR to a directory of yours" ;;
    esac
    if [ "$acordcs_owner" != "$acordcs_uid" ]; then
        acordcs_refuse "the run directory $1 belongs to user id $acordcs_owner, not to you ($acordcs_uid): not used (its owner could plant a token or forge pid files); set ACORDCS_RUN_DIR to a directory of yours"
    fi
    case $acordcs_perm in
        d????-??-? | d????-??-?.) ;;
        d????-??-?+) acordcs_refuse "the run directory $1 has an access control list, which may let others write it: not used; remove it (setfacl -b) or set ACORDCS_RUN_DIR to another directory" ;;
        *) acordcs_refuse "the run directory $1 can be written by others ($acordcs_perm): not used (they could plant a token or forge pid files); make it yours alone (chmod go-w) or set ACORDCS_RUN_DIR to another directory" ;;
    esac
}

# acordcs_run_dir: ACORDCS_RUN_DIR checked (acordcs_private), or made when empty, and absolute.
acordcs_run_dir() {
    if [ -z "$ACORDCS_RUN_DIR" ]; then
        acordcs_base=/tmp
        case ${TMPDIR-} in /?*) acordcs_base=$TMPDIR ;; esac
        case ${XDG_RUNTIME_DIR-} in /?*) acordcs_base=$XDG_RUNTIME_DIR ;; esac
        acordcs_private "$acordcs_base/acordcs-$acordcs_uid"
        ACORDCS_RUN_DIR=$acordcs_base/acordcs-$acordcs_uid/$ACORDCS_PACKAGE
    fi
    case $ACORDCS_RUN_DIR in
        *"$acordcs_nl"*) acordcs_refuse "ACORDCS_RUN_DIR holds a line break: set it to a directory whose path has none" ;;
    esac
    acordcs_private "$ACORDCS_RUN_DIR"
    ACORDCS_RUN_DIR=$(CDPATH='' cd -- "$ACORDCS_RUN_DIR" && pwd) ||
        acordcs_refuse "cannot enter the run directory: set ACORDCS_RUN_DIR to a directory of yours"
}

# acordcs_token: ACORDCS_TOKEN when set, else the first line of $ACORDCS_RUN_DIR/token, made from
# 128 random bits when missing. The file is used only when it is a regular file of yours with
# mode 0600 (in the run directory, which only you can write): anything else may have been planted.
acordcs_token() {
    [ -z "${ACORDCS_TOKEN-}" ] || return 0
    acordcs_file=$ACORDCS_RUN_DIR/token
    if [ ! -e "$acordcs_file" ] && [ ! -L "$acordcs_file" ]; then
        # Made beside, then linked into place: two scripts starting at once read the same token.
        (umask 077 && od -An -tx1 -N16 /dev/urandom | tr -d ' \n' >"$acordcs_file.$$") &&
            { ln -- "$acordcs_file.$$" "$acordcs_file" 2>/dev/null || [ -e "$acordcs_file" ]; }
        acordcs_made=$?
        rm -f -- "$acordcs_file.$$"
        [ "$acordcs_made" = 0 ] || acordcs_refuse "cannot make the token file $acordcs_file: check the run directory, or set ACORDCS_TOKEN"
    fi
    acordcs_mode "$acordcs_file"
    case $acordcs_perm in
        -rw------- | -rw-------.) ;;
        *) acordcs_refuse "the token file $acordcs_file is not a regular file with mode 0600 (-rw-------) but $acordcs_perm: not used, it may have been planted; remove it (a new one is made) or set ACORDCS_TOKEN" ;;
    esac
    if [ "$acordcs_owner" != "$acordcs_uid" ]; then
        acordcs_refuse "the token file $acordcs_file belongs to user id $acordcs_owner, not to you ($acordcs_uid): not used; remove it (a new one is made) or set ACORDCS_TOKEN"
    fi
    ACORDCS_TOKEN=''
    IFS= read -r ACORDCS_TOKEN <"$acordcs_file" || :
    [ -n "$ACORDCS_TOKEN" ] || acordcs_refuse "the token file $acordcs_file is empty: remove it (a new one is made) or set ACORDCS_TOKEN"
}

# acordcs_nap: a tenth of a second (a second where sleep takes whole seconds only).
acordcs_nap() {
    sleep 0.1 2>/dev/null || sleep 1
}

# acordcs_alive PID: whether process PID exists and is not a zombie (its state, after the last
# ')' of /proc/PID/stat on Linux, else from ps).
acordcs_alive() {
    kill -0 "$1" 2>/dev/null || return 1
    if [ -r /proc/self/stat ]; then
        acordcs_state=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
        acordcs_state=${acordcs_state##*) }
    else
        acordcs_state=$(ps -o stat= -p "$1" 2>/dev/null)
    fi
    case $acordcs_state in Z* | X*) return 1 ;; esac
    return 0
}

# acordcs_runs PID NAME: whether process PID runs container NAME of this application from this run
# directory: its command line has -m $ACORDCS_PACKAGE.NAME and --exit-file
# $ACORDCS_RUN_DIR/NAME.exit, as -start gives them (Linux: /proc/PID/cmdline, argument by
# argument; elsewhere ps -o args=). A zombie has no command line: it does not run.
acordcs_runs() {
    if [ -r /proc/self/cmdline ]; then
        [ -r "/proc/$1/cmdline" ] || return 1
        tr '\000' '\n' <"/proc/$1/cmdline" 2>/dev/null |
            M=$ACORDCS_PACKAGE.$2 E=$ACORDCS_RUN_DIR/$2.exit awk '
                previous == "-m" && $0 == ENVIRON["M"] { m = 1 }
                previous == "--exit-file" && $0 == ENVIRON["E"] { e = 1 }
                { previous = $0 }
                END { exit !(m && e) }'
        return
    fi
    case " $(ps -o args= -p "$1" 2>/dev/null) " in
        *" -m $ACORDCS_PACKAGE.$2 --exit-file $ACORDCS_RUN_DIR/$2.exit "*) return 0 ;;
    esac
    return 1
}

# acordcs_pid NAME clean|keep: whether the pid file of container NAME names a process that runs
# it (acordcs_runs): pid is then its process id, else empty. A pid file that names no such process
# (not a process id: empty, text, 0, negative, too long; a process that ended; a process that does
# not run NAME) is never signalled: it is reported on standard error and, with clean, removed;
# acordcs_stale is then yes.
acordcs_pid() {
    pid='' acordcs_stale='' acordcs_why=''
    acordcs_file=$ACORDCS_RUN_DIR/$1.pid
    [ -e "$acordcs_file" ] || [ -L "$acordcs_file" ] || return 1
    acordcs_stale=yes
    if [ -L "$acordcs_file" ] || [ ! -f "$acordcs_file" ]; then
        acordcs_why="it is not a regular file"
    else
        acordcs_read=''
        IFS= read -r acordcs_read <"$acordcs_file" || :
        case $acordcs_read in
            '' | *[!0-9]* | 0* | ????????*)
                acordcs_why="it does not hold a process id (a positive whole number)" ;;
            *)
                if acordcs_runs "$acordcs_read" "$1"; then
                    pid=$acordcs_read acordcs_stale=''
                    return 0
                elif ps -p "$acordcs_read" >/dev/null 2>&1; then
                    acordcs_why="process $acordcs_read does not run $1 from this run directory (its command line lacks -m $ACORDCS_PACKAGE.$1 --exit-file $ACORDCS_RUN_DIR/$1.exit)"
                else
                    acordcs_why="no process $acordcs_read runs (it ended without removing its pid file)"
                fi ;;
        esac
    fi
    if [ "$2" = clean ]; then
        rm -f -- "$acordcs_file"
        echo "$1: pid file $acordcs_file not used: $acordcs_why; not signalled, removed" >&2
    else
        echo "$1: pid file $acordcs_file not used: $acordcs_why" >&2
    fi
    return 1
}

# acordcs_start NAME ARGUMENTS...: starts container NAME (python -m, with --exit-file and the
# ARGUMENTS) in the background, its pid in NAME.pid, its output appended to NAME.log; waits until
# its log says it serves (at most ACORDCS_START_TIMEOUT s). 0 serving; 1 it stopped before (the
# end of its log is shown) or did not serve in time (it still runs).
acordcs_start() {
    acordcs_name=$1
    shift
    acordcs_log=$ACORDCS_RUN_DIR/$acordcs_name.log
    acordcs_from=1
    if [ -f "$acordcs_log" ]; then acordcs_from=$(($(wc -c <"$acordcs_log") + 1)); fi
    rm -f -- "$ACORDCS_RUN_DIR/$acordcs_name.exit"
    nohup "$PYTHON" -m "$ACORDCS_PACKAGE.$acordcs_name" --exit-file "$ACORDCS_RUN_DIR/$acordcs_name.exit" \
        "$@" >>"$acordcs_log" 2>&1 </dev/null &
    pid=$!
    echo "$pid" >"$ACORDCS_RUN_DIR/$acordcs_name.pid"
    acordcs_ticks=$((ACORDCS_START_TIMEOUT * 10))
    until tail -c "+$acordcs_from" -- "$acordcs_log" 2>/dev/null | grep -q "^$acordcs_name: serving at "; do
        if ! acordcs_alive "$pid"; then
            rm -f -- "$ACORDCS_RUN_DIR/$acordcs_name.pid"
            echo "$acordcs_name: stopped before serving; the end of $acordcs_log:" >&2
            tail -c "+$acordcs_from" -- "$acordcs_log" | tail -n 20 >&2
            return 1
        fi
        if [ "$acordcs_ticks" -le 0 ]; then
            echo "$acordcs_name: not serving after $ACORDCS_START_TIMEOUT s (ACORDCS_START_TIMEOUT); it still runs (pid $pid): see $acordcs_log, stop it with $bin/$acordcs_name-stop" >&2
            return 1
        fi
        acordcs_nap
        acordcs_ticks=$((acordcs_ticks - 1))
    done
    echo "$acordcs_name: started (pid $pid, log $acordcs_log)"
}

# acordcs_stop NAME: TERM to the process running container NAME (acordcs_pid), KILL after
# ACORDCS_STOP_TIMEOUT s if it still runs it; its pid file removed. 0 stopped or not running;
# 1 it still runs after KILL.
acordcs_stop() {
    if ! acordcs_pid "$1" clean; then
        echo "$1: not running"
        return 0
    fi
    kill -TERM "$pid" 2>/dev/null || :
    acordcs_ticks=$((ACORDCS_STOP_TIMEOUT * 10))
    while acordcs_runs "$pid" "$1" && [ "$acordcs_ticks" -gt 0 ]; do
        acordcs_nap
        acordcs_ticks=$((acordcs_ticks - 1))
    done
    if acordcs_runs "$pid" "$1"; then
        kill -KILL "$pid" 2>/dev/null || :
        [ -e "$ACORDCS_RUN_DIR/$1.exit" ] || echo killed >"$ACORDCS_RUN_DIR/$1.exit"
        echo "$1: killed (pid $pid): it did not stop within $ACORDCS_STOP_TIMEOUT s of TERM"
        acordcs_ticks=50
        while acordcs_runs "$pid" "$1"; do
            if [ "$acordcs_ticks" -le 0 ]; then
                echo "$1: still running (pid $pid) 5 s after KILL" >&2
                return 1
            fi
            acordcs_nap
            acordcs_ticks=$((acordcs_ticks - 1))
        done
    fi
    rm -f -- "$ACORDCS_RUN_DIR/$1.pid"
    echo "$1: stopped (pid $pid)"
}

# acordcs_status NAME: whether container NAME runs; when not, how it ended, from NAME.exit (the
# line EXIT_CODE FAULTS the container writes at exit, or killed, written by -stop). Exit (LSB):
# 0 running; 3 not running (never started, or exit 0 and no fault); 1 not running after a failure
# (another exit code, faults, killed, or gone without an exit file while its pid file remains);
# 4 unknown (an exit file that does not read as one).
acordcs_status() {
    if acordcs_pid "$1" keep; then
        echo "$1: running (pid $pid)"
        return 0
    fi
    acordcs_file=$ACORDCS_RUN_DIR/$1.exit
    acordcs_log=$ACORDCS_RUN_DIR/$1.log
    if [ ! -e "$acordcs_file" ] && [ ! -L "$acordcs_file" ]; then
        if [ -n "$acordcs_stale" ]; then
            echo "$1: not running: it ended without saying how (no $acordcs_file: killed or crashed); see $acordcs_log"
            return 1
        fi
        echo "$1: not running"
        return 3
    fi
    acordcs_code='' acordcs_faults='' acordcs_more=''
    if [ -f "$acordcs_file" ] && [ ! -L "$acordcs_file" ]; then
        read -r acordcs_code acordcs_faults acordcs_more <"$acordcs_file" || :
    fi
    case $acordcs_code:$acordcs_faults:$acordcs_more in
        0:0:)
            echo "$1: not running (it stopped cleanly: exit 0, no fault)"
            return 3 ;;
        killed::)
            echo "$1: not running: killed by $1-stop, TERM had not stopped it; see $acordcs_log"
            return 1 ;;
        [0-9]*:[0-9]*:)
            case $acordcs_code$acordcs_faults in
                *[!0-9]*) ;;
                *)
                    echo "$1: not running: it stopped with exit code $acordcs_code and $acordcs_faults faults; see $acordcs_log"
                    return 1 ;;
            esac ;;
    esac
    echo "$1: not running; its exit file $acordcs_file does not hold EXIT_CODE FAULTS: how it ended is unknown; see $acordcs_log"
    return 4
}
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
        || 'Exit: 0 started and serving, 1 it stopped before serving (the end of its log is shown) or did not serve in time, '
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
</xsl:stylesheet>
