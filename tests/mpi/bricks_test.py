#!/usr/bin/python3
"""tests/mpi/bricks_test.py — bricked runs (--memory, mpirun, --resume) against the in-memory run.

Reads every .vti and .pvti with its own parser (XML header, raw appended Float64 array,
numpy) and every VTKHDF .hdf with HDF5's own reader (h5py), and compares values bit for
bit; a .vdb is compared byte for byte except its archive UUID (the same tree encodes to
the same bytes). Usage:
  bricks_test.py FORTU SHARED_DIR SOURCE_DIR WORK_DIR [MPIRUN]
Without MPIRUN only the single-process checks run.
"""
import os
import re
import sys

import numpy as np

import brick_files
from brick_files import (FAILURES, check, read_pvti, read_vti, read_vtkhdf, same_values, vdb_bytes,
                         vti_origin_spacing)

FORTU, SHARED, SOURCE, WORK, MPIRUN = brick_files.setup(sys.argv)


def run(args, expect=0, mpi=0):
    return brick_files.run(FORTU, args, expect, mpi)


def same_vti(a, b):
    return same_values(read_vti(a)["value"], read_vti(b)["value"])


def same_as_vti(ref, got):
    """A .vti, .pvti or .hdf equals the reference .vti value for value."""
    if got.endswith(".pvti"):
        return same_values(read_vti(ref)["value"], read_pvti(got)[0]["value"])
    if got.endswith(".hdf"):
        arrays, origin, spacing = read_vtkhdf(got)
        return same_values(read_vti(ref)["value"], arrays["value"]) and (origin, spacing) == vti_origin_spacing(ref)
    return same_vti(ref, got)


MODELS = [
    ("sphere", os.path.join(SOURCE, "examples", "floz3_sphere80.fortu"), 41),
    ("tor", os.path.join(SHARED, "data", "ranok-scripts", "Tor.fortu"), 37),
    ("bear", os.path.join(SHARED, "data", "bear.vm"), 33),
]


def out(name):
    return os.path.join(WORK, name)


# In memory, then in bricks on one process: the same values, the same .vdb.
for name, model, size in MODELS:
    for ext in ("vti", "vdb"):
        ref = out(f"{name}_mem.{ext}")
        run([model, "--size", str(size), "-o", ref])
        got = out(f"{name}_bricks.{ext}")
        run([model, "--size", str(size), "--memory", "1G", "--brick", "16", "-o", got])
        same = same_vti(ref, got) if ext == "vti" else vdb_bytes(ref) == vdb_bytes(got)
        check(same, f"{name}: bricked .{ext} equals the in-memory one")
        check(not os.path.exists(got + ".done"), f"{name}: the done map is removed when the .{ext} is complete")

# .pvti (pieces by layers of bricks) and VTKHDF .hdf: always bricked, equal to the .vti.
for name, model, size in MODELS:
    ref = out(f"{name}_mem.vti")
    got = out(f"{name}_bricks.pvti")
    run([model, "--size", str(size), "--brick", "16", "-o", got])
    check(same_as_vti(ref, got), f"{name}: .pvti pieces equal the in-memory .vti")
    check(read_pvti(got)[1] > 1, f"{name}: the .pvti has a piece per layer of bricks ({read_pvti(got)[1]})")
    got = out(f"{name}_bricks.hdf")
    run([model, "--size", str(size), "--memory", "1G", "--brick", "16", "-o", got])
    check(same_as_vti(ref, got), f"{name}: VTKHDF .hdf (read by h5py) equals the in-memory .vti")
    check(not os.path.exists(got + ".done"), f"{name}: the done map is removed when the .hdf is complete")

# A bound that cannot hold one brick is refused before any work.
p = run([MODELS[0][1], "--size", "64", "--memory", "1M", "-o", out("refused.vti")], expect=2)
check("--memory 1.0 MiB: one brick of 128³ nodes needs about" in p.stderr and not os.path.exists(out("refused.vti")),
      "--memory too small: refused with the brick's need")

# A sweep: one run per value of CONSTANT R, each equal to the run with that value written in.
disc = out("disc.fortu")
open(disc, "w").write("ARGUMENT X(-1, 1), Y(-1, 1);\nCONSTANT R = 0.5;\nRETURN R^2 - X^2 - Y^2;\n")
run([disc, "--size", "17", "--set", "R=0.1:1.0:0.1", "-o", out("sweep_%R.npy")])
names = ["0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1"]
check(all(os.path.exists(out(f"sweep_{n}.npy")) for n in names), "sweep: one file per value, named by %R")
for n in ("0.3", "1"):
    written = out(f"disc_{n}.fortu")
    open(written, "w").write(f"ARGUMENT X(-1, 1), Y(-1, 1);\nCONSTANT R = {n};\nRETURN R^2 - X^2 - Y^2;\n")
    run([written, "--size", "17", "-o", out(f"disc_{n}.npy")])
    check(open(out(f"disc_{n}.npy"), "rb").read() == open(out(f"sweep_{n}.npy"), "rb").read(),
          f"sweep: R={n} equals the script with R = {n}")
