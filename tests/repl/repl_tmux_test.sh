#!/bin/sh
# tests/repl/repl_tmux_test.sh FORTU — drives `fortu repl` in a tmux pane (send-keys, then
# capture-pane) and checks what a user sees: the half-block picture of a disc, a syntax error
# with its caret, Tab completion, Ctrl-C stopping a long evaluation (not the REPL) and dropping a half-typed
# line, Ctrl-D quitting, the history file. Exit 0 only if every check passed. Every step waits
# for what the session shows (or, for a running evaluation, for the CPU time it has used), never
# for a fixed time, so the test passes on a loaded machine too.
set -u
FORTU=${1:?usage: repl_tmux_test.sh PATH/TO/fortu}
if ! command -v tmux >/dev/null 2>&1; then
    echo "FAIL: tmux is not installed (apt-get install tmux); the interactive REPL test cannot run"
    exit 1
fi

WORK=$(mktemp -d "${TMPDIR:-/tmp}/fortu_repl_tmux.XXXXXX")
SOCKET="fortu_repl_test_$$"
T="tmux -L $SOCKET"
cleanup() { $T kill-server >/dev/null 2>&1; rm -rf "$WORK"; }
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $1"; failures=$((failures + 1)); }
pass() { echo "ok: $1"; }

# Runs "${@:2}" every 0.1 s until it succeeds, for at most $1 seconds: every wait below
# waits on a condition, never on a fixed sleep, so the test holds under load.
poll() {
    tries=$(( $1 * 10 ))
    shift
    while [ "$tries" -gt 0 ]; do
        "$@" && return 0
        sleep 0.1
        tries=$((tries - 1))
    done
    return 1
}

pane() { $T capture-pane -p -S -200 -t repl 2>/dev/null; }
show_pane() { pane | grep -v '^$' | tail -20; }

# Waits (up to $2 seconds, default 60) until the pane shows text matching the regex $1.
pane_matches() { pane | grep -Eq -- "$1"; }
wait_for() {
    poll "${2:-60}" pane_matches "$1" && return 0
    echo "--- pane after waiting for /$1/:"
    show_pane
    return 1
}

# Waits until the session is idle at an empty prompt right after the line "fortu> $1": it has
# read that line and finished what it asked for.
idle_after() { [ "$(pane | grep -v '^$' | tail -2)" = "$(printf 'fortu> %s\nfortu>' "$1")" ]; }
wait_for_prompt_after() {
    poll 60 idle_after "$1" && return 0
    echo "--- pane after waiting for the prompt after '$1':"
    show_pane
    return 1
}

# The CPU time (clock ticks, all threads) the fortu process has used so far.
cpu_ticks() { awk '{ print $14 + $15 }' "/proc/$(cat "$WORK/fortu.pid")/stat" 2>/dev/null || echo 0; }

# Waits until fortu has used $1 more clock ticks of CPU than $2: it is evaluating. Only an
# evaluation spends CPU time; the prompt waits for input without using any.
used_cpu() { [ "$(cpu_ticks)" -ge $(( $2 + $1 )) ]; }
wait_for_cpu() {
    poll 60 used_cpu "$1" "$2" && return 0
    echo "--- fortu used only $(( $(cpu_ticks) - $2 )) ticks of CPU"
    return 1
}

mkdir -p "$WORK/home"
cd "$WORK" || exit 1
echo 'VARIABLE RING = 0.6 - SQRT(X^2 + Y^2)' > "$WORK/ring_model.fortu"   # for :load's completion
# The launcher records fortu's process id (exec keeps it) for wait_for_cpu.
cat > "$WORK/launch.sh" <<EOF
echo \$\$ > '$WORK/fortu.pid'
exec env -u NO_COLOR HOME='$WORK/home' TERM=xterm-256color '$FORTU' repl
EOF
$T new-session -d -s repl -x 100 -y 40 \
    "sh '$WORK/launch.sh'; echo \"repl exited with status \$?\"; sleep 60" || { echo "FAIL: tmux could not start"; exit 1; }
wait_for '^fortu>' || fail "no prompt"

# A syntax error: reported with the typed line and a caret; the session goes on.
$T send-keys -t repl 'ARGUMENT X, Y' Enter 'RETURN 0.6 - SQRT(X^2 + Y^2' Enter
wait_for "<input>:1:28: error: unexpected end of file" && wait_for '^ {27}\^$' \
    && pass "syntax error with caret" || fail "syntax error not reported with a caret"

