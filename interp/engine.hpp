// interp/engine.hpp — the one interface every engine implements, and the table of engines
// (engine_table.cpp) that the command line, `fortu bench`, `fortu golden` and the REPL read.
//
// Why: the engines are what the papers compare, and new ones (float32, the sign renderer)
// keep arriving. Each engine is a class in its own files that says what it can do
// (EngineCapabilities) and owns its own options; adding one is its files plus one row of
// the table. Nothing outside an engine's files names it except that row.
#pragma once

#include "interp/model.hpp"
#include "runtime/field.hpp"
#include "runtime/grid.hpp"
#include "runtime/palette.hpp"

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fortu {

/// One named definition as an engine with `steps` computed it (EvalOptions::on_step).
struct EvalStep {
    int index = 0;                  ///< 1, 2, ... in the order the engine computed them
    std::string_view name;          ///< the definition's name
    const Field& values;            ///< its values at every node of the grid
    /// Its M-images as the engine stores them, decoded: n1..n4 (3D: n1..n5), one array per
    /// component in image order; NaN at invalid nodes.
    const std::vector<std::vector<double>>& components;
    std::optional<Palette> palette; ///< the palette they are stored in; nullopt: unquantised
};

/// What every engine takes for a grid evaluation.
struct EvalOptions {
    int threads = 0;                                   ///< 0: all cores
    std::function<void(std::size_t points)> progress;  ///< called as tiles/rows complete
    const std::atomic<bool>* cancel = nullptr;         ///< set to stop early (REPL Ctrl-C)
    /// Engines with `steps`: the definitions (Model::definitions) to hand to on_step as each
    /// is computed, in the engine's order of computation.
    std::vector<std::pair<std::string, ir::NodeId>> steps;
    std::function<void(const EvalStep&)> on_step;
};

/// Node values exchanged with an engine that has `known_and_kept` (the REPL's incremental
/// evaluation); every array is in grid order, one value per point.
struct NodeValues {
    /// Read instead of computed; what only they use is not computed.
    std::vector<std::pair<ir::NodeId, const double*>> known;
    /// Also written out beside the root's. Incomplete if the evaluation was cancelled.
    std::vector<std::pair<ir::NodeId, double*>> keep;
    bool empty() const { return known.empty() && keep.empty(); }
};

/// What an engine can do; callers choose and refuse by these, never by an engine's name.
struct EngineCapabilities {
    bool grid = true;            ///< evaluates whole grids
    bool point = false;          ///< evaluates single points (fortu eval, the REPL's probe)
    bool gradients = false;      ///< its points come with exact gradients
    bool sign_only = false;      ///< computes the sign (1, 0, -1, NaN), not the values
    bool float32 = false;        ///< computes in single precision (values within 1e-5 of the field)
    bool known_and_kept = false; ///< takes NodeValues (reads known nodes, writes kept ones)
    /// Its values equal the reference's bit for bit: `golden-engine both` runs every such
    /// engine and they must agree.
    bool exact = false;
    /// Walks the expanded tree (classic_cost.hpp): a run's cost is known before it starts
    /// and refused above --budget.
    bool expanded_tree_cost = false;
    /// Computes X-only sub-expressions once per grid column and those without X once per
    /// row on wide grids (hoist.hpp), as `--stats` and `fortu ir --stage hoist` report.
    bool hoists = false;
    /// Stores every intermediate result in a palette it can choose (--palette: P = 256,
    /// P = 2^24 or unquantised).
    bool palette = false;
    /// Hands out each named definition's values and M-images as it computes them
    /// (EvalOptions::on_step; --steps).
    bool steps = false;
};

/// The voxel engine's number type: float64 (default: values identical to the classic
/// engine's) or float32 (twice the lanes per vector; see README "Performance" for the tolerance).
enum class Precision { Float64, Float32 };

/// How an engine with `palette` stores M-images (--palette): quantised to one of the
/// papers' palettes, or unquantised doubles.
enum class MimageStorage { Grey8, Rgb24, Float };

/// What the command line tunes (--precision, --no-hoist, --palette); each engine takes what
/// applies to it and ignores the rest (Engine::tuned).
struct EngineSettings {
    Precision precision = Precision::Float64;
    bool hoist = true;
    bool compile = true;                      ///< --no-jit: false
    std::optional<MimageStorage> storage{};   ///< unset: the engine's default
};

struct PointValue {
    double value = 0.0;
    std::array<double, 3> gradient{};   ///< exact (forward-mode AD), d/dX, d/dY, d/dZ
};

class Engine {
public:
    virtual ~Engine() = default;
    /// The name `--engine`, `--engines`, `golden-engine` and `:engine` take.
    virtual std::string_view name() const = 0;
    /// One line for --help.
    virtual std::string_view summary() const = 0;
    /// The name with the settings that change its results (`fv, P = 256`), for reports.
    virtual std::string description() const { return std::string(name()); }
    virtual EngineCapabilities capabilities() const = 0;
    /// This engine with `settings` applied where they concern it.
    virtual std::unique_ptr<Engine> tuned(const EngineSettings& settings) const = 0;
    /// Samples `root` on every node of `grid`. `reuse` must be empty unless the engine has
    /// `known_and_kept` (std::invalid_argument otherwise).
    virtual Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid,
                                const EvalOptions& options, const NodeValues& reuse) const = 0;
    /// The value (and, with `gradients`, the gradient) at one point; engines without
    /// `point` throw std::logic_error.
    virtual PointValue evaluate_point(const ir::Graph& graph, ir::NodeId root, std::array<double, 3> point) const;
};

