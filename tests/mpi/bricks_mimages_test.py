#!/usr/bin/python3
"""tests/mpi/bricks_mimages_test.py — M-images (--mimages) of bricked runs against the in-memory run.

A bricked run evaluates each brick one node further on its forward sides, so the FV model's
components n1..n5 of its nodes equal those of the whole field: this checks it bit for bit,
for .vti (read by this test's own parser of the appended arrays), .pvti (its pieces) and
VTKHDF .hdf (HDF5's own reader, h5py), with bricks that do not divide the grid, under
mpirun, and after a kill and --resume. Usage:
  bricks_mimages_test.py FORTU SHARED_DIR SOURCE_DIR WORK_DIR [MPIRUN]
Without MPIRUN only the single-process checks run.
"""
import os
import re
import sys

import numpy as np

import brick_files
from brick_files import FAILURES, check, read_any, read_pvti, read_vti, read_vtkhdf, vdb_bytes

FORTU, SHARED, SOURCE, WORK, MPIRUN = brick_files.setup(sys.argv)
ARRAYS = ["value", "n1", "n2", "n3", "n4", "n5"]


def run(args, expect=0, mpi=0):
    return brick_files.run(FORTU, args, expect, mpi, shown=8)


def same_arrays(ref, got, names=ARRAYS):
    return brick_files.same_arrays(ref, got, names)


def out(name):
    return os.path.join(WORK, name)


MODELS = [
    ("sphere", os.path.join(SOURCE, "examples", "floz3_sphere80.fortu")),
    ("tor", os.path.join(SHARED, "data", "ranok-scripts", "Tor.fortu")),
    ("bear", os.path.join(SHARED, "data", "bear.vm")),
]
SIZE = 37   # 16 and 8 divide none of its axes

# The in-memory references: the value alone (-o) and the value with n1..n5 (--mimages).
REF = {}
for name, model in MODELS:
    run([model, "--size", str(SIZE), "-o", out(f"{name}_mem.vti"), "--mimages", out(f"{name}_mem_m.vti")])
    REF[name] = read_vti(out(f"{name}_mem_m.vti"))
    check(same_arrays(REF[name], {"value": read_vti(out(f"{name}_mem.vti"))["value"]}, ["value"]),
          f"{name}: the in-memory M-images file holds the -o file's values")
    finite = np.isfinite(REF[name]["n4"])
    check(finite.sum() > 0.9 * finite.size, f"{name}: the reference's components are mostly finite")

# One process in bricks: .vti, .pvti and .hdf, bricks of 16 and 8 (about 16³ and 8³ nodes).
for name, model in MODELS:
    for brick in (16, 8):
        for ext in ("vti", "pvti", "hdf"):
            got = out(f"{name}_b{brick}_m.{ext}")
            run([model, "--size", str(SIZE), "--memory", "1G", "--brick", str(brick), "--mimages", got])
            check(same_arrays(REF[name], read_any(got)), f"{name}: bricks of {brick}, --mimages .{ext} equals the "
                                                          "in-memory value and n1..n5 bit for bit")
            check(not os.path.exists(got + ".done"), f"{name}: no done map left beside the .{ext}")
            if ext == "vti":
                check(open(got, "rb").read() == open(out(f"{name}_mem_m.vti"), "rb").read(),
                      f"{name}: bricks of {brick}, the --mimages .vti is byte for byte the in-memory one")

# -o and --mimages together: each file as in memory. A .vdb cuts cubes, so the M-images
# bricks are cubes of 16³ here (not whole rows), and every value is computed for them.
for name, model in MODELS:
    run([model, "--size", str(SIZE), "-o", out(f"{name}_mem.vdb")])
    got_o, got_m = out(f"{name}_both.vdb"), out(f"{name}_both_m.vti")
    run([model, "--size", str(SIZE), "--memory", "1G", "--brick", "16", "-o", got_o, "--mimages", got_m])
    check(vdb_bytes(out(f"{name}_mem.vdb")) == vdb_bytes(got_o), f"{name}: -o .vdb beside --mimages equals in memory")
    check(same_arrays(REF[name], read_vti(got_m)), f"{name}: --mimages .vti in cubes of 16³ equals the in-memory one")
    got_o = out(f"{name}_both.hdf")
    run([model, "--size", str(SIZE), "--brick", "8", "-o", got_o, "--mimages", out(f"{name}_both_m.hdf")])
    check(same_arrays(REF[name], read_vtkhdf(got_o)[0], ["value"]) and
          same_arrays(REF[name], read_vtkhdf(out(f"{name}_both_m.hdf"))[0]),
          f"{name}: -o .hdf holds the value, --mimages .hdf the value and n1..n5")

# The grid's far sides: bricks one node thick at the last slice and the top row take their
# backward neighbour (as the whole field does), which lies in the brick before.
for size in (9, 17):
    run([MODELS[0][1], "--size", str(size), "--mimages", out(f"thin_mem_{size}.vti")])
    run([MODELS[0][1], "--size", str(size), "--memory", "1G", "--brick", "8", "--mimages", out(f"thin_{size}.hdf")])
    check(same_arrays(read_vti(out(f"thin_mem_{size}.vti")), read_vtkhdf(out(f"thin_{size}.hdf"))[0]),
          f"sphere {size}³ in bricks of 8: the last layer's components equal the in-memory ones")

