<?xml version="1.0" encoding="UTF-8"?>
<!--
  Part of target "shell" (included by shell.xsl): the sh functions every generated script gets
  from bin/env.sh, after the settings: the checks of the settings, the run directory and the token
  file, and what starts, stops and checks a container (which process a stop may signal, how a
  start knows the container serves, how a status reads the exit file). docs/build.md, "The
  scripts' security model", says what they promise.
-->
<xsl:stylesheet version="3.0" xmlns:xsl="http://www.w3.org/1999/XSL/Transform">

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

# acordcs_start NAME ARGUMENTS...: starts container NAME (python -m, with --exit-file, --state-dir
# (the run directory: the state of its components tagged persistent) and the
# ARGUMENTS) in the background, its pid in NAME.pid, its output appended to NAME.log; waits until
# its log says it serves (at most ACORDCS_START_TIMEOUT s): the container says so at the end of
# its start-up (on a real clock, once its --run operations are past their first moments). 0
# serving (or it ended at once without a fault: a virtual clock's short run); 1 it stopped before,
# or as it said it serves, with a failure (the end of its log is shown), or did not serve in time
# (it still runs).
acordcs_start() {
    acordcs_name=$1
    shift
    acordcs_log=$ACORDCS_RUN_DIR/$acordcs_name.log
    acordcs_from=1
    if [ -f "$acordcs_log" ]; then acordcs_from=$(($(wc -c <"$acordcs_log") + 1)); fi
    rm -f -- "$ACORDCS_RUN_DIR/$acordcs_name.exit"
    nohup "$PYTHON" -m "$ACORDCS_PACKAGE.$acordcs_name" --exit-file "$ACORDCS_RUN_DIR/$acordcs_name.exit" \
        --state-dir "$ACORDCS_RUN_DIR" "$@" >>"$acordcs_log" 2>&1 </dev/null &
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
    if ! acordcs_alive "$pid"; then
        # It said it serves and ended already: how, its exit file says (EXIT_CODE FAULTS).
        rm -f -- "$ACORDCS_RUN_DIR/$acordcs_name.pid"
        acordcs_code='' acordcs_faults=''
        if [ -f "$ACORDCS_RUN_DIR/$acordcs_name.exit" ]; then
            read -r acordcs_code acordcs_faults _ <"$ACORDCS_RUN_DIR/$acordcs_name.exit" || :
        fi
        if [ "$acordcs_code:$acordcs_faults" = 0:0 ]; then
            echo "$acordcs_name: started and stopped at once, cleanly (exit 0, no fault; log $acordcs_log)"
            return 0
        fi
        echo "$acordcs_name: stopped during its start-up (exit ${acordcs_code:-unknown}, faults ${acordcs_faults:-unknown}); the end of $acordcs_log:" >&2
        tail -c "+$acordcs_from" -- "$acordcs_log" | tail -n 20 >&2
        return 1
    fi
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

# acordcs_status NAME: whether container NAME runs, with the digest of the descriptor it runs
# (the last "NAME: [now ]runs descriptor sha256 DIGEST" line of its log: at start, and after each
# acordcs-gen update); when not, how it ended, from NAME.exit (the
# line EXIT_CODE FAULTS the container writes at exit, or killed, written by -stop). Exit (LSB):
# 0 running; 3 not running (never started, or exit 0 and no fault); 1 not running after a failure
# (another exit code, faults, killed, or gone without an exit file while its pid file remains);
# 4 unknown (an exit file that does not read as one).
acordcs_status() {
    if acordcs_pid "$1" keep; then
        acordcs_digest=$(sed -n "s/^$1: \(now \)\{0,1\}runs descriptor sha256 \([0-9a-f]\{64\}\)\$/\2/p" \
            "$ACORDCS_RUN_DIR/$1.log" 2>/dev/null | tail -n 1)
        echo "$1: running (pid $pid${acordcs_digest:+, descriptor sha256 $acordcs_digest})"
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
</xsl:stylesheet>
