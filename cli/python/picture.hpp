// cli/python/picture.hpp — the notebook picture (`_repr_png_`): the command line's own
// picture of a field (runtime/picture.hpp through write_field), as PNG bytes.
#pragma once

#include "runtime/field.hpp"

#include <pybind11/pybind11.h>

namespace fortu::python {

/// The PNG `fortu run -o x.png` writes for `field` (3D: the middle slice). Written to a
/// temporary file by the same writer, read back and removed. RuntimeError if it cannot be.
pybind11::bytes png_bytes(const Field& field);

}  // namespace fortu::python
