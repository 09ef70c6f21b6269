# tests/python/test_mesh.py — m.mesh is the mesh `fortu run -o m.ply` writes, bit for bit
# (vertices, triangles and normals), on the FLOZ3 sphere and RANOK's torus; closed and
# manifold; the command line's refusals as ValueError; meshing releases the GIL and stops
# on Ctrl-C.
import os
import signal
import threading
import time
import warnings

import numpy as np
import pytest

import fortu
from conftest import EXAMPLES, SHARED_DATA, run_fortu, same_bits

TORUS = SHARED_DATA / "ranok-scripts" / "Tor.fortu"
TORUS_DOMAIN = ((-6.5, 6.5), (-6.5, 6.5), (-6.5, 6.5))   # its header comment "x : 6.5 ; y : 6.5 ; z : 6.5"


def read_ply(path):
    """The binary PLY fortu writes (runtime/mesh_io.cpp's write_ply): float64 x y z nx ny nz
    per vertex, then per face a uchar 3 and three uint32 indices, little-endian."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert header[:2] == ["ply", "format binary_little_endian 1.0"]
    counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element ")}
    properties = [line.split()[-1] for line in header if line.startswith("property double ")]
    assert properties == ["x", "y", "z", "nx", "ny", "nz"]
    vertex_bytes = counts["vertex"] * 6 * 8
    vertices = np.frombuffer(data, dtype="<f8", count=counts["vertex"] * 6, offset=end).reshape(-1, 6)
    face = np.dtype([("corners", "u1"), ("indices", "<u4", (3,))])   # packed: 13 bytes a face
    faces = np.frombuffer(data, dtype=face, count=counts["face"], offset=end + vertex_bytes)
    assert end + vertex_bytes + faces.nbytes == len(data)
    assert (faces["corners"] == 3).all()
    return vertices[:, :3], faces["indices"], vertices[:, 3:]


def cli_mesh(path, tmp_path, *options):
    out = tmp_path / "cli.ply"
    run_fortu("run", path, *options, "-o", out)
    return read_ply(out)


def edge_uses(triangles):
    """How many triangles each undirected edge is in, and whether each directed edge occurs
    once (consistent orientation: a neighbour runs the shared edge the other way)."""
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]).astype(np.int64)
    _, uses = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    _, directed_uses = np.unique(directed, axis=0, return_counts=True)
    return uses, directed_uses


@pytest.mark.parametrize("path, options, size, domain", [
    (EXAMPLES / "floz3_sphere80.fortu", [], 21, None),
    (TORUS, ["--domain", "-6.5:6.5,-6.5:6.5,-6.5:6.5"], 49, TORUS_DOMAIN),
], ids=["floz3_sphere80", "Tor"])
def test_mesh_equals_fortu_run_ply(path, options, size, domain, tmp_path):
    vertices, triangles, normals = fortu.compile(path).mesh(size=size, domain=domain)
    assert vertices.dtype == np.float64 and triangles.dtype == np.uint32 and normals.dtype == np.float64
    assert vertices.shape[1] == triangles.shape[1] == normals.shape[1] == 3
    assert len(triangles) > 1000 and len(normals) == len(vertices)
    cli_vertices, cli_triangles, cli_normals = cli_mesh(path, tmp_path, "--size", size, *options)
    assert same_bits(vertices, cli_vertices)
    assert np.array_equal(triangles, cli_triangles)
    assert same_bits(normals, cli_normals)
    uses, directed_uses = edge_uses(triangles)
    assert (uses == 2).all()   # watertight and manifold
    assert (directed_uses == 1).all()


def test_mesh_counts_and_options():
    m = fortu.compile(SHARED_DATA / "ranok-scripts" / "sphere.fortu")
    domain = ((-1.1, 1.1), (-1.1, 1.1), (-1.1, 1.1))   # its header comment "x : 1.1 ; y : 1.1 ; z : 1.1"
    vertices, triangles, normals = m.mesh(size=23, domain=domain)
    assert (len(vertices), len(triangles)) == (5582, 11160)
    assert len(vertices) - len(triangles) * 3 // 2 + len(triangles) == 2   # V - E + F: a sphere's
    assert np.abs(np.linalg.norm(normals, axis=1) - 1).max() < 1e-15
    assert (np.einsum("ij,ij->i", normals, vertices) > 0).all()   # outward
    one_thread = m.mesh(size=23, domain=domain, threads=1)
    assert same_bits(one_thread[0], vertices) and np.array_equal(one_thread[1], triangles)
    flat = m.mesh(size=23, domain=(-1.1, 1.1, -1.1, 1.1, -1.1, 1.1))   # the domain as grid() also takes it
    assert same_bits(flat[0], vertices) and np.array_equal(flat[1], triangles)
    # A surface that misses the domain: empty (0, 3) arrays.
    empty = m.mesh(size=5, domain=((2, 3), (2, 3), (2, 3)))
    assert [a.shape for a in empty] == [(0, 3), (0, 3), (0, 3)]
    assert [a.dtype for a in empty] == [np.float64, np.uint32, np.float64]


def test_constants_reach_the_mesh():
    text = "ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\nCONSTANT R = 0.55;\nRETURN R*R - X*X - Y*Y - Z*Z;\n"
    m = fortu.compile(text)
    small, large = m.mesh(size=21), m.mesh(size=21, R=0.85)
    assert np.abs(np.linalg.norm(small[0], axis=1) - 0.55).max() < 1e-12
    assert np.abs(np.linalg.norm(large[0], axis=1) - 0.85).max() < 1e-12
    direct = fortu.compile(text.replace("0.55", "0.85")).mesh(size=21)
    assert same_bits(large[0], direct[0]) and np.array_equal(large[1], direct[1])


def test_refusals_are_the_command_lines(tmp_path):
    flat = fortu.compile(EXAMPLES / "circles_or.fortu")
    with pytest.raises(ValueError) as e:
        flat.mesh(size=64)
    assert str(e.value) == "a mesh needs a 3D model (X, Y, Z); this one has 2 argument(s)"
    cli = run_fortu("run", EXAMPLES / "circles_or.fortu", "--size", 64, "-o", tmp_path / "x.ply", check=False)
    assert cli.stderr.rstrip().endswith(f"-o {tmp_path / 'x.ply'}: {e.value}")
    sphere = fortu.compile(SHARED_DATA / "ranok-scripts" / "sphere.fortu")
    with pytest.raises(ValueError) as e:
        sphere.mesh(size=(9, 1, 9))
    assert str(e.value) == "size: a mesh needs at least 2 nodes along each axis"
    with pytest.raises(ValueError) as e:
        sphere.mesh(size=1000)
    assert str(e.value) == ("1000000000 grid nodes requested, more than max_points = 268435456; "
                            "raise max_points if the time is there")
    with pytest.raises(ValueError, match="more than max_points = 1000"):
        sphere.mesh(size=11, max_points=1000)


def test_a_second_thread_runs_while_a_mesh_is_made():
    m = fortu.compile(TORUS)
    counter, running = [0], [True]

    def count():
        while running[0]:
            counter[0] += 1

    thread = threading.Thread(target=count)
    thread.start()
    try:
        time.sleep(0.05)
        before = counter[0]
        start = time.monotonic()
        # 321 nodes: long enough (0.25 s on a Zen 5) for the window to mean something.
        m.mesh(size=321, domain=TORUS_DOMAIN, threads=1)
        seconds = time.monotonic() - start
        during = counter[0] - before
    finally:
        running[0] = False
        thread.join()
    assert seconds > 0.1, seconds
    assert during > 10_000, during   # with the GIL held it would be 0


def test_ctrl_c_stops_a_long_mesh():
    m = fortu.compile(SHARED_DATA / "bear.vm")
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        m.mesh(size=513)   # about two minutes if not stopped (docs/meshing.md)
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 5, elapsed
    with warnings.catch_warnings():   # a coarse mesh may come with a note
        warnings.simplefilter("ignore", UserWarning)
        assert len(m.mesh(size=9)[1]) > 0   # the model is still usable


def test_what_the_mesh_leaves_out_is_a_warning():
    # A sheet 0.002 thick on the middle plane of 70 nodes over [-1, 1]^3 passes the centres
    # of 67 x 67 cells, more than are refined at most (the command line's note, word for
    # word). A ball cut by a slit 0.02 wide, refined where the slit is, warns of nothing.
    sheet = fortu.compile("ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\nRETURN 0.000001 - Z*Z;\n")
    with pytest.warns(UserWarning) as caught:
        sheet.mesh(size=70)
    assert [str(w.message) for w in caught] == [
        "parts of the solid thinner than a cell (or holes in it) go on beyond the 4096 cells refined for them, and "
        "are missing from the mesh in 583 more cells, the first at (-0.956522, -0.985507, 0): at a --size whose "
        "cells are smaller than the part is thick, the lattice itself meshes it"]
    slit = fortu.compile("ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\n"
                         "RETURN (0.49 - X*X - Y*Y - Z*Z) & ((Z - 0.05)^2 - 0.0001);\n")
    ball = fortu.compile("ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\nRETURN 0.49 - X*X - Y*Y - Z*Z;\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        slit.mesh(size=21)
        ball.mesh(size=21)
