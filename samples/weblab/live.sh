#!/bin/sh
# `make live`: the generated WebLab application as two OS processes in real time, started and
# stopped by its generated scripts (app/bin), talking over the remote connector (Pyro5) on the
# loopback interface. The user's process runs Navigator.run (ACORDCS_UserSide_RUN); the WebLab's
# process hosts the simulated robot on a real clock. After the Navigator's run (the finish line
# or WEBLAB_LIVE_SECONDS, default 60), prints what happened from both logs and stops both; also
# on Ctrl-C and on failure. Exit 0 when the Navigator completed and neither process had a fault.
#
# `make live-console` is `live.sh console [CONSOLE OPTIONS]`: the same two processes, and the
# WebLab console attached to them (python -m weblab_console --attach app, with the options given),
# until Ctrl-C (or TERM to this script), which stops the console, then both processes, and prints
# what happened from both logs. The Navigator drives to the finish line (WEBLAB_LIVE_SECONDS, if
# set, caps it). Exit 0 when the console stopped cleanly and neither process had a fault.
set -u
here=$(CDPATH='' cd -- "$(dirname -- "$0")" && pwd) || exit 1
app=$here/app
mode=run
if [ "${1-}" = console ]; then
    mode=console
    shift
fi
if [ "$mode" = console ]; then seconds=${WEBLAB_LIVE_SECONDS-}; else seconds=${WEBLAB_LIVE_SECONDS:-60}; fi
[ -n "${PYTHON-}" ] || PYTHON=python3
# The generated scripts' settings: real time, both containers on loopback, the Navigator's run.
ACORDCS_RUN_DIR=${ACORDCS_RUN_DIR:-$app/run}
ACORDCS_CLOCK=real
ACORDCS_UserSide_HOST=127.0.0.1
ACORDCS_WebLabSide_HOST=127.0.0.1
ACORDCS_UserSide_RUN=Navigator.run
# A stop() that fires a recovery (4.5 s) or a person's help (10 s) answers late: not a timeout.
ACORDCS_TIMEOUT=${ACORDCS_TIMEOUT:-30}
WEBLAB_TIME_CAP=$seconds
# The Navigator asks for 200 mm/s as in the experiment's adaptive condition; SpeedLimiting caps it.
WEBLAB_FORWARD_SPEED=${WEBLAB_FORWARD_SPEED:-200}
PYTHONPATH=$here${PYTHONPATH:+:$PYTHONPATH} # weblab_sim, which the components use
export PYTHON PYTHONPATH ACORDCS_RUN_DIR ACORDCS_CLOCK ACORDCS_UserSide_HOST \
    ACORDCS_WebLabSide_HOST ACORDCS_UserSide_RUN ACORDCS_TIMEOUT WEBLAB_TIME_CAP WEBLAB_FORWARD_SPEED
user_log=$ACORDCS_RUN_DIR/UserSide.log
lab_log=$ACORDCS_RUN_DIR/WebLabSide.log

