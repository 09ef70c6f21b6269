# cli/python/__init__.py — the package `fortu`: everything is in the extension _fortu
# (cli/python/*.cpp); this file only re-exports it.
"""FORTU models (R-functions, the functional-voxel method) from Python: see fortu._fortu.__doc__."""
from ._fortu import (DEFAULT_MAX_POINTS, Diagnostic, Field, FortuError, Model, compile, engines,
                     stdlib_path)
from ._fortu import __doc__  # noqa: F401

__all__ = ["compile", "Model", "Field", "Diagnostic", "FortuError", "engines", "stdlib_path",
           "DEFAULT_MAX_POINTS"]
