#!/usr/bin/env bash
# bench/peers.sh — fortu beside independent evaluators (numpy, OpenVDB AX, libfive) in one
# session. Why one script: the machine is shared and noisy, so only figures measured minutes
# apart on the same machine make a fair ratio. A peer that is not installed is reported and
# skipped (exit 0); nothing in the test suite calls this.
#
# Usage: bench/peers.sh [--fortu BIN] [--shared DIR] [--repeat N] [--threads N] [--peers LIST]
#                       [--libfive DIR | --fetch-libfive DIR] [--rows LIST] [--slow-repeat N]
#                       [--libfive-threads LIST] [--out DIR]
#   --fortu    the fortu binary (default: build/release/fortu of this source tree)
#   --shared   the shared/ folder with data/*.vm and peers/ (default: $FORTU_SHARED_DIR,
#              else ../shared beside the source tree)
#   --repeat   timed runs per measurement; medians are compared (default 5)
#   --threads  fortu's and AX's worker threads in the numpy/AX table (default: all cores)
#   --peers    which comparisons run: numpy, ax, libfive (default numpy,ax, plus libfive when
#              a libfive folder is given)
#   --libfive DIR        libfive's source folder, built (DIR/build/libfive/src/libfive.so)
#   --fetch-libfive DIR  fetch libfive at commit e8370983 into DIR/libfive-src and build it
#                        there (once; DIR must be outside this source tree)
#   --rows     the libfive rows to run, comma-separated (default all; `list` prints them)
#   --slow-repeat        rounds for the slow rows (3D fields, meshes, views; default 3)
#   --libfive-threads    thread counts of the libfive rows (default 1,2)
#   --out      where the libfive rows' runs.csv and table.md go (default bench-results/peers)
# Peers: numpy_vm.py needs Debian's python3-numpy (for /usr/bin/python3); the AX driver
# (ax_driver.cpp) is compiled here and needs libopenvdb-ax-dev; the libfive drivers
# (../shared/peers/libfive_vm.cpp and bench/peers/libfive_mesh.cpp) are compiled here with
# libfive's own flags into DIR/build/fortu-peers/, beside that libfive build.
# PEERS_PYTHON overrides the interpreter.
set -uo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
fortu=$root/build/release/fortu
shared=${FORTU_SHARED_DIR:-$root/../shared}
repeat=5
threads=$(nproc)
python=${PEERS_PYTHON:-/usr/bin/python3}
peer_list=""
libfive_dir="" fetch_dir="" rows=all slow_repeat=3 lf_threads=1,2 out=bench-results/peers

die() { echo "peers.sh: error: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
    case $1 in
        --fortu) [ $# -ge 2 ] || die "--fortu needs a value"; fortu=$2; shift 2 ;;
        --shared) [ $# -ge 2 ] || die "--shared needs a value"; shared=$2; shift 2 ;;
        --repeat) [ $# -ge 2 ] || die "--repeat needs a value"; repeat=$2; shift 2 ;;
        --threads) [ $# -ge 2 ] || die "--threads needs a value"; threads=$2; shift 2 ;;
        --peers) [ $# -ge 2 ] || die "--peers needs a value"; peer_list=$2; shift 2 ;;
        --libfive) [ $# -ge 2 ] || die "--libfive needs a value"; libfive_dir=$2; shift 2 ;;
        --fetch-libfive) [ $# -ge 2 ] || die "--fetch-libfive needs a value"; fetch_dir=$2; shift 2 ;;
        --rows) [ $# -ge 2 ] || die "--rows needs a value"; rows=$2; shift 2 ;;
        --slow-repeat) [ $# -ge 2 ] || die "--slow-repeat needs a value"; slow_repeat=$2; shift 2 ;;
        --libfive-threads) [ $# -ge 2 ] || die "--libfive-threads needs a value"; lf_threads=$2; shift 2 ;;
        --out) [ $# -ge 2 ] || die "--out needs a value"; out=$2; shift 2 ;;
        -h|--help) sed -n '7,28p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) die "unknown argument '$1' (see --help)" ;;
    esac
