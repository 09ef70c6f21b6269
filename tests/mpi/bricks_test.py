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
import signal
import subprocess
import sys
import time

import numpy as np

FORTU, SHARED, SOURCE, WORK = sys.argv[1:5]
MPIRUN = sys.argv[5] if len(sys.argv) > 5 else None
os.makedirs(WORK, exist_ok=True)
FAILURES = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        FAILURES.append(what)


# Under AddressSanitizer, LeakSanitizer reports Open MPI's own allocations at exit (libmpi and
# its dlopened components, unmatchable by a suppression once unloaded): ranks under mpirun run
# without leak detection; every single-process run here and in the other suites keeps it.
MPI_ENV = dict(os.environ, ASAN_OPTIONS=(os.environ.get("ASAN_OPTIONS", "") + ":detect_leaks=0").lstrip(":"))


def run(args, expect=0, mpi=0):
    cmd = ([MPIRUN, "--oversubscribe", "-np", str(mpi)] if mpi else []) + [FORTU, "run"] + args
    p = subprocess.run(cmd, capture_output=True, text=True, env=MPI_ENV if mpi else None)
    if p.returncode != expect:
        print("command:", " ".join(cmd), "\nexit", p.returncode, "\n", p.stdout, p.stderr)
    check(p.returncode == expect, f"exit {expect}: {' '.join(cmd[-6:])}")
    return p


def read_vti(path):
    data = open(path, "rb").read()
    head = data[: data.index(b"<AppendedData")].decode()
    extent = [int(v) for v in re.search(r'WholeExtent="([^"]+)"', head).group(1).split()]
    nx, ny, nz = extent[1] - extent[0] + 1, extent[3] - extent[2] + 1, extent[5] - extent[4] + 1
    start = data.index(b"_", data.index(b"<AppendedData")) + 1
    size = int(np.frombuffer(data[start:start + 8], dtype="<u8")[0])
    assert size == 8 * nx * ny * nz, (size, nx, ny, nz)
    values = np.frombuffer(data[start + 8:start + 8 + size], dtype="<f8").reshape(nz, ny, nx)
    assert data[start + 8 + size:].startswith(b"\n  </AppendedData>")
    return values


def same_vti(a, b):
    va, vb = read_vti(a), read_vti(b)
    return va.shape == vb.shape and np.array_equal(va.view("<u8"), vb.view("<u8"))


def read_pvti(path):
    """The whole volume from a .pvti and its pieces; checks that the pieces tile the extent
    along Z with one shared plane between neighbours and agree on it."""
    text = open(path).read()
    whole = [int(v) for v in re.search(r'<PImageData WholeExtent="([^"]+)"', text).group(1).split()]
    origin = re.search(r'<PImageData[^>]* Origin="([^"]+)"', text).group(1)
    pieces = re.findall(r'<Piece Extent="([^"]+)" Source="([^"]+)"/>', text)
    nx, ny, nz = whole[1] + 1, whole[3] + 1, whole[5] + 1
    volume = np.full((nz, ny, nx), np.nan)
    expected_first = 0
    for extent, source in pieces:
        e = [int(v) for v in extent.split()]
        assert e[:4] == whole[:4] and e[4] == expected_first, (e, expected_first)
        piece_path = os.path.join(os.path.dirname(path), source)
        head = open(piece_path, "rb").read(600).decode(errors="replace")
        assert f'WholeExtent="{extent}"' in head and f'Origin="{origin}"' in head, head
        values = read_vti(piece_path)
        assert values.shape == (e[5] - e[4] + 1, ny, nx), values.shape
        if e[4] > 0:   # the shared plane, written twice, equal
            assert np.array_equal(volume[e[4]].view("<u8"), values[0].view("<u8"))
        volume[e[4]:e[5] + 1] = values
        expected_first = e[5]
    assert expected_first == whole[5], (expected_first, whole)
    return volume, len(pieces)


def read_vtkhdf(path):
    import h5py
    with h5py.File(path, "r") as f:
        g = f["VTKHDF"]
        assert list(g.attrs["Version"]) == [1, 0] and g.attrs["Type"] in (b"ImageData", "ImageData")
        values = g["PointData"]["value"][()]
        extent = list(g.attrs["WholeExtent"])
        assert extent == [0, values.shape[2] - 1, 0, values.shape[1] - 1, 0, values.shape[0] - 1], extent
        assert list(g.attrs["Direction"]) == [1, 0, 0, 0, 1, 0, 0, 0, 1]
        return values, list(g.attrs["Origin"]), list(g.attrs["Spacing"])


def vti_origin_spacing(path):
    head = open(path, "rb").read(600).decode(errors="replace")
    origin = [float(v) for v in re.search(r' Origin="([^"]+)"', head).group(1).split()]
    spacing = [float(v) for v in re.search(r' Spacing="([^"]+)"', head).group(1).split()]
    return origin, spacing


def same_values(a, b):
    return a.shape == b.shape and np.array_equal(a.view("<u8"), b.view("<u8"))


def same_as_vti(ref, got):
    """A .vti, .pvti or .hdf equals the reference .vti value for value."""
    if got.endswith(".pvti"):
        return same_values(read_vti(ref), read_pvti(got)[0])
    if got.endswith(".hdf"):
        values, origin, spacing = read_vtkhdf(got)
        return same_values(read_vti(ref), values) and (origin, spacing) == vti_origin_spacing(ref)
    return same_vti(ref, got)


def vdb_bytes(path):
    uuid = rb"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}"
    return re.sub(uuid, b"UUID", open(path, "rb").read(), count=1)


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
check(same_values(flat, read_vtkhdf(out("disc2d.hdf"))[0][0]), "2D .hdf equals the .npy")
check(same_values(flat, read_pvti(out("disc2d.pvti"))[0][0]), "2D .pvti equals the .npy")

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
        for stale in (target, target + ".done"):
            if os.path.exists(stale):
                os.remove(stale)
        job = subprocess.Popen([MPIRUN, "--oversubscribe", "-np", "4", FORTU, "run", model, "--size", str(size),
                                "--brick", "8", "--threads", "1", "-o", target],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=MPI_ENV)
        done_map = target + ".done"
        deadline = time.time() + 120
        while time.time() < deadline:
            if os.path.exists(done_map) and len(open(done_map).read().splitlines()) > 1 + 20:
                break
            time.sleep(0.005)
        ranks = subprocess.run(["ps", "-o", "pid=,args=", "--ppid", str(job.pid)], capture_output=True,
                               text=True).stdout.split("\n")
        pids = [int(line.split()[0]) for line in ranks if FORTU in line]
        check(len(pids) == 4, f".{ext}: 4 ranks found under mpirun ({len(pids)})")
        if pids:
            os.kill(pids[1], signal.SIGKILL)
        job.wait(timeout=120)
        check(job.returncode != 0, f".{ext}: the job ended with the killed rank (exit {job.returncode})")
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
