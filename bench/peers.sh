#!/usr/bin/env bash
# bench/peers.sh — fortu beside the independent evaluators of ../shared/peers (numpy, OpenVDB
# AX) on issue 5's models, in one session. Why one script: the machine is shared and noisy,
# so only figures measured minutes apart on the same machine make a fair ratio. A peer that
# is not installed is reported and skipped (exit 0); nothing in the test suite calls this.
#
# Usage: bench/peers.sh [--fortu BIN] [--shared DIR] [--repeat N] [--threads N]
#   --fortu    the fortu binary (default: build/release/fortu of this source tree)
#   --shared   the shared/ folder with data/prospero.vm and peers/ (default: $FORTU_SHARED_DIR,
#              else ../shared beside the source tree)
#   --repeat   timed runs per measurement; medians are compared (default 5)
#   --threads  fortu's and AX's worker threads (default: all cores; numpy is single-threaded)
# Peers: numpy_vm.py needs Debian's python3-numpy (for /usr/bin/python3); the AX driver
# (ax_driver.cpp) is compiled here and needs libopenvdb-ax-dev. PEERS_PYTHON overrides the
# interpreter.
set -uo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
fortu=$root/build/release/fortu
shared=${FORTU_SHARED_DIR:-$root/../shared}
repeat=5
threads=$(nproc)
python=${PEERS_PYTHON:-/usr/bin/python3}

die() { echo "peers.sh: error: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
    case $1 in
        --fortu) [ $# -ge 2 ] || die "--fortu needs a value"; fortu=$2; shift 2 ;;
        --shared) [ $# -ge 2 ] || die "--shared needs a value"; shared=$2; shift 2 ;;
        --repeat) [ $# -ge 2 ] || die "--repeat needs a value"; repeat=$2; shift 2 ;;
        --threads) [ $# -ge 2 ] || die "--threads needs a value"; threads=$2; shift 2 ;;
        -h|--help) sed -n '7,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) die "unknown argument '$1' (see --help)" ;;
    esac
done
[[ $repeat =~ ^[1-9][0-9]*$ ]] || die "--repeat: '$repeat' is not a positive integer"
[[ $threads =~ ^[1-9][0-9]*$ ]] || die "--threads: '$threads' is not a positive integer"
[ -x "$fortu" ] || { echo "peers.sh: error: no fortu binary at $fortu (build it: cmake --preset release && cmake --build --preset release, or give --fortu BIN)" >&2; exit 1; }
peers=$shared/peers
[ -d "$peers" ] || { echo "peers.sh: error: no peers folder at $peers (give --shared DIR)" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0

# The median of a comma-separated list of numbers.
median() { tr ',' '\n' <<<"$1" | sort -g | awk '{v[NR] = $1} END {if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# One field (key=value) of a peer's RESULT line.
result_field() { sed -n "s/.*[[:space:]]$2=\([^[:space:]]*\).*/\1/p" <<<"$1"; }
shown() { if [ -n "$1" ]; then echo "$1 ms"; else echo failed; fi; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {if (b > 0) printf "%.3g", a / b; else print "?"}'; }

# --- which peers are here -------------------------------------------------------------
have_numpy=0
if "$python" -c 'import numpy' 2>/dev/null; then
    have_numpy=1
    echo "numpy: $("$python" -c 'import numpy; print(numpy.__version__)') ($python), single-threaded"
else
    echo "numpy: not installed for $python (Debian: python3-numpy) — skipped"
fi
have_ax=0
if [ ! -f /usr/include/openvdb_ax/ax.h ]; then
    if command -v vdb_ax >/dev/null; then
        echo "OpenVDB AX: vdb_ax is installed, but timing AX without file I/O needs ax_driver.cpp built against libopenvdb-ax-dev — skipped"
    else
        echo "OpenVDB AX: not installed (Debian: libopenvdb-ax-dev) — skipped"
    fi
elif g++ -std=c++17 -O2 "$peers/ax_driver.cpp" -o "$work/ax_driver" -lopenvdb_ax -lopenvdb -lImath-3_1 -ltbb \
        >"$work/ax_build.log" 2>&1; then
    have_ax=1
    echo "OpenVDB AX: ax_driver built, $threads thread(s)"
else
    echo "OpenVDB AX: ax_driver.cpp did not build — skipped:"
    sed 's/^/  /' "$work/ax_build.log" | head -5
fi
echo "fortu: $fortu, $threads thread(s); medians of $repeat runs, evaluation only"
echo

# --- the measurements -------------------------------------------------------------------
# fortu_ms MODEL N ENGINE: the median of `fortu bench` (CSV column 10, seconds) in ms.
fortu_ms() {
    "$fortu" bench "$1" --engines "$3" --sizes "$2" --repeat "$repeat" --threads "$threads" \
        --csv "$work/fortu.csv" >/dev/null 2>"$work/fortu.log" || return 1
    awk -F, 'NR == 2 {printf "%.2f", $10 * 1000}' "$work/fortu.csv"
}
# numpy_ms MODEL N: the median of numpy_vm.py's runs in float32.
numpy_ms() {
    local line
    line=$("$python" "$peers/numpy_vm.py" "$1" "$2" --dtype float32 --repeat "$repeat" 2>"$work/numpy.log" | grep '^RESULT') || return 1
    median "$(result_field "$line" eval_ms_all)"
}
# ax_ms MODEL N: the median of ax_driver's runs (float32) on gen_ax.py's translation.
ax_ms() {
    PYTHONPATH=$peers "$python" "$peers/gen_ax.py" "$1" "$2" "$work/model.ax" >"$work/ax.log" 2>&1 || return 1
    local line
    line=$("$work/ax_driver" "$work/model.ax" "$2" --threads "$threads" --repeat "$repeat" 2>>"$work/ax.log" | grep '^RESULT') || return 1
    median "$(result_field "$line" eval_ms_all)"
}

echo "| model | grid | fortu float32 | fortu float64 | numpy float32 | numpy / fortu float32 | OpenVDB AX | AX / fortu float32 |"
echo "|---|---|---|---|---|---|---|---|"
for case in "prospero.vm:$shared/data/prospero.vm:1024" "floz64.vm:$root/bench/models/floz64.vm:800"; do
    IFS=: read -r name model n <<<"$case"
    if [ ! -f "$model" ]; then
        echo "| $name | ${n}² | not found: $model | | | | | |"
        continue
    fi
    f32=$(fortu_ms "$model" "$n" voxel-f32) || { f32=""; failed=1; sed 's/^/  fortu: /' "$work/fortu.log" >&2; }
    f64=$(fortu_ms "$model" "$n" voxel) || { f64=""; failed=1; sed 's/^/  fortu: /' "$work/fortu.log" >&2; }
    numpy="skipped" numpy_ratio="—" ax="skipped" ax_ratio="—"
    if [ $have_numpy = 1 ]; then
        if ms=$(numpy_ms "$model" "$n"); then numpy="$ms ms"; numpy_ratio=$(ratio "$ms" "$f32");
        else numpy="failed"; failed=1; sed 's/^/  numpy: /' "$work/numpy.log" >&2; fi
    fi
    if [ $have_ax = 1 ]; then
        if ms=$(ax_ms "$model" "$n"); then ax="$ms ms"; ax_ratio=$(ratio "$ms" "$f32");
        else ax="failed"; failed=1; sed 's/^/  AX: /' "$work/ax.log" >&2; fi
    fi
    echo "| $name | ${n}² | $(shown "$f32") | $(shown "$f64") | $numpy | $numpy_ratio | $ax | $ax_ratio |"
done
exit $failed
