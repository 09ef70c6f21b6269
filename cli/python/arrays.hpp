// cli/python/arrays.hpp — numpy in and out: coordinates of any broadcastable shape read in
// place (no broadcast copies), fields, M-images and meshes handed to numpy without a copy.
#pragma once

#include "runtime/field.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstddef>
#include <vector>

namespace fortu::python {

/// The coordinate arguments of one call, broadcast against each other (numpy's rules).
class PointArrays {
public:
    /// Each of `coordinates` a number or an array of real numbers (bool, int, float):
    /// TypeError for anything else (complex, strings, objects), ValueError when the shapes
    /// do not broadcast.
    explicit PointArrays(const std::vector<pybind11::handle>& coordinates);

    const std::vector<pybind11::ssize_t>& shape() const { return shape_; }
    std::size_t points() const { return points_; }
    /// Coordinates of points [first, first + count) (C order over shape()) into out[axis]
    /// (nullptr: not wanted). Reads the arrays in place: safe without the GIL.
    void gather(std::size_t first, int count, double* const out[3]) const;

private:
    struct Operand {
        pybind11::array_t<double> array;        ///< float64 (converted if it was not)
        std::vector<pybind11::ssize_t> strides; ///< in bytes, over shape(); 0 where broadcast
        const char* data = nullptr;
        bool contiguous = false;                ///< C-contiguous over exactly shape()
    };
    std::vector<Operand> operands_;
    std::vector<pybind11::ssize_t> shape_;
    std::size_t points_ = 1;
};

/// Converts one coordinate argument: TypeError unless its dtype is bool, integer or float.
pybind11::array_t<double> real_array(pybind11::handle value, const char* name);

/// The values of `field` as an ndarray in the command line's orientation: (rows, cols), or
/// (slices, rows, cols) in 3D; row 0 is the largest Y. Takes the values without a copy;
/// float32 converts (what `fortu run --float32 -o x.npy` writes).
pybind11::array field_array(Field&& field, bool float32);

/// An ndarray owning `values`, of `shape`, without a copy.
pybind11::array_t<double> owning_array(std::vector<double>&& values, std::vector<pybind11::ssize_t> shape);

/// An (n, 3) ndarray owning `rows` (a mesh's vertices, normals or triangles), without a copy:
/// std::array<T, 3> has no padding, so the vector's storage is already C order.
template <typename T>
pybind11::array_t<T> owning_rows(std::vector<std::array<T, 3>>&& rows) {
    static_assert(sizeof(std::array<T, 3>) == 3 * sizeof(T));
    auto* owned = new std::vector<std::array<T, 3>>(std::move(rows));
    pybind11::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<std::array<T, 3>>*>(p); });
    return pybind11::array_t<T>({static_cast<pybind11::ssize_t>(owned->size()), pybind11::ssize_t{3}},
                                owned->empty() ? nullptr : owned->front().data(), free_when_done);
}

/// The node coordinates along one axis (0 x, 1 y, 2 z) in the order of field_array's
/// axes: x ascending (columns), y descending (rows), z ascending (slices).
pybind11::array_t<double> axis_coordinates(const Grid& grid, int axis);

}  // namespace fortu::python
