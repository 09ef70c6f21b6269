// cli/python/arrays.cpp — broadcasting by strides, and vectors handed to numpy by capsule.
#include "cli/python/arrays.hpp"

#include <cstring>
#include <memory>
#include <string>

namespace py = pybind11;

namespace fortu::python {

py::array_t<double> real_array(py::handle value, const char* name) {
    py::array array = py::array::ensure(value);
    if (!array) throw py::type_error(std::string(name) + ": expected a number or an array of numbers");
    const char kind = array.dtype().kind();
    if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
        throw py::type_error(std::string(name) + ": expected real numbers, got an array of dtype " +
                             std::string(py::str(array.dtype())));
    return py::array_t<double>::ensure(array);
}

PointArrays::PointArrays(const std::vector<py::handle>& coordinates) {
    static const char* const kNames[] = {"x", "y", "z"};
    py::tuple arrays(coordinates.size());
    for (std::size_t i = 0; i < coordinates.size(); ++i) {
        Operand op;
        op.array = real_array(coordinates[i], kNames[i]);
        arrays[i] = op.array;
        operands_.push_back(std::move(op));
    }
    // numpy's own rules and message ("shape mismatch: objects cannot be broadcast ...").
    // Never destroyed (see errors.cpp's fortu_error_type).
    static const py::object* broadcast_shapes = new py::object(py::module_::import("numpy").attr("broadcast_shapes"));
    py::list shapes;
    for (const Operand& op : operands_) shapes.append(op.array.attr("shape"));
    const py::tuple shape = (*broadcast_shapes)(*shapes);
    for (py::handle extent : shape) shape_.push_back(extent.cast<py::ssize_t>());
    for (py::ssize_t extent : shape_) points_ *= static_cast<std::size_t>(extent);
    for (Operand& op : operands_) {
        const py::ssize_t lead = static_cast<py::ssize_t>(shape_.size()) - op.array.ndim();
        op.strides.assign(shape_.size(), 0);
        for (py::ssize_t d = 0; d < op.array.ndim(); ++d)
            op.strides[lead + d] = op.array.shape(d) == 1 ? 0 : op.array.strides(d);
        op.data = reinterpret_cast<const char*>(op.array.data());
        op.contiguous = lead == 0 && (op.array.flags() & py::array::c_style) && op.array.size() == py::ssize_t(points_);
    }
}

void PointArrays::gather(std::size_t first, int count, double* const out[3]) const {
    const std::size_t dims = shape_.size();
    for (std::size_t a = 0; a < operands_.size(); ++a) {
        if (!out[a]) continue;
        const Operand& op = operands_[a];
        if (op.contiguous) {
            std::memcpy(out[a], reinterpret_cast<const double*>(op.data) + first, sizeof(double) * count);
            continue;
        }
        // The multi-index of `first`, then stepped like an odometer.
        std::vector<py::ssize_t> index(dims, 0);
        std::size_t rest = first;
        for (std::size_t d = dims; d-- > 0;) {
            index[d] = static_cast<py::ssize_t>(rest % static_cast<std::size_t>(shape_[d]));
            rest /= static_cast<std::size_t>(shape_[d]);
        }
        py::ssize_t offset = 0;
        for (std::size_t d = 0; d < dims; ++d) offset += index[d] * op.strides[d];
        for (int i = 0; i < count; ++i) {
            std::memcpy(&out[a][i], op.data + offset, sizeof(double));
            for (std::size_t d = dims; d-- > 0;) {
                offset += op.strides[d];
                if (++index[d] < shape_[d]) break;
                offset -= op.strides[d] * shape_[d];
                index[d] = 0;
            }
        }
    }
}

py::array_t<double> owning_array(std::vector<double>&& values, std::vector<py::ssize_t> shape) {
    auto* owned = new std::vector<double>(std::move(values));
    py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
    return py::array_t<double>(shape, owned->data(), free_when_done);
}

py::array field_array(Field&& field, bool float32) {
    const Grid g = field.grid;
    std::vector<py::ssize_t> shape{g.rows(), g.cols()};
    if (g.dims == 3) shape.insert(shape.begin(), g.slices());
    py::array_t<double> values = owning_array(std::move(field.values), shape);
    if (float32) return values.attr("astype")("float32");
    return values;
}

py::array_t<double> axis_coordinates(const Grid& grid, int axis) {
    const int nodes = axis == 0 ? grid.cols() : axis == 1 ? grid.rows() : grid.slices();
    py::array_t<double> out(nodes);
    double* p = out.mutable_data();
    for (int i = 0; i < nodes; ++i) p[i] = axis == 0 ? grid.x_at(i) : axis == 1 ? grid.y_at(i) : grid.z_at(i);
    return out;
}

}  // namespace fortu::python
