"""tests/mpi/brick_files.py — what the bricks tests share: running fortu (alone or under
mpirun), recording checks, and reading the files bricked runs write with parsers of their
own (.vti's appended raw arrays, a .pvti's pieces) or HDF5's own reader (h5py, VTKHDF).

Usage in a test: `from brick_files import *`, then `setup(sys.argv)`.
"""
import os
import re
import signal
import subprocess
import time

import numpy as np

FAILURES = []
_MPIRUN = [None]

# Under AddressSanitizer, LeakSanitizer reports Open MPI's own allocations at exit (libmpi and
# its dlopened components, unmatchable by a suppression once unloaded): ranks under mpirun run
# without leak detection; every single-process run here and in the other suites keeps it.
MPI_ENV = dict(os.environ, ASAN_OPTIONS=(os.environ.get("ASAN_OPTIONS", "") + ":detect_leaks=0").lstrip(":"))


def setup(argv):
    """FORTU, SHARED, SOURCE, WORK, MPIRUN (None without) from `test.py FORTU SHARED_DIR
    SOURCE_DIR WORK_DIR [MPIRUN]`; WORK is created."""
    fortu, shared, source, work = argv[1:5]
    _MPIRUN[0] = argv[5] if len(argv) > 5 else None
    os.makedirs(work, exist_ok=True)
    return fortu, shared, source, work, _MPIRUN[0]


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        FAILURES.append(what)


def run(fortu, args, expect=0, mpi=0, shown=6):
    """`fortu run ARGS` (under mpirun with `mpi` ranks), its exit status checked."""
    cmd = ([_MPIRUN[0], "--oversubscribe", "-np", str(mpi)] if mpi else []) + [fortu, "run"] + args
    p = subprocess.run(cmd, capture_output=True, text=True, env=MPI_ENV if mpi else None)
    if p.returncode != expect:
        print("command:", " ".join(cmd), "\nexit", p.returncode, "\n", p.stdout, p.stderr)
    check(p.returncode == expect, f"exit {expect}: {' '.join(cmd[-shown:])}")
    return p


def read_vti(path):
    """Every appended array of a .vti by name, each (slices, rows, cols), checked against the
    header's offsets: the arrays follow one another, each after its UInt64 byte count."""
    data = open(path, "rb").read()
    head = data[: data.index(b"<AppendedData")].decode()
    extent = [int(v) for v in re.search(r'<Piece Extent="([^"]+)"', head).group(1).split()]
    shape = (extent[5] - extent[4] + 1, extent[3] - extent[2] + 1, extent[1] - extent[0] + 1)
    start = data.index(b"_", data.index(b"<AppendedData")) + 1
    arrays = {}
    at = 0
    for name, offset in re.findall(r'<DataArray type="Float64" Name="([^"]+)" format="appended" offset="(\d+)"/>',
                                   head):
        assert int(offset) == at, (name, offset, at)
        size = int(np.frombuffer(data[start + at:start + at + 8], dtype="<u8")[0])
        assert size == 8 * shape[0] * shape[1] * shape[2], (name, size, shape)
        arrays[name] = np.frombuffer(data[start + at + 8:start + at + 8 + size], dtype="<f8").reshape(shape)
        at += 8 + size
    assert data[start + at:] == b"\n  </AppendedData>\n</VTKFile>\n", data[start + at:][:40]
    return arrays


