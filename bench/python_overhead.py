# bench/python_overhead.py — what `import fortu` costs over the fortu command: the per-call
# overhead of a 1-point eval after compile, and a 1024² grid from Python against the same
# grid in `fortu run` (its `--stats` evaluation time, from its points/s). Medians of several runs.
#   PYTHONPATH=build/release/python /usr/bin/python3 bench/python_overhead.py [build/release/fortu [RUNS]]
import re
import statistics
import subprocess
import sys
import time
import timeit
from pathlib import Path

import fortu

ROOT = Path(__file__).resolve().parents[1]
BINARY = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build/release/fortu")
SHARED = ROOT.parent / "shared/data"
RUNS = 7


def eval_overhead(path):
    m = fortu.compile(path if isinstance(path, str) else Path(path))
    m.eval(0.1, 0.2)
    calls = 200_000
    per_call = [t / calls * 1e6 for t in timeit.repeat(lambda: m.eval(0.1, 0.2), number=calls, repeat=RUNS)]
    return statistics.median(per_call)


def grid_times(path, size=1024, options=()):
    """Medians of the Python call and of `fortu run`'s evaluation, runs interleaved so both
    see the same machine."""
    m = fortu.compile(path)
    kwargs = dict(options)
    m.grid(size=size, **kwargs)
    flags = [f"--{k}={v}" for k, v in options]
    python, outside, cli = [], [], []
    for _ in range(RUNS):
        start = time.perf_counter()
        field = m.grid(size=size, **kwargs)
        python.append(time.perf_counter() - start)
        outside.append(python[-1] - field.seconds)   # the call minus the engine's own time
        out = subprocess.run([BINARY, "run", str(path), "--size", str(size), "--stats", *flags],
                             capture_output=True, text=True, check=True).stdout
        speed = float(re.search(r"speed: ([0-9,]+) points/s", out).group(1).replace(",", ""))
        cli.append(size * size / speed)   # the evaluation time, to more digits than `evaluate`
    return statistics.median(python), statistics.median(outside), statistics.median(cli)


if __name__ == "__main__":
    print(f"load average before: {open('/proc/loadavg').read().split()[0]}")
    if len(sys.argv) > 2:
        RUNS = int(sys.argv[2])
    # RETURN X: nothing to evaluate, so the time is the call's overhead alone.
    identity = "ARGUMENT X, Y;\nRETURN X;"
    print(f"1-point eval, RETURN X: {eval_overhead(identity):.2f} µs per call")
    for name in ["circles_or", "s1_fig3a_floz"]:
        print(f"1-point eval, {name}: {eval_overhead(ROOT / 'examples' / f'{name}.fortu'):.2f} µs per call")
    models = [(ROOT / "examples/s1_fig3a_floz.fortu", ()), (ROOT / "examples/s1_fig3a_floz.fortu", (("threads", 1),)),
              (SHARED / "prospero.vm", ()), (SHARED / "prospero.vm", (("precision", "float32"),))]
    for path, options in models:
        py, outside, cli = grid_times(path, options=options)
        label = path.name + "".join(f" {k}={v}" for k, v in options)
        print(f"1024² {label}: Python {py * 1e3:.1f} ms (outside the engine {outside * 1e3:.2f} ms), "
              f"fortu run {cli * 1e3:.1f} ms, {100 * (py / cli - 1):+.1f}%")