# 2D: --mimages to .hdf and .pvti hold the same arrays as the .vti (n1..n4).
disc = out("disc.fortu")
open(disc, "w").write("ARGUMENT X(-1, 1), Y(-1, 1);\nRETURN 0.25 - X^2 - Y^2;\n")
run([disc, "--size", "19", "--mimages", out("disc_m.vti")])
flat = read_vti(out("disc_m.vti"))
for ext in ("hdf", "pvti"):
    run([disc, "--size", "19", "--mimages", out(f"disc_m.{ext}")])
    check(same_arrays(flat, read_any(out(f"disc_m.{ext}")), ARRAYS[:5]), f"2D --mimages .{ext} equals the .vti")

# Refusals: the formats that cannot hold the components, and the fv engine with its reason.
p = run([MODELS[0][1], "--size", "17", "--memory", "1G", "--mimages", out("m.vdb")], expect=2)
check("--mimages: OpenVDB holds the value alone (narrow band, --band); M-images need a .exr, .vti, .pvti or .hdf file "
      "or a picture series such as 'm_%d.png'" in p.stderr, "--mimages .vdb: refused, naming what takes M-images")
p = run([MODELS[0][1], "--size", "17", "--memory", "1G", "-o", out("v.vti"), "--mimages", out("m.exr")], expect=2)
check("--mimages m.exr: a bricked run writes M-images brick by brick to .vti, .pvti or .hdf (the value and n1..n5 "
      "as point data)" in p.stderr.replace(out(""), ""), "--mimages .exr in a bricked run: refused with the formats")
p = run([MODELS[0][1], "--size", "17", "--memory", "1G", "--engine", "fv", "-o", out("fv.vti")], expect=2)
check("is not one of them: its value at a node is composed from the M-images of every operation, "
      "so it depends on neighbours through the whole model and no overlap of bricks can make it exact"
      in p.stderr, "--engine fv in bricks: refused with the reason")
p = run([MODELS[2][1], "--size", "64", "--memory", "1M", "--mimages", out("refused_m.vti")], expect=2)
check("(with its overlap and the M-images' 5 components)" in p.stderr and not os.path.exists(out("refused_m.vti")),
      "--memory too small for a brick with components: refused with the brick's need")

if MPIRUN:
    # 4 ranks (oversubscribed): the same components in .vti, .pvti (one piece per rank) and
    # the one .hdf written collectively.
    for name, model in MODELS:
        for ext in ("vti", "pvti", "hdf"):
            got = out(f"{name}_mpi_m.{ext}")
            run([model, "--size", str(SIZE), "--brick", "8", "--threads", "1", "--mimages", got], mpi=4)
            check(same_arrays(REF[name], read_any(got)), f"{name}: 4 ranks' --mimages .{ext} equals the in-memory one")
            if ext == "pvti":
                check(read_pvti(got)[1] == 4, f"{name}: the M-images .pvti has one piece per rank")
        got_o, got_m = out(f"{name}_mpi_both.hdf"), out(f"{name}_mpi_both_m.pvti")
        run([model, "--size", str(SIZE), "--brick", "16", "--threads", "2", "-o", got_o, "--mimages", got_m], mpi=4)
        check(same_arrays(REF[name], read_vtkhdf(got_o)[0], ["value"]) and same_arrays(REF[name], read_pvti(got_m)[0]),
              f"{name}: 4 ranks' -o .hdf beside --mimages .pvti equal the in-memory files")

    # Resume: SIGKILL one rank mid-run, then --resume on one process computes only the
    # missing bricks, and the components equal an uninterrupted run's.
    model, size = MODELS[2][1], 97
    run([model, "--size", str(size), "--mimages", out("resume_ref_m.vti")])
    ref = read_vti(out("resume_ref_m.vti"))
    for ext in ("vti", "hdf"):
        target = out(f"resume_m.{ext}")
        status = brick_files.kill_one_rank(FORTU, [model, "--size", str(size), "--brick", "8", "--threads", "1",
                                                   "--mimages", target], target, f"--mimages .{ext}")
        done_map = target + ".done"
        check(status != 0 and not os.path.exists(target), f"--mimages .{ext}: the job ended with the kill")
        lines = open(done_map).read().splitlines()
        check(f"; mimages .{ext}" in lines[0], f"--mimages .{ext}: the done map's key names the M-images file")
        before = len(set(lines[1:]))
        # The same file as -o (values only) is another run: its done map is refused, not mixed in.
        p = run([model, "--size", str(size), "--brick", "8", "--resume", "-o", target], expect=1)
        check("was written by another run" in p.stderr, f"--mimages .{ext}: a values-only resume is refused")
        p = run([model, "--size", str(size), "--brick", "8", "--threads", "1", "--resume", "--stats",
                 "--mimages", target])
        total = 49 * 49   # 97 nodes in whole rows of 97 x 2 x 2 nodes
        m = re.search(r"(\d+) bricks of 97x2x2 nodes \((\d+) from the done map, (\d+) computed\)", p.stdout)
        check(m is not None and int(m.group(1)) == total and int(m.group(2)) == before and
              int(m.group(3)) == total - before and 0 < before < total,
              f"--mimages .{ext}: resumed {before} of {total} bricks from the done map, computed the rest")
        check(same_arrays(ref, read_any(target)), f"--mimages .{ext}: the resumed file equals an uninterrupted run")

print(f"{len(FAILURES)} failure(s)")
sys.exit(1 if FAILURES else 0)
