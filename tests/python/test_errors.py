# tests/python/test_errors.py — a bad model, a bad request or a huge one gives a clear
# Python exception, never a crash or an out-of-memory kill: FortuError with the command
# line's exact text, ValueError / TypeError for shapes, dtypes and options.
import numpy as np
import pytest

import fortu
from conftest import EXAMPLES, run_fortu

BAD = "ARGUMENT X, Y;\nVARIABLE D = 1 - X*X;\nRETURN D & Y2;\n"


def test_fortu_error_is_the_command_lines_text(tmp_path):
    path = tmp_path / "bad.fortu"
    path.write_text(BAD)
    with pytest.raises(fortu.FortuError) as e:
        fortu.compile(str(path))
    assert str(e.value) == run_fortu("eval", path, 0, 0, check=False).stderr
    assert str(e.value) == (f"{path}:3:12: error: unknown name 'Y2'\n"
                            "RETURN D & Y2;\n"
                            "           ^~\n")
    [d] = e.value.diagnostics
    assert (d.severity, d.file, d.line, d.column, d.end_line, d.end_column, d.message, d.notes) == \
        ("error", str(path), 3, 12, 3, 14, "unknown name 'Y2'", [])
    assert d.text == str(e.value)


def test_fortu_error_carries_notes_and_several_errors():
    with pytest.raises(fortu.FortuError) as e:
        fortu.compile("ARGUMENT X, Y;\nVARIABLE P = [1, 2];\nRETURN X + ZZ;\n")
    messages = [(d.line, d.column, d.message, d.notes) for d in e.value.diagnostics]
    assert messages == [(2, 14, "array 'P' must be a CONSTANT", ["arrays hold compile-time numbers: CONSTANT P = [1, 2, 3];"]),
                        (3, 12, "unknown name 'ZZ'", [])]
    assert str(e.value) == "".join(d.text for d in e.value.diagnostics)
    assert "note: arrays hold compile-time numbers" in str(e.value)


def test_missing_file_and_bad_compile_options(tmp_path):
    with pytest.raises(FileNotFoundError):
        fortu.compile(str(tmp_path / "nowhere.fortu"))
    with pytest.raises(ValueError, match="rsystem: 'r7'"):
        fortu.compile(EXAMPLES / "circles_or.fortu", rsystem="r7")
    with pytest.raises(TypeError):
        fortu.compile(42)


def test_wrong_shapes_and_dtypes():
    m = fortu.compile(EXAMPLES / "circles_or.fortu")
    with pytest.raises(ValueError, match="broadcast"):
        m.eval(np.zeros(3), np.zeros(4))
    with pytest.raises(TypeError, match="complex"):
        m.eval(np.zeros(3, dtype=complex), 0)
    with pytest.raises(TypeError):
        m.eval(np.array(["a", "b"]), 0)
    with pytest.raises(TypeError):
        m.eval([object()], 0)
    with pytest.raises(TypeError, match="give 2 coordinate"):
        m.eval(0.5)
    with pytest.raises(TypeError, match="give 2 coordinate"):
        m.eval(0.5, 0.5, 0.5)
    with pytest.raises(ValueError, match="size: 0 nodes"):
        m.grid(size=0)
    with pytest.raises(ValueError, match="give N or"):
        m.grid(size=(4, 4, 4))
    with pytest.raises(ValueError, match="axis x needs finite min < max"):
        m.grid(domain=((1, -1), (0, 1)))
    with pytest.raises(ValueError, match="unknown engine 'fast'"):
        m.grid(engine="fast")
    with pytest.raises(ValueError, match="precision: 'float16'"):
        m.grid(precision="float16")
    with pytest.raises(ValueError, match="stage: 'parse'"):
        m.ir("parse")


def test_a_hundred_million_points_are_refused_before_any_allocation():
    m = fortu.compile(EXAMPLES / "circles_or.fortu")
    with pytest.raises(ValueError) as e:
        m.grid(size=10_000)
    assert str(e.value) == ("100000000 points requested, more than max_points = 67108864 (each float64 array "
                            "512.0 MiB); evaluate in pieces, or raise max_points if the memory is there")
    with pytest.raises(ValueError, match="100000000 points requested"):
        m.eval(np.zeros((10_000, 1)), np.zeros((1, 10_000)))
    with pytest.raises(ValueError, match="points requested"):
        m.mimages(size=10_000)


def test_a_vm_model_has_no_constants_to_set(shared_data):
    m = fortu.compile(shared_data / "prospero.vm")
    with pytest.raises(fortu.FortuError, match="cannot set 'R': a .vm model has no CONSTANT definitions"):
        m.eval(0, 0, R=1)


def test_classic_budget_is_the_command_lines():
    m = fortu.compile(EXAMPLES / "s1_fig3a_formula.fortu")
    with pytest.raises(ValueError, match="the classic engine would need 3,838 operations per point"):
        m.grid(size=2000, engine="classic", budget=1e9)