done
[[ $repeat =~ ^[1-9][0-9]*$ ]] || die "--repeat: '$repeat' is not a positive integer"
[[ $threads =~ ^[1-9][0-9]*$ ]] || die "--threads: '$threads' is not a positive integer"
[[ $slow_repeat =~ ^[1-9][0-9]*$ ]] || die "--slow-repeat: '$slow_repeat' is not a positive integer"
[[ $lf_threads =~ ^[12](,[12])?$ ]] || die "--libfive-threads: '$lf_threads' is not 1, 2 or 1,2"
[ -z "$libfive_dir" ] || [ -z "$fetch_dir" ] || die "give --libfive or --fetch-libfive, not both"
if [ -z "$peer_list" ]; then
    peer_list=numpy,ax
    [ -z "$libfive_dir$fetch_dir" ] || peer_list=$peer_list,libfive
fi
for p in ${peer_list//,/ }; do
    case $p in numpy|ax|libfive) ;; *) die "--peers: unknown peer '$p' (numpy, ax, libfive)" ;; esac
done
wants() { [[ ,$peer_list, == *,$1,* ]]; }
if wants libfive && [ -z "$libfive_dir$fetch_dir" ]; then
    die "--peers libfive needs --libfive DIR (a built libfive) or --fetch-libfive DIR"
fi
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
if ! wants numpy; then
    :
elif "$python" -c 'import numpy' 2>/dev/null; then
    have_numpy=1
    echo "numpy: $("$python" -c 'import numpy; print(numpy.__version__)') ($python), single-threaded"
else
    echo "numpy: not installed for $python (Debian: python3-numpy) — skipped"
fi
have_ax=0
if ! wants ax; then
    :
elif [ ! -f /usr/include/openvdb_ax/ax.h ]; then
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

numpy_ax_table() {
echo "fortu: $fortu, $threads thread(s); medians of $repeat runs, evaluation only"
echo
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
echo
}
if wants numpy || wants ax; then numpy_ax_table; fi