def read_pvti(path):
    """The arrays of a .pvti's pieces put together, and the number of pieces; checks that the
    pieces tile the extent along Z with one shared plane between neighbours, equal in both,
    that each piece has the index's origin, and that the index names every array."""
    text = open(path).read()
    whole = [int(v) for v in re.search(r'<PImageData WholeExtent="([^"]+)"', text).group(1).split()]
    origin = re.search(r'<PImageData[^>]* Origin="([^"]+)"', text).group(1)
    names = re.findall(r'<PDataArray type="Float64" Name="([^"]+)"/>', text)
    shape = (whole[5] + 1, whole[3] + 1, whole[1] + 1)
    volumes = {name: np.full(shape, np.nan) for name in names}
    pieces = re.findall(r'<Piece Extent="([^"]+)" Source="([^"]+)"/>', text)
    expected_first = 0
    for extent, source in pieces:
        e = [int(v) for v in extent.split()]
        assert e[:4] == whole[:4] and e[4] == expected_first, (e, expected_first)
        piece_path = os.path.join(os.path.dirname(path), source)
        head = open(piece_path, "rb").read(600).decode(errors="replace")
        assert f'WholeExtent="{extent}"' in head and f'Origin="{origin}"' in head, head
        arrays = read_vti(piece_path)
        assert sorted(arrays) == sorted(names), (list(arrays), names)
        for name in names:
            assert arrays[name].shape == (e[5] - e[4] + 1, shape[1], shape[2]), arrays[name].shape
            if e[4] > 0:   # the shared plane, written twice, equal
                assert np.array_equal(volumes[name][e[4]].view("<u8"), arrays[name][0].view("<u8")), name
            volumes[name][e[4]:e[5] + 1] = arrays[name]
        expected_first = e[5]
    assert expected_first == whole[5], (expected_first, whole)
    return volumes, len(pieces)


def read_vtkhdf(path):
    """A VTKHDF ImageData's point arrays by name, its origin and spacing (h5py)."""
    import h5py
    with h5py.File(path, "r") as f:
        g = f["VTKHDF"]
        assert list(g.attrs["Version"]) == [1, 0] and g.attrs["Type"] in (b"ImageData", "ImageData")
        arrays = {name: g["PointData"][name][()] for name in g["PointData"]}
        shape = arrays["value"].shape
        extent = list(g.attrs["WholeExtent"])
        assert extent == [0, shape[2] - 1, 0, shape[1] - 1, 0, shape[0] - 1], extent
        assert list(g.attrs["Direction"]) == [1, 0, 0, 0, 1, 0, 0, 0, 1]
        return arrays, list(g.attrs["Origin"]), list(g.attrs["Spacing"])


def read_any(path):
    """The arrays of a .vti, .pvti or .hdf by name."""
    if path.endswith(".pvti"):
        return read_pvti(path)[0]
    if path.endswith(".hdf"):
        return read_vtkhdf(path)[0]
    return read_vti(path)


def vti_origin_spacing(path):
    head = open(path, "rb").read(600).decode(errors="replace")
    origin = [float(v) for v in re.search(r' Origin="([^"]+)"', head).group(1).split()]
    spacing = [float(v) for v in re.search(r' Spacing="([^"]+)"', head).group(1).split()]
    return origin, spacing


def same_values(a, b):
    """Bit for bit (a NaN equals the same NaN)."""
    return a.shape == b.shape and np.array_equal(a.view("<u8"), b.view("<u8"))


def same_arrays(ref, got, names):
    """The arrays `names` of `got` are exactly those, each equal to `ref`'s bit for bit."""
    return sorted(got) == sorted(names) and all(same_values(ref[n], got[n]) for n in names)


def vdb_bytes(path):
    """A .vdb's bytes but its archive UUID (the same tree encodes to the same bytes)."""
    uuid = rb"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}"
    return re.sub(uuid, b"UUID", open(path, "rb").read(), count=1)


def kill_one_rank(fortu, args, target, what):
    """`fortu run ARGS` on 4 ranks writing `target` (old files removed first); one rank is
    killed with SIGKILL once the done map holds 20 bricks. Returns the job's exit status."""
    for stale in (target, target + ".done"):
        if os.path.exists(stale):
            os.remove(stale)
    job = subprocess.Popen([_MPIRUN[0], "--oversubscribe", "-np", "4", fortu, "run"] + args,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=MPI_ENV)
    done_map = target + ".done"
    deadline = time.time() + 120
    while time.time() < deadline:
        if os.path.exists(done_map) and len(open(done_map).read().splitlines()) > 1 + 20:
            break
        time.sleep(0.005)
    ranks = subprocess.run(["ps", "-o", "pid=,args=", "--ppid", str(job.pid)], capture_output=True,
                           text=True).stdout.split("\n")
    pids = [int(line.split()[0]) for line in ranks if fortu in line]
    check(len(pids) == 4, f"{what}: 4 ranks found under mpirun ({len(pids)})")
    if pids:
        os.kill(pids[1], signal.SIGKILL)
    job.wait(timeout=120)
    return job.returncode
