# tests/python/test_threads.py — evaluation releases the GIL (another Python thread runs
# meanwhile), Ctrl-C stops a long evaluation, and the example's dask sweep returns the same
# fields as serial calls.
import importlib.util
import os
import signal
import threading
import time

import numpy as np
import pytest

import fortu
from conftest import EXAMPLES, SOURCE_DIR, same_bits


def test_a_second_thread_runs_while_a_grid_evaluates():
    m = fortu.compile(EXAMPLES / "s1_fig3a_formula.fortu")
    counter, running = [0], [True]

    def count():
        while running[0]:
            counter[0] += 1

    thread = threading.Thread(target=count)
    thread.start()
    try:
        time.sleep(0.05)
        before = counter[0]
        field = m.grid(size=300, engine="classic", threads=1)   # about 0.5 s in C++
        during = counter[0] - before
    finally:
        running[0] = False
        thread.join()
    assert field.seconds > 0.1
    assert during > 10_000, during   # with the GIL held it would be 0


def test_ctrl_c_stops_a_long_evaluation():
    m = fortu.compile(EXAMPLES / "s1_fig3a_formula.fortu")
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        m.grid(size=4000, engine="classic", budget=1e12)   # about a minute if not stopped
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 5, elapsed
    assert m.eval(0.0, 0.0) == m.eval(0.0, 0.0)   # the model is still usable


def test_the_examples_dask_sweep_equals_serial_calls(tmp_path):
    pytest.importorskip("distributed")
    spec = importlib.util.spec_from_file_location("fig3a_notebook", SOURCE_DIR / "examples/python/fig3a_notebook.py")
    notebook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(notebook)
    timings = notebook.render_both(size=64, out_dir=tmp_path)
    assert (tmp_path / "fig3a_voxel.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert set(timings) == {"classic", "voxel"}
    values = [2, 6, 12]
    swept = notebook.sweep(values, size=48, workers=2)
    model = fortu.compile(EXAMPLES / "nested_discs.fortu")
    serial = [model.grid(size=48, N=v).values for v in values]
    assert len(swept) == len(values)
    for a, b in zip(swept, serial):
        assert same_bits(a, b)
    assert not same_bits(swept[0], swept[1])   # the parameter reaches the model


def test_threads_sharing_a_model_with_different_constants():
    m = fortu.compile(EXAMPLES / "nested_discs.fortu")
    expected = {n: m.grid(size=200, N=n).values for n in range(1, 13)}
    results, errors = {}, []

    def work(offset):
        try:
            for k in range(12):
                n = (k + offset) % 12 + 1   # 12 values, more than the 8 variants kept: evictions while others run
                results[(offset, k)] = (n, m.grid(size=200, N=n, threads=1).values)
        except Exception as e:   # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(o,)) for o in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    assert len(results) == 48
    for n, values in results.values():
        assert same_bits(values, expected[n])