# --- libfive ------------------------------------------------------------------------------
# The commit ../shared/peers/README.md names; the drivers are written against its API.
libfive_commit=e8370983e7bc6d49409affcc34fc70c673cc876f
# fetch_libfive DIR: DIR/libfive-src at that commit, its core library built as the peers README
# says (Release, no Studio, no bindings). Once: a finished build is reused.
fetch_libfive() {
    local dir=$1 src=$1/libfive-src
    [ -f "$src/build/libfive/src/libfive.so" ] && return 0
    for pkg in libeigen3-dev libpng-dev libboost-dev; do
        dpkg -s "$pkg" >/dev/null 2>&1 || die "building libfive needs Debian's $pkg (apt-get install -y $pkg)"
    done
    mkdir -p "$dir" || die "cannot create $dir"
    if [ ! -f "$src/CMakeLists.txt" ]; then
        echo "libfive: fetching commit $libfive_commit into $src"
        curl -fsSL "https://github.com/libfive/libfive/archive/$libfive_commit.tar.gz" -o "$dir/libfive.tar.gz" ||
            die "cannot download libfive (network?)"
        tar -xzf "$dir/libfive.tar.gz" -C "$dir" && mv "$dir/libfive-$libfive_commit" "$src" ||
            die "cannot unpack $dir/libfive.tar.gz"
    fi
    echo "libfive: building the core library in $src/build (several minutes)"
    cmake -S "$src" -B "$src/build" -DCMAKE_BUILD_TYPE=Release -DBUILD_STUDIO_APP=OFF \
        -DBUILD_GUILE_BINDINGS=OFF -DBUILD_PYTHON_BINDINGS=OFF -DENABLE_DEBUG=OFF >"$dir/cmake.log" 2>&1 &&
        make -C "$src/build" -j"$(nproc)" libfive >"$dir/make.log" 2>&1 ||
        die "libfive did not build: see $dir/cmake.log and $dir/make.log"
}
# build_driver EXE SOURCE... [-DNAME]: compile one driver with libfive's own release flags,
# unless the executable is newer than its sources and the library.
build_driver() {
    local exe=$1 lib=$libfive_dir/build/libfive/src fresh=1 f
    shift
    for f in "$@" "$lib/libfive.so"; do
        [ -f "$f" ] || continue
        [ -x "$exe" ] && [ "$exe" -nt "$f" ] || fresh=0
    done
    [ $fresh = 1 ] && return 0
    echo "libfive: compiling $(basename "$exe")"
    # shellcheck disable=SC2046
    g++ -std=c++17 -O3 -march=native -DEIGEN_NO_DEBUG -I"$libfive_dir/libfive/include" \
        $(pkg-config --cflags eigen3) "$@" -o "$exe" -L"$lib" -lfive -Wl,-rpath,"$lib" -lpthread \
        >"$work/lf_build.log" 2>&1 || { sed 's/^/  /' "$work/lf_build.log" | head -20 >&2; return 1; }
}
# libfive's optimiser (Tree::optimized(), called by the Deck constructor) does not finish on
# floz64's 64-deep R0 fold; libfive_vm_noopt links a copy of libfive's own eval/deck.cpp,
# made here beside the build, with that call removed (the executable's Deck::Deck wins).
make_deck_noopt() {
    sed 's/const auto root = root_\.optimized();/const auto\& root = root_;  \/\/ fortu peers: not optimised/' \
        "$libfive_dir/libfive/src/eval/deck.cpp" >"$1.$$.tmp" && grep -q 'fortu peers: not optimised' "$1.$$.tmp" ||
        { echo "libfive: eval/deck.cpp has no 'root_.optimized()' line to remove (another commit?)" >&2; return 1; }
    if cmp -s "$1.$$.tmp" "$1"; then rm -f "$1.$$.tmp"; else mv "$1.$$.tmp" "$1"; fi
}
libfive_rows() {
    if [ "$rows" = list ]; then
        "$python" "$here/peers/libfive_rows.py" --rows list --fortu - --lf-vm - --lf-vm-noopt - \
            --lf-mesh - --data "$shared/data" --floz - --out -
        return
    fi
    if [ -n "$fetch_dir" ]; then
        case $(realpath -m "$fetch_dir")/ in
            "$(realpath "$root")"/*) die "--fetch-libfive: $fetch_dir is inside the source tree; give a scratch folder outside it" ;;
        esac
        mkdir -p "$fetch_dir" || die "cannot create $fetch_dir"
        fetch_libfive "$fetch_dir"
        libfive_dir=$fetch_dir/libfive-src
    fi
    [ -f "$libfive_dir/build/libfive/src/libfive.so" ] ||
        die "no libfive build in $libfive_dir (expected build/libfive/src/libfive.so; --fetch-libfive DIR makes one)"
    libfive_dir=$(realpath "$libfive_dir")
    local bin=$libfive_dir/build/fortu-peers
    mkdir -p "$bin" || die "cannot create $bin"
    build_driver "$bin/libfive_vm" "$peers/libfive_vm.cpp" &&
        make_deck_noopt "$bin/deck_noopt.cpp" &&
        build_driver "$bin/libfive_vm_noopt" "$peers/libfive_vm.cpp" "$bin/deck_noopt.cpp" -DLIBFIVE_VM_NO_OPT &&
        build_driver "$bin/libfive_mesh" "$here/peers/libfive_mesh.cpp" || { echo "libfive: a driver did not build" >&2; return 1; }
    echo "libfive: $libfive_dir ($(git -C "$libfive_dir" rev-parse --short HEAD 2>/dev/null || echo "commit $libfive_commit")), drivers in $bin"
    echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores"
    mkdir -p "$work/out" || return 1
    "$python" "$here/peers/libfive_rows.py" --fortu "$fortu" --lf-vm "$bin/libfive_vm" \
        --lf-vm-noopt "$bin/libfive_vm_noopt" --lf-mesh "$bin/libfive_mesh" --data "$shared/data" --floz "$root/bench/models/floz64.vm" \
        --out "$out" --work "$work/out" --rows "$rows" --threads "$lf_threads" \
        --repeat "$repeat" --slow-repeat "$slow_repeat"
}
if wants libfive; then libfive_rows || failed=1; fi
exit $failed
