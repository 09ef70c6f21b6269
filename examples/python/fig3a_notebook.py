# examples/python/fig3a_notebook.py — fortu from Python, notebook style (run it as a script,
# or paste the cells into Jupyter, where models and fields show as pictures):
#   PYTHONPATH=build/release/python /usr/bin/python3 examples/python/fig3a_notebook.py [SIZE]
# 1. S1 Fig. 3a both ways: formula (3) on the classic engine, the FLOZ-construction on the
#    voxel engine (the papers' experiment E1), pictures written, timings compared (plotted
#    with matplotlib when it is installed).
# 2. A parameter sweep on a dask.distributed LocalCluster, one task per value of a CONSTANT:
#    the nesting depth N of examples/nested_discs.fortu, set per call without editing it.
import sys
import time
from pathlib import Path

import numpy as np

import fortu

EXAMPLES = Path(__file__).resolve().parents[1]


# %% 1. Fig. 3a, classic (formula 3) and voxel (FLOZ-construction)
def render_both(size=800, out_dir=Path(".")):
    """Renders both forms of Fig. 3a at size x size; returns {engine: seconds}."""
    runs = {"classic": ("s1_fig3a_formula.fortu", "classic"), "voxel": ("s1_fig3a_floz.fortu", "voxel")}
    timings = {}
    for name, (script, engine) in runs.items():
        model = fortu.compile(EXAMPLES / script)
        start = time.perf_counter()
        field = model.grid(size=size, engine=engine)
        timings[name] = time.perf_counter() - start
        (out_dir / f"fig3a_{name}.png").write_bytes(field._repr_png_())   # the picture `fortu run -o` writes
        inside = int((field.values > 0).sum())
        print(f"{name:8s} {script:24s} {size}x{size}: {timings[name]:.4f} s, {inside} points inside")
    return timings


def plot_timings(timings, path="fig3a_timing.png"):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot")
        return
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.bar(list(timings), list(timings.values()), color=["#2f5fb3", "#e8751a"])
    ax.set_yscale("log")
    ax.set_ylabel("seconds")
    ax.set_title("S1 Fig. 3a: classic vs voxel")
    fig.tight_layout()
    fig.savefig(path)
    print(f"wrote {path}")


# %% 2. A sweep of CONSTANT N on a dask LocalCluster, one task per value
def field_for(model, n, size):
    return model.grid(size=size, N=n).values   # the Model pickles (its text), the values are an ndarray


def sweep(values, size=256, workers=2, processes=False):
    """The fields of nested_discs.fortu for each N in `values`, one dask task each.

    processes=False runs the workers as threads of this process: fortu releases the GIL, so
    they evaluate in parallel; processes=True ships the Model to worker processes."""
    from dask.distributed import Client, LocalCluster
    model = fortu.compile(EXAMPLES / "nested_discs.fortu")
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=processes,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        futures = client.map(field_for, [model] * len(values), values, [size] * len(values), pure=False)
        return client.gather(futures)


if __name__ == "__main__":
    size = int(sys.argv[1]) if len(sys.argv) > 1 else 800
    timings = render_both(size)
    plot_timings(timings)
    depths = [1, 2, 4, 8, 12]
    fields = sweep(depths, size=min(size, 256))
    for n, values in zip(depths, fields):
        print(f"N = {n:2d}: {int((values > 0).sum())} points inside")
