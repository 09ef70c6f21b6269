#!/bin/sh
# tests/install/install_test.sh BUILD_DIR CMAKE PLUGIN_DIR — `cmake --install` into a scratch DESTDIR
# (nothing else copied), then the installed binary run from /tmp on a script that INCLUDEs
# the stdlib: it must find its stdlib, its plug-ins and its examples relative to itself
# (BIN/../share/fortu, BIN/../PLUGIN_DIR: lib/fortu or lib/x86_64-linux-gnu/fortu), never in the build tree it came from.
set -eu
build=$1
cmake=$2
plugins=$3
stage=$(mktemp -d /tmp/fortu-install-test-XXXXXX)
trap 'rm -rf "$stage"' EXIT
fail() { echo "install test: $*" >&2; exit 1; }

DESTDIR="$stage" "$cmake" --install "$build" --prefix /usr > "$stage/install.log" || fail "cmake --install failed"
usr="$stage/usr"
for f in bin/fortu "$plugins/libfortu_image.so" share/fortu/stdlib/shapes.fortu \
         share/fortu/examples/circles_parabola.fortu share/fortu/bench/models/floz64.vm \
         share/man/man1/fortu.1.gz share/bash-completion/completions/fortu share/zsh/vendor-completions/_fortu; do
  [ -f "$usr/$f" ] || fail "missing $f"
done
for plugin in libfortu_vdb.so libfortu_hdf5.so libfortu_mpi.so; do
  if [ -f "$build/$plugin" ]; then [ -f "$usr/$plugins/$plugin" ] || fail "missing $plugin"; fi
done

fortu="$usr/bin/fortu"
work="$stage/work"
mkdir "$work"
printf "INCLUDE 'shapes.fortu';\nARGUMENT X, Y;\nRETURN DISC(X, Y, 0, 0, 0.5);\n" > "$work/inc.fortu"
printf "INCLUDE 'nowhere.fortu';\nARGUMENT X, Y;\nRETURN 1;\n" > "$work/missing.fortu"
cd /tmp
clean="env -u FORTU_STDLIB -u FORTU_PATH -u FORTU_EXAMPLES -u FORTU_IMAGE_MODULE"

# The stdlib through INCLUDE, and the image plug-in from lib/fortu (LD_DEBUG names the file loaded;
# an .exr needs the plug-in, a .png is written by the core).
$clean LD_DEBUG=files "$fortu" run "$work/inc.fortu" --size 64 -o "$work/x.exr" 2> "$work/run.log" \
  || { cat "$work/run.log" | grep -v '^ *[0-9]*:' >&2; fail "run with INCLUDE failed"; }
grep -q "wrote $work/x.exr (64x64)" "$work/run.log" || fail "no 'wrote' line: $(grep -v '^ *[0-9]*:' "$work/run.log")"
grep -q "file=$usr/$plugins/libfortu_image.so" "$work/run.log" || fail "the image plug-in was not loaded from $plugins"

# A missing INCLUDE names the installed stdlib, not the build tree's.
status=0
$clean "$fortu" check "$work/missing.fortu" > "$work/check.log" 2>&1 || status=$?
[ "$status" = 1 ] || fail "missing INCLUDE: exit status $status"
expected="note: searched: $work, $usr/share/fortu/stdlib"
grep -qxF "$expected" "$work/check.log" || fail "expected '$expected' in: $(cat "$work/check.log")"

# The installed examples, and the examples folder `fortu bench` would read.
$clean "$fortu" run "$usr/share/fortu/examples/circles_parabola.fortu" --size 32 -o "$work/c.png" -q \
  || fail "the installed example did not run"
[ -s "$work/c.png" ] || fail "no c.png"

# The man page holds every command's options; bash completes --engine's values.
zgrep -q 'fortu singular' "$usr/share/man/man1/fortu.1.gz" || fail "the man page lacks the commands"
zgrep -q '\\-\\-contour' "$usr/share/man/man1/fortu.1.gz" || fail "the man page lacks --contour"
engines=$(bash -c ". '$usr/share/bash-completion/completions/fortu'; COMP_WORDS=(fortu run --engine ''); COMP_CWORD=3; _fortu; echo \${COMPREPLY[*]}")
[ "$engines" = "classic voxel voxel-f32 sign fv" ] || fail "bash completion of --engine: '$engines'"
echo "install test: ok ($usr)"
