# tests/python/test_values.py — fortu from Python gives the command line's values bit for bit:
# m.eval against `fortu eval`, m.grid against `fortu run -o x.npy`, on the examples and the
# RANOK scripts; broadcasting; CONSTANT values per call; gradient, sign, M-images, IR.
import pickle

import numpy as np
import pytest

import fortu
from conftest import EXAMPLES, SHARED_DATA, cli_eval, cli_grid, run_fortu, same_bits

EXAMPLE_MODELS = ["circles_or", "circles_parabola_and", "s1_fig3a_floz", "s1_fig3a_formula", "s1_fig4a_arcs",
                  "s1_fig7_bezier", "lrfm_polygon14", "singular_pentagon", "parabola_not", "pawn"]
RANOK_MODELS = ["Bone", "Chainik", "TeaCup", "Tor", "economf", "new_2dspace", "sphere", "Pawn",
                "xsin_PIy_a__plus_y2cos_PIx_a_"]
MODELS = [EXAMPLES / f"{name}.fortu" for name in EXAMPLE_MODELS] + \
         [SHARED_DATA / "ranok-scripts" / f"{name}.fortu" for name in RANOK_MODELS]


def points_of(model):
    """A few points inside each model's box, off the grid nodes."""
    grid = model.grid(size=2)
    corners = [grid.x[0], grid.x[-1]], [grid.y[-1], grid.y[0]]
    ts = [0.13, 0.5, 0.77]
    points = [[lo + t * (hi - lo) for (lo, hi), t in zip(zip(*zip(*corners)), (t, 1 - t))] for t in ts]
    if model.dims == 3:
        z = grid.z
        points = [p + [z[0] + t * (z[-1] - z[0])] for p, t in zip(points, ts)]
    return points


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_eval_equals_fortu_eval(path):
    m = fortu.compile(path)
    for point in points_of(m):
        value, gradient = cli_eval(path, *point)
        assert same_bits(m.eval(*point), value), (point, m.eval(*point), value)
        if gradient is not None:
            assert same_bits(m.gradient(*point), gradient)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_grid_equals_fortu_run_npy(path, tmp_path):
    m = fortu.compile(str(path))
    size = 24 if m.dims == 3 else 96
    field = m.grid(size=size)
    assert same_bits(field.values, cli_grid(path, tmp_path, "--size", size))
    assert np.shares_memory(np.asarray(field), field.values)
    # The same points through eval (arbitrary points, no grid): the same bits.
    if m.dims == 3:
        z, y, x = np.meshgrid(field.z, field.y, field.x, indexing="ij")
        assert same_bits(m.eval(x, y, z), field.values)
    else:
        assert same_bits(m.eval(field.x[None, :], field.y[:, None]), field.values)


def test_grid_options_match_the_command_line(tmp_path):
    path = EXAMPLES / "s1_fig3a_floz.fortu"
    m = fortu.compile(path)
    f = m.grid(size=(120, 80), domain=((-2, 3), (-1, 4)))
    assert f.values.shape == (80, 120)
    assert same_bits(f.values, cli_grid(path, tmp_path, "--size", "120x80", "--domain", "-2:3,-1:4"))
    assert f.x[0] == -2 and f.x[-1] == 3 and f.y[0] == 4 and f.y[-1] == -1   # row 0 is the largest Y
    assert f.domain == ((-2.0, 3.0), (-1.0, 4.0))
    classic = m.grid(size=40, engine="classic")
    assert same_bits(classic.values, m.grid(size=40).values) and classic.engine == "classic"
    f32 = m.grid(size=64, precision="float32")
    assert f32.values.dtype == np.float32 and f32.engine == "voxel-f32"
    assert same_bits(f32.values, cli_grid(path, tmp_path, "--size", 64, "--precision", "float32"))
    sign = m.sign(size=64)
    assert same_bits(sign.values, cli_grid(path, tmp_path, "--size", 64, "--sign-only"))
    assert set(np.unique(sign.values)) <= {-1.0, 0.0, 1.0}


def test_fields_are_freed():
    m = fortu.compile(EXAMPLES / "circles_or.fortu")

    def resident_mib():
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * 4096 / 2**20

    for _ in range(3):
        m.grid(size=1024).values.sum()
    before = resident_mib()
    for _ in range(40):   # 8 MiB each: 320 MiB if they were kept
        f = m.grid(size=1024)
        v = f.values
        assert v.base is not None and m.eval(v[:1, :1], 0).shape == (1, 1)
        del f, v
    assert resident_mib() - before < 64