/// Every engine, in the order help texts list them (engine_table.cpp).
std::span<const Engine* const> engine_table();
/// The engine of that name, or nullptr.
const Engine* find_engine(std::string_view name);
/// The engine of that name; throws std::invalid_argument for an unknown one (for callers
/// whose names are fixed, such as tests).
const Engine& engine_named(std::string_view name);
/// The names of the engines that pass `filter`, in table order, joined by `separator` with
/// `last_separator` before the last: ("classic, voxel or sign"), ("classic|voxel").
std::string engine_names(std::string_view separator = ", ", std::string_view last_separator = ", ",
                         const std::function<bool(const EngineCapabilities&)>& filter = {});
/// One line per engine of the table, each after a newline (`\n  voxel       SUMMARY`), to
/// close a help text that lists the engines.
std::string engine_summaries();
/// The engines whose values must agree (`exact`): what `golden-engine both` runs.
std::vector<std::reference_wrapper<const Engine>> exact_engines();
/// The engine fortu uses when none is named.
const Engine& default_engine();

/// Samples the model (or any node of its graph) on every node of `grid`.
Field evaluate_grid(const Model& model, const Grid& grid, const Engine& engine, const EvalOptions& options = {});
Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const Engine& engine,
                    const EvalOptions& options = {});
/// The value and gradient at one point (coordinates beyond the model's arguments ignored).
PointValue evaluate_point(const Model& model, std::array<double, 3> point, const Engine& engine);

/// The grid over the model's box — per axis `domain[a]` if given, else the script's range
/// (ARGUMENT X(5), RECTANGLE), else [-1, 1] — with `nodes` per axis; a 2D model gets one
/// slice and a one-argument model one row.
Grid model_grid(const Model& model, std::array<int, 3> nodes,
                const std::array<std::optional<AxisRange>, 3>& domain = {});

/// Nodes per axis for a run: `size` (1 to 3 numbers, the last repeated), else RECTBMP, else
/// 256² (2D) or 64³ (3D).
std::array<int, 3> grid_nodes(const Model& model, const std::vector<int>& size);

/// Deepest recursion the classic engine accepts (its walk is recursive by definition).
inline constexpr int kClassicMaxDepth = 20000;

/// Length of the longest operand chain from the root (the classic engine's recursion depth).
int dag_depth(const ir::Graph& graph, ir::NodeId root);

}  // namespace fortu