# Stops both; while the Navigator may still be driving, the user's process first, so that its
# calls do not meet a WebLab that is gone.
finished=0
stop() {
    trap - EXIT INT TERM
    if [ "$finished" = 0 ]; then sh "$app/bin/UserSide-stop"; fi
    sh "$app/bin/stop-all"
}
trap stop EXIT
trap 'echo "live: interrupted"; exit 130' INT TERM
# A shell started with SIGINT ignored (a background job of a non-interactive shell, or a child of
# a program that ignores it) cannot trap it: Ctrl-C would not reach this script. Say so.
ignored=$(sed -n 's/^SigIgn:[[:space:]]*//p' /proc/$$/status 2>/dev/null) || ignored=
if [ -n "$ignored" ] && [ $((0x${ignored#"${ignored%????}"} & 0x4002)) -ne 0 ]; then
    echo "live: SIGINT or SIGTERM is ignored in this shell (started in the background?): Ctrl-C will not stop it; stop it with: kill -TERM $$ (or $app/bin/stop-all)" >&2
fi

# The run directory is the user's alone (the scripts refuse one others can write).
(umask 077 && mkdir -p -- "$ACORDCS_RUN_DIR") || exit 1
rm -f -- "$user_log" "$lab_log"
if [ -n "$seconds" ]; then
    echo "live: the WebLab on loopback in real time, at most $seconds s of driving (logs in $ACORDCS_RUN_DIR)"
else
    echo "live: the WebLab on loopback in real time, driving to the finish line (logs in $ACORDCS_RUN_DIR)"
fi
sh "$app/bin/start-all" || exit 1
echo "live: processes: $(cat -- "$ACORDCS_RUN_DIR/UserSide.pid") (UserSide), $(cat -- "$ACORDCS_RUN_DIR/WebLabSide.pid") (WebLabSide)"
if [ "$mode" = console ]; then
    # The console in the background, so that a signal to this script alone (TERM) reaches the
    # trap at once (a shell runs a trap only once its foreground command ends); the trap passes
    # it on. Its first lines say what it attached to and its link (the sign it is ready).
    echo "live: the console attaches to both (Ctrl-C stops the console and both processes)"
    console=
    trap 'trap "" INT TERM; echo "live: stopping"; [ -z "$console" ] || kill -TERM "$console" 2>/dev/null' INT TERM
    "$PYTHON" -m weblab_console --attach "$app" "$@" &
    console=$!
    console_status=0
    wait "$console" || console_status=$?
    while kill -0 "$console" 2>/dev/null; do # a signal ended the wait, not the console
        console_status=0
        wait "$console" || console_status=$?
    done
else
    echo "live: running (Ctrl-C stops both)"

    # Wait for the Navigator's run to end (or its process to stop), showing its progress.
    waited=0
    shown=0
    limit=$((seconds + 60))
    while :; do
        if grep -q -e '--run Navigator.run() returned' -e '--run Navigator.run() failed' "$user_log" 2>/dev/null; then
            break
        fi
        if ! sh "$app/bin/UserSide-status" >/dev/null; then
            echo "live: the user's process stopped before the Navigator's run ended" >&2
            break
        fi
        if [ "$waited" -ge "$limit" ]; then
            echo "live: the Navigator's run did not end within $limit s" >&2
            break
        fi
        lines=$(grep -c '^Navigator t=' "$user_log" 2>/dev/null) || lines=0
        if [ "$lines" -gt "$shown" ]; then
            grep '^Navigator t=' "$user_log" | sed -n "$((shown + 1)),\$p"
            shown=$lines
        fi
        sleep 1
        waited=$((waited + 1))
    done
    grep '^Navigator t=' "$user_log" | sed -n "$((shown + 1)),\$p"
fi
grep -q -e '--run Navigator.run() returned' "$user_log" && finished=1
stop
trap - EXIT INT TERM
echo
echo "== the user's process (UserSide.log)"
grep -e 'serving at' -e '^Navigator:' -e '--run' "$user_log"
grep -v -e '^Navigator t=' -e 'serving at' -e '^Navigator:' -e '--run' -e 'stopped at' "$user_log" | head -n 20
grep 'stopped at' "$user_log"
echo
echo "== the WebLab's process (WebLabSide.log)"
grep -e 'serving at' -e '^WebLab t=' "$lab_log"
grep -v -e 'serving at' -e '^WebLab t=' -e 'stopped at' "$lab_log" | head -n 20
grep 'stopped at' "$lab_log"
echo
echo "== summary"
grep '^Navigator:' "$user_log"
awk -F 'SpeedLimiting: maxSpeed +' '/^WebLab t=.*SpeedLimiting: maxSpeed/ {
    split($2, a, " "); v = a[1] + 0
    if (n == 0 || v < lo) lo = v
    if (n == 0 || v > hi) hi = v
    n++
} END { if (n) printf "SpeedLimiting: Locomotion.maxSpeed between %.1f and %.1f mm/s in %d status lines (model default 200)\n", lo, hi, n }' "$lab_log"
echo "Recovering: $(grep -c 'Recovering: recover #' "$lab_log") recoveries, $(grep -c 'Recovering: askUser #' "$lab_log") user requests"
echo "faults: UserSide $(sed -n 's/^UserSide: stopped at t=.*faults: //p' "$user_log"), WebLabSide $(sed -n 's/^WebLabSide: stopped at t=.*faults: //p' "$lab_log")"
echo
if [ "$mode" = console ]; then
    if [ "$console_status" = 0 ] && grep -q 'faults: 0$' "$user_log" && grep -q 'faults: 0$' "$lab_log"; then
        echo "live: done: the console and both processes stopped, no fault in either process"
        exit 0
    fi
    echo "live: the console (exit $console_status) or a process did not stop cleanly: see the logs above and in $ACORDCS_RUN_DIR" >&2
    exit 1
fi
if grep -q -e '--run Navigator.run() returned' "$user_log" &&
    grep -q 'faults: 0$' "$user_log" && grep -q 'faults: 0$' "$lab_log"; then
    echo "live: done: the Navigator completed its run over Pyro5, no fault in either process"
    exit 0
fi
echo "live: the run did not complete cleanly: see the logs above and in $ACORDCS_RUN_DIR" >&2
exit 1
