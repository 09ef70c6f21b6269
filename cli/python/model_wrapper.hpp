// cli/python/model_wrapper.hpp — fortu.Model and fortu.Field: a compiled model and what its
// methods compute, on the same engines, grids and writers the command line uses.
#pragma once

#include "cli/python/errors.hpp"
#include "grammar/source.hpp"
#include "interp/model.hpp"
#include "interp/point_list.hpp"
#include "runtime/field.hpp"
#include "runtime/grid.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <list>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fortu::python {

/// Points one call may return (each float64 array at most 512 MiB): a larger request is a
/// ValueError naming the limit, never an allocation the machine cannot hold.
inline constexpr std::size_t kDefaultMaxPoints = std::size_t{1} << 26;
/// Grid nodes a mesh may walk by default: the command line's grid limit, since the mesher
/// keeps only the cells the surface crosses (a 513³ lattice is within it, over 2²⁶).
inline constexpr std::size_t kDefaultMeshMaxPoints = kMaxGridPoints;

/// CONSTANT values given to one call (`m.grid(R=0.8)`), by name.
using ConstantValues = std::vector<std::pair<std::string, double>>;

/// A sampled field with its grid (fortu.Field).
struct FieldView {
    Field field;
    bool float32 = false;        ///< computed in float32: `values` is float32
    std::string engine;
    double seconds = 0.0;        ///< evaluation time
    pybind11::object values;     ///< float32: the converted values, made on first use
};

/// A compiled model (fortu.Model).
class ModelWrapper {
public:
    /// Compiles `text`, read from `path` (or `<string>`). Raises FortuError.
    ModelWrapper(std::string text, std::string path, std::vector<std::string> include_path,
                 std::optional<std::string> rsystem);

    const Model& model() const { return compiled_->model; }
    const std::string& text() const { return source_->text(); }
    const std::string& path() const { return source_->path(); }
    const std::vector<std::string>& include_path() const { return include_path_; }
    const std::optional<std::string>& rsystem() const { return rsystem_text_; }
    /// Warnings (and notes) of the compilation.
    pybind11::list diagnostics() const;

    pybind11::object eval(const std::vector<pybind11::handle>& coordinates, int threads, std::size_t max_points,
                          const ConstantValues& constants);
    pybind11::array gradient(const std::vector<pybind11::handle>& coordinates, std::size_t max_points,
                             const ConstantValues& constants);
    FieldView grid(pybind11::handle size, pybind11::handle domain, const std::string& precision,
                   pybind11::handle engine, int threads, std::size_t max_points, double budget,
                   const ConstantValues& constants);
    pybind11::array mimages(pybind11::handle size, pybind11::handle domain, int threads, std::size_t max_points,
                            const ConstantValues& constants);
    /// The mesh `fortu run -o m.ply` writes: (vertices, triangles, normals).
    pybind11::tuple mesh(pybind11::handle size, pybind11::handle domain, int threads, std::size_t max_points,
                         const ConstantValues& constants);
    pybind11::array singular_points(pybind11::handle size, pybind11::handle domain, const ConstantValues& constants);
    std::string ir(const std::string& stage, const ConstantValues& constants);
    pybind11::bytes png(const ConstantValues& constants);

private:
    /// A model and what evaluates its points, compiled with some CONSTANT values.
    struct Compiled {
        ConstantValues constants;
        Model model;
        PointListEvaluator points;
    };
    /// The model with `constants` applied: compiled once per distinct set and kept (the
    /// last few), so a sweep over R recompiles each R once and repeated calls not at all.
    /// Shared: a call holds it while another thread (the GIL released) may evict it.
    std::shared_ptr<const Compiled> with(const ConstantValues& constants);
    std::shared_ptr<const Compiled> compile_with(const ConstantValues& constants, std::vector<DiagnosticView>* warnings) const;
    /// The grid `size` and `domain` name, as `fortu run` sizes it; ValueError over
    /// `max_points` (`arrays`: points the call returns values for, else nodes a mesh walks).
    Grid grid_for(const Model& model, pybind11::handle size, pybind11::handle domain, std::size_t max_points,
                  bool arrays = true) const;

    std::shared_ptr<const SourceFile> source_;
    std::vector<std::string> include_path_;
    std::optional<std::string> rsystem_text_;
    std::optional<RSystem> rsystem_;
    std::vector<DiagnosticView> warnings_;
    std::shared_ptr<const Compiled> compiled_;
    std::list<std::shared_ptr<const Compiled>> variants_;   ///< most recently used first
};

}  // namespace fortu::python
