#!/bin/sh
# bench/mesh_accuracy.sh — how far each 3D RANOK script's mesh (and bear.vm's) is from the
# true surface, both ways, in cells, by the tests' independent check (fortu_mesh_check): a
# Markdown table for docs/meshing.md. The domains are chosen as the test of every 3D RANOK
# script chooses them: the header comment's, else --domain auto, else (unbounded) the default.
# Usage: bench/mesh_accuracy.sh [BUILD] [SIZE] [SAMPLES] [REGEX]
# (default build/release, 65, 24, every script). Columns: mesh to surface, surface to mesh
# (">1": a sample with no triangle within a cell), and what the topology check found wrong.
set -eu
build=${1:-build/release}
size=${2:-65}
samples=${3:-24}
only=${4:-.}
here=$(dirname "$0")
# The shared folder as CMake finds it: ../shared beside the repository, else the vendored copy.
shared=${FORTU_SHARED_DIR:-$here/../../shared}
[ -d "$shared/data/ranok-scripts" ] || shared=$here/../tests/shared
for tool in "$build/fortu" "$build/tests/fortu_mesh_check"; do
    [ -x "$tool" ] || { echo "mesh_accuracy.sh: no $tool: build first (cmake --build --preset release)" >&2; exit 2; }
done
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
echo "| model | nodes | mesh to surface | surface to mesh | topology |"
echo "|---|---|---|---|---|"
over=0
for model in "$shared"/data/ranok-scripts/*.fortu "$shared"/data/bear.vm; do
    name=$(basename "$model")
    printf '%s\n' "$name" | grep -Eq -- "$only" || continue
    mesh() { "$build/fortu" run "$model" --size "$size" -o "$scratch/m.ply" --stats "$@" > "$scratch/stats" 2>&1; }
    status=0; mesh || status=$?
    if grep -q "needs a 3D model" "$scratch/stats"; then continue; fi
    if ! grep -q "comes from this header comment" "$scratch/stats" || grep -q "the mesh is empty" "$scratch/stats"; then
        status=0; mesh --domain auto || status=$?
        if [ "$status" = 2 ] && grep -q unbounded "$scratch/stats"; then status=0; mesh || status=$?; fi
    fi
    if [ "$status" != 0 ]; then echo "| $name | | | | fortu failed: $(tail -n 1 "$scratch/stats") |"; over=$((over + 1)); continue; fi
    nodes=$(grep -o '[0-9]*x[0-9]*x[0-9]* nodes' "$scratch/stats" | head -n 1 | cut -d' ' -f1)
    "$build/tests/fortu_mesh_check" "$model" "$scratch/m.ply" "$scratch/stats" --samples "$samples" > "$scratch/check"
    row=$(awk -v name="$name" -v nodes="$nodes" '{
        for (i = 1; i < NF; i++) v[$i] = $(i + 1)
        wrong = ""
        split("open overused same-direction degenerate intersecting", keys, " ")
        for (k = 1; k <= 5; k++) if (v[keys[k]] + 0 > 0) wrong = wrong " " keys[k] " " v[keys[k]]
        if (v["volume"] + 0 <= 0) wrong = wrong " inward"
        printf "| %s | %s | %s | %s | %s |", name, nodes, v["mesh-to-surface"], v["surface-to-mesh"], wrong == "" ? "ok" : wrong
        bad = (v["mesh-to-surface"] == ">1" || v["mesh-to-surface"] + 0 > 0.5 || v["surface-to-mesh"] == ">1" || v["surface-to-mesh"] + 0 > 0.5 || wrong != "")
        exit bad ? 3 : 0 }' "$scratch/check") && bad=0 || bad=$?
    echo "$row"
    [ "$bad" = 3 ] && over=$((over + 1))
done
echo
echo "$over beyond half a cell or not a closed, oriented, intersection-free mesh"
