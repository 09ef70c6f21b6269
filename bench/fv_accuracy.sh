#!/bin/sh
# bench/fv_accuracy.sh — the fv engine's error against exact evaluation (the voxel engine) on
# the examples that reproduce the papers' figures, at P = 256, P = 2^24 and unquantised: a
# Markdown table for docs/fv-method.md ("Accuracy"). Usage: bench/fv_accuracy.sh [FORTU] [SIZE2D] [SIZE3D]
# (default build/release/fortu, 200, 32). Columns: max |fv - exact| / largest |exact| (the
# field's magnitude), RMS, nodes whose sign differs.
set -eu
fortu=${1:-build/release/fortu}
size2=${2:-200}
size3=${3:-32}
examples=$(dirname "$0")/../examples
echo "| example (figure) | grid | P = 256: max / magnitude, RMS, sign differs | P = 2^24 | unquantised |"
echo "|---|---|---|---|---|"
for name in circles_parabola circles_parabola_and circles_or parabola_not s1_fig3a_formula s1_fig3a_floz \
            s1_fig4a_arcs s1_fig4b_inner s1_fig7_bezier s1_fig8_predicate lrfm_polygon14 lrfm_triangle_floz \
            vyatkin_analytic; do
    model="$examples/$name.fortu"
    size=$size2
    case $name in lrfm_triangle_floz|vyatkin_analytic) size=$size3 ;; esac
    row="| $name | $size |"
    for palette in 8 24 float; do
        report=$("$fortu" run "$model" --engine fv --palette "$palette" --size "$size" --compare voxel 2>/dev/null)
        cell=$(printf '%s\n' "$report" | awk '
            /max \|difference\|/ { max = $3; for (i = 1; i <= NF; i++) if ($i == "|value|") magnitude = $(i + 1) }
            /RMS difference/ { rms = $3 }
            /sign differs at/ { signs = $4 }
            /invalid in only one/ { invalid = $(NF - 1) }
            END { note = ""; if (invalid + 0 > 0) note = " (" invalid " invalid in one)"; printf "%.3g, %.3g, %s%s", max / magnitude, rms, signs, note }')
        row="$row $cell |"
    done
    echo "$row"
done