def test_broadcasting_shapes():
    m = fortu.compile("ARGUMENT X, Y;\nRETURN 1 - X*X - 2*Y;")
    x = np.linspace(-1, 1, 5)
    assert m.eval(x[:, None], np.array([0.0, 0.5, 1.0])).shape == (5, 3)
    assert m.eval(x, 0.25).shape == (5,)
    assert m.eval(np.zeros((2, 1, 4)), np.ones((3, 1))).shape == (2, 3, 4)
    assert np.asarray(m.eval(np.float64(0.5), np.array(0.25))).shape == ()
    assert isinstance(m.eval(0.5, 0.25), float) and m.eval(0.5, 0.25) == 1 - 0.25 - 0.5
    grid = np.arange(24, dtype=np.float64).reshape(4, 6) / 10
    strided = grid.T[::2]                       # not contiguous: read through its strides
    expected = np.array([[m.eval(float(a), float(b)) for a, b in zip(r, r[::-1])] for r in strided])
    assert same_bits(m.eval(strided, strided[:, ::-1]), expected)
    assert m.eval([1, 2, 3], [True, False, True]).tolist() == [1 - 1 - 2, 1 - 4 - 0, 1 - 9 - 2]
    assert m.eval(np.float32(0.5), 0) == m.eval(0.5, 0)
    big = np.linspace(0, 1, 100_000)            # many tiles, on all threads
    assert same_bits(m.eval(big, big[::-1]), 1 - big * big - 2 * big[::-1])
    assert m.eval(np.array([]), np.zeros((3, 1))).shape == (3, 0)
    assert m.gradient(x, 0).shape == (5, 2)
    assert m.gradient(0.5, 0).tolist() == [-1.0, -2.0]


def test_constants_per_call_without_touching_the_model(tmp_path):
    text = "ARGUMENT X(-1, 1), Y(-1, 1);\nCONSTANT R = 0.6;\nCONSTANT R2 = R*R;\nRETURN R2 - X^2 - Y^2;\n"
    m = fortu.compile(text)
    changed = fortu.compile(text.replace("R = 0.6", "R = 0.8"))
    assert same_bits(m.grid(size=50, R=0.8).values, changed.grid(size=50).values)
    assert same_bits(m.grid(size=50).values, fortu.compile(text).grid(size=50).values)   # unchanged
    assert m.eval(0, 0, R=0.8) == 0.8 * 0.8 and m.eval(0, 0) == 0.6 * 0.6
    assert m.eval(0, 0, constants={"r": 0.5}) == 0.25   # names as in the script, any case
    with pytest.raises(fortu.FortuError) as e:
        m.eval(0, 0, Q=1)
    assert str(e.value) == "error: cannot set 'Q': the script has no top-level CONSTANT of that name\n"
    with pytest.raises(TypeError):
        m.eval(0, 0, R="big")


def test_mimages_singular_points_ir_pickle(tmp_path):
    path = EXAMPLES / "singular_parabola.fortu"
    m = fortu.compile(path)
    n = m.mimages(size=(30, 20))
    assert n.shape == (4, 20, 30)
    assert np.allclose((n ** 2).sum(axis=0), 1.0) and (n[2] > 0).all()   # unit planes, n3 > 0
    corners = m.singular_points()
    assert corners.shape == (2, 2) and np.allclose(corners, [[-2, 4], [2, 4]], atol=1e-9)
    cli = run_fortu("singular", path).stdout.splitlines()[1:]
    assert corners.tolist() == [[float(v) for v in line.split("  ")[0].strip("()").split(", ")] for line in cli]
    assert m.ir() == run_fortu("ir", path).stdout
    assert m.ir("tape") == run_fortu("ir", path, "--stage", "tape").stdout
    again = pickle.loads(pickle.dumps(m))
    assert same_bits(again.grid(size=33).values, m.grid(size=33).values) and again.path == str(path)


def test_pictures_are_the_command_lines(tmp_path):
    path = EXAMPLES / "circles_or.fortu"
    m = fortu.compile(path)
    out = tmp_path / "cli.png"
    run_fortu("run", path, "--size", 64, "-o", out)
    assert m.grid(size=64)._repr_png_() == out.read_bytes()
    run_fortu("run", path, "-o", out)
    assert m._repr_png_() == out.read_bytes()