# The disc, drawn in truecolour half blocks.
$T send-keys -t repl 'RETURN 0.6 - SQRT(X^2 + Y^2)' Enter ':show' Enter
if wait_for 'warm inside, blue outside, black contour'; then
    $T capture-pane -p -e -t repl > "$WORK/show.txt"
    blocks=$(grep -c '▀' "$WORK/show.txt")
    first=$(grep -m1 '▀' "$WORK/show.txt")
    middle=$(grep '▀' "$WORK/show.txt" | sed -n "$(( (blocks + 1) / 2 ))p")
    [ "$blocks" -ge 30 ] && pass "half-block picture, $blocks lines" || fail "only $blocks half-block lines"
    # Outside (deep blue) at the top edge, no inside there; the middle line crosses the disc:
    # deep orange inside and the black contour.
    printf '%s' "$first" | grep -q '38;2;47;95;179m' && ! printf '%s' "$first" | grep -q '232;117;26m' \
        && pass "top edge is outside" || fail "top edge is not outside"
    printf '%s' "$middle" | grep -q '232;117;26m' && printf '%s' "$middle" | grep -Eq '[34]8;2;0;0;0m' \
        && pass "middle line crosses the disc and its contour" || fail "no disc in the middle line"
else
    fail ":show drew nothing"
fi

# Tab completes a command, a built-in function, an engine, a file name. Each line is then
# finished with Enter (keys stay in order; a Ctrl-C would race with the typing).
$T send-keys -t repl ':ren' Tab
wait_for '^fortu> :render ?$' && pass "Tab completes :ren to :render" || fail "Tab did not complete :ren"
$T send-keys -t repl Enter
wait_for '^fortu: error: :render needs a file name$' || fail ":render without a file"
$T send-keys -t repl 'VARIABLE DISC = 0.6 - SQ' Tab
wait_for '^fortu> VARIABLE DISC = 0\.6 - SQRT ?$' && pass "Tab completes SQ to SQRT" || fail "Tab did not complete SQ"
$T send-keys -t repl '(X^2 + Y^2)' Enter ':engine vo' Tab
wait_for '^fortu> :engine voxel ?$' && pass "Tab completes an engine" || fail "Tab did not complete the engine"
$T send-keys -t repl Enter ':load ring_m' Tab
wait_for '^fortu> :load ring_model\.fortu ?$' && pass "Tab completes a file name after :load" \
    || fail "Tab did not complete the file"
$T send-keys -t repl Enter
wait_for '^loaded ring_model\.fortu \(1 statement\)$' || fail "the completed file was not loaded"

# Ctrl-C stops a long evaluation, not the REPL; no half-written file is left.
$T send-keys -t repl 'VARIABLE D = 0' Enter 'FOR I = 1, 2000' Enter \
    'D = D | (0.01 - SQRT((X - I/1000)^2 + Y^2))' Enter 'END FOR' Enter 'RETURN D' Enter \
    ':size 2000' Enter
wait_for '^size: 2000x2000$' || fail "the long model was not set up"
before=$(cpu_ticks)
$T send-keys -t repl ':render big.npy' Enter
wait_for_cpu 20 "$before" || fail "the evaluation did not start"
$T send-keys -t repl C-c
wait_for 'fortu: error: interrupted' && pass "Ctrl-C interrupted the evaluation" || fail "Ctrl-C did not interrupt"
[ ! -e big.npy ] && pass "no file written" || fail "an interrupted :render wrote big.npy"
$T send-keys -t repl ':eval 0.5 0' Enter
wait_for '^inside: ' && pass "the session goes on after Ctrl-C" || fail "the session did not survive Ctrl-C"

# Ctrl-C at the prompt drops the half-typed line.
$T send-keys -t repl 'half typed'
wait_for '^fortu> half typed$' || fail "the half-typed line was not echoed"
$T send-keys -t repl C-c
wait_for_prompt_after 'half typed' || fail "no new prompt after Ctrl-C"
$T send-keys -t repl ':engine' Enter
wait_for '^engine: voxel$' && pass "Ctrl-C at the prompt drops the line" || fail "Ctrl-C at the prompt"

# Ctrl-D quits; the history was kept.
$T send-keys -t repl C-d
wait_for '^repl exited with status 0$' && pass "Ctrl-D quits" || fail "Ctrl-D did not quit"
grep -q ':show' "$WORK/home/.fortu_history" 2>/dev/null && pass "history in ~/.fortu_history" \
    || fail "no history in ~/.fortu_history"

[ "$failures" -eq 0 ] && echo "all repl tmux checks passed" && exit 0
echo "$failures repl tmux check(s) failed"
exit 1