p = run([disc, "--size", "17", "--set", "R=0.1:0.3:0.1", "-o", out("same.npy")], expect=2)
check("--set R: '" in p.stderr and "has no %R, so every run would overwrite it" in p.stderr,
      "sweep: a path without %R is refused")

# A 2D run to .hdf and .pvti: the field written as one brick, one slice.
run([disc, "--size", "17", "-o", out("disc2d.npy")])
run([disc, "--size", "17", "-o", out("disc2d.hdf")])
run([disc, "--size", "17", "-o", out("disc2d.pvti")])
flat = np.load(out("disc2d.npy"))[::-1]   # image rows from the top; volume rows from the bottom
check(same_values(flat, read_vtkhdf(out("disc2d.hdf"))[0]["value"][0]), "2D .hdf equals the .npy")
check(same_values(flat, read_pvti(out("disc2d.pvti"))[0]["value"][0]), "2D .pvti equals the .npy")

if MPIRUN:
    # The sweep's runs shared out over 3 ranks: the same files.
    run([disc, "--size", "17", "--set", "R=0.1:1.0:0.1", "-o", out("msweep_%R.npy")], mpi=3)
    check(all(open(out(f"msweep_{n}.npy"), "rb").read() == open(out(f"sweep_{n}.npy"), "rb").read() for n in names),
          "sweep over 3 ranks: every file equals the single-process one")

    # Over 4 ranks (oversubscribed on this machine): the same files.
    for name, model, size in MODELS:
        for ext in ("vti", "vdb"):
            got = out(f"{name}_mpi.{ext}")
            run([model, "--size", str(size), "--brick", "8", "--threads", "1", "-o", got], mpi=4)
            ref = out(f"{name}_mem.{ext}")
            same = same_vti(ref, got) if ext == "vti" else vdb_bytes(ref) == vdb_bytes(got)
            check(same, f"{name}: 4 ranks' .{ext} equals the single-process one")

    # .pvti: one piece per rank; VTKHDF: one file written by the 4 ranks through parallel HDF5.
    for name, model, size in MODELS:
        ref = out(f"{name}_mem.vti")
        got = out(f"{name}_mpi.pvti")
        run([model, "--size", str(size), "--brick", "8", "--threads", "1", "-o", got], mpi=4)
        check(same_as_vti(ref, got), f"{name}: 4 ranks' .pvti pieces equal the single-process .vti")
        check(read_pvti(got)[1] == 4, f"{name}: the .pvti has one piece per rank ({read_pvti(got)[1]})")
        got = out(f"{name}_mpi.hdf")
        run([model, "--size", str(size), "--brick", "8", "--threads", "2", "-o", got], mpi=4)
        check(same_as_vti(ref, got), f"{name}: 4 ranks' VTKHDF .hdf (read by h5py) equals the single-process .vti")

    # Resume: SIGKILL one rank mid-run; the job ends; --resume computes only the missing bricks.
    for ext in ("vti", "vdb", "hdf"):
        # Big enough that the kill comes between the first batch of the done map (a second in)
        # and the end: the .vdb skips most points, so it takes more of them.
        model, size = MODELS[2][1], 161 if ext == "vdb" else 97
        ref = out(f"resume_ref.{'vdb' if ext == 'vdb' else 'vti'}")
        if ext != "hdf":   # the .hdf compares with the .vti made just before
            run([model, "--size", str(size), "-o", ref])
        target = out(f"resume.{ext}")
        status = brick_files.kill_one_rank(FORTU, [model, "--size", str(size), "--brick", "8", "--threads", "1",
                                                   "-o", target], target, f".{ext}")
        done_map = target + ".done"
        check(status != 0, f".{ext}: the job ended with the killed rank (exit {status})")
        check(not os.path.exists(target), f".{ext}: no output after the kill")
        before = len(set(open(done_map).read().splitlines()[1:]))
        # .vdb: 161 nodes in cubes of 8³; .vti, .hdf: 97 in whole rows, 97 x 2 x 2 (about 8³ nodes)
        total = 21 * 21 * 21 if ext == "vdb" else 49 * 49
        shape = "8x8x8" if ext == "vdb" else "97x2x2"
        p = run([model, "--size", str(size), "--brick", "8", "--threads", "1", "--resume", "--stats", "-o", target])
        m = re.search(r"(\d+) bricks of " + shape + r" nodes \((\d+) from the done map, (\d+) computed\)", p.stdout)
        check(m is not None, f".{ext}: --stats counts the bricks")
        if m:
            check(int(m.group(1)) == total and int(m.group(2)) == before and int(m.group(3)) == total - before,
                  f".{ext}: resumed {m.group(2)} bricks from the done map ({before} recorded), computed {m.group(3)}")
            check(0 < before < total, f".{ext}: the kill came mid-run ({before} of {total} bricks done)")
        same = vdb_bytes(ref) == vdb_bytes(target) if ext == "vdb" else same_as_vti(ref, target)
        check(same, f".{ext}: the resumed result equals an uninterrupted run")

print(f"{len(FAILURES)} failure(s)")
sys.exit(1 if FAILURES else 0)
