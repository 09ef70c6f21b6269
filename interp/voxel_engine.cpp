// interp/voxel_engine.cpp — the tape evaluated tile by tile, each node once per point (or,
// hoisted, once per grid column or row).
#include "interp/voxel_engine.hpp"

#include "interp/hoist.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/number_operands.hpp"
#include "interp/parallel.hpp"
#include "interp/tape_jit.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <type_traits>
#include <vector>

namespace fortu {
namespace {

using namespace ir;

// Runtime ISA dispatch of the voxel engine's lane loops (GCC function multiversioning): each
// wrapper is compiled twice, for x86-64-v4 (AVX-512) and for the build's -march, and the
// program loader picks one for this CPU; `flatten` inlines the lane kernel into each copy.
// Both copies round identically (IEEE operations, -ffp-contract=off, the same libm).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX512F__)
#define FORTU_LANE_CLONES __attribute__((target_clones("arch=x86-64-v4", "default"), flatten))
#else
#define FORTU_LANE_CLONES
#endif

FORTU_LANE_CLONES void run_tile_float(const Instruction* code, std::size_t count, float* const* slots, int lanes) {
    if (lanes == kTileSize) run_lanes<float, kTileSize>(code, count, slots, lanes);
    else run_lanes<float, 0>(code, count, slots, lanes);
}

FORTU_LANE_CLONES void run_tile_double(const Instruction* code, std::size_t count, double* const* slots, int lanes) {
    if (lanes == kTileSize) run_lanes<double, kTileSize>(code, count, slots, lanes);
    else run_lanes<double, 0>(code, count, slots, lanes);
}

template <class T>
void run_code(const std::vector<Instruction>& code, T* const* slots, int lanes) {
    if constexpr (std::is_same_v<T, float>) run_tile_float(code.data(), code.size(), slots, lanes);
    else run_tile_double(code.data(), code.size(), slots, lanes);
}

/// A run of consecutive grid points evaluated together.
struct Tile {
    std::size_t first_point = 0;
    int lanes = 0;
    int first_col = 0;       ///< row tiling: the tile's first column
    std::size_t row = 0;     ///< row tiling: the tile's first row (over all slices)
    int rows = 1;            ///< row tiling: whole rows in the tile (1: the tile is part of one row)
};

/// How a grid is cut into tiles: flat (kTileSize consecutive points, rows ignored) or by
/// rows (each tile inside one row or made of whole rows of one slice, as column, row and
/// plane values need). A long row is cut into equal pieces, a multiple of 16 lanes wide, so
/// no tile is mostly padding; short rows are grouped, as many as fit in kTileSize lanes (a
/// 128³ grid's rows alone would run the lane loops 128 long). Rows cut into pieces are walked
/// a band of columns at a time, every row of the first band before the second, so the
/// column values in use are one band's (prospero.vm float64: 1,431 column nodes × 8 B ×
/// 2048 columns = 23 MB, twice one band). Narrower bands (256, 512 lanes) were no faster at
/// 2048² and 1.3-1.5 times slower at 1024²: shorter lane loops cost more than the cache saves.
struct Tiling {
    std::size_t points = 0;
    int cols = 1;
    int rows = 1;            ///< row tiling: rows per slice
    int width = 0;           ///< row tiling: lanes per row in a tile; 0: flat
    int tiles_per_row = 1;
    int rows_per_tile = 1;
    int tiles_per_slice = 1;

    static Tiling flat(std::size_t points) { return Tiling{points, 1, 1, 0, 1, 1, 1}; }
    static Tiling by_rows(const Grid& grid) {
        Tiling t{grid.points(), grid.cols(), grid.rows(), 0, 1, 1, 1};
        const int pieces = (t.cols + kTileSize - 1) / kTileSize;
        t.width = std::min(kTileSize, ((t.cols + pieces - 1) / pieces + 15) / 16 * 16);
        t.tiles_per_row = (t.cols + t.width - 1) / t.width;
        if (t.tiles_per_row == 1) {
            t.width = t.cols;
            t.rows_per_tile = std::max(1, std::min(t.rows, kTileSize / t.cols));
        }
        t.tiles_per_slice = (t.rows + t.rows_per_tile - 1) / t.rows_per_tile;
        return t;
    }
    std::size_t count() const {
        if (width == 0) return (points + kTileSize - 1) / kTileSize;
        const std::size_t slices = points / (static_cast<std::size_t>(cols) * rows);
        return slices * tiles_per_slice * tiles_per_row;
    }
    Tile tile(std::size_t i) const {
        if (width == 0) {
            const std::size_t first = i * kTileSize;
            return Tile{first, static_cast<int>(std::min<std::size_t>(kTileSize, points - first)), 0, 0, 1};
        }
        Tile t;
        if (tiles_per_row > 1) {
            const std::size_t row_count = points / static_cast<std::size_t>(cols);
            t.row = i % row_count;
            t.first_col = static_cast<int>(i / row_count) * width;
            t.lanes = std::min(width, cols - t.first_col);
        } else {
            const std::size_t slice = i / tiles_per_slice;
            const int first_row = static_cast<int>(i % tiles_per_slice) * rows_per_tile;
            t.rows = std::min(rows_per_tile, rows - first_row);
            t.row = slice * rows + first_row;
            t.lanes = t.rows * cols;
        }
        t.first_point = t.row * cols + t.first_col;
        return t;
    }
};

/// Where a tape's input values come from: values of every grid point (read per tile,
/// converted to T), or hoisted T values. Those of grid row r of slice s start at
/// hoisted + r × row_stride + s × slice_stride: a value per column there (column and plane
/// nodes), or one value for the whole row (row nodes, `per_row_value`). A tile's values
/// are read in place when they follow each other as its lanes do (`spans_rows`: those of
/// its next row come next), else copied into the tile.
template <class T>
struct InputSource {
    const double* per_point = nullptr;
    const T* hoisted = nullptr;
    std::size_t row_stride = 0;
    std::size_t slice_stride = 0;
    bool per_row_value = false;
    bool spans_rows = false;

    bool read_in_place(const Tile& tile) const { return hoisted && !per_row_value && (tile.rows == 1 || spans_rows); }
};

/// Where a tape's output values go, one per point: as doubles (the field, kept nodes) or
/// as T (the column and row values of hoisted nodes, read by the per-point tape).
template <class T>
struct OutputSink {
    double* as_double = nullptr;
    T* as_t = nullptr;
};

template <class T>
struct Pass {
    const Tape& tape;
    const Grid& grid;                       ///< coordinates of the points (argument slots)
    std::vector<InputSource<T>> inputs;     ///< by TapeSpec::inputs index
    /// Row by row: row r's value of spec.uniforms[u] at r × spec.uniforms.size() + u, so
    /// that a row's values are read together (patched into the code, or compiled code's pool).
    std::vector<T> uniforms;
    std::vector<OutputSink<T>> outputs;     ///< by TapeSpec::outputs index
    /// What the tape was compiled from, for number_operands; the first `opaque_inputs`
    /// inputs hold values kept from elsewhere.
    const Graph& graph;
    const TapeSpec& spec;
    std::size_t opaque_inputs = 0;
};

/// One worker's tile memory, allocated before the loop and reused for all its tiles
/// (nothing is allocated per tile).
template <class T>
struct Workspace {
    std::vector<T> storage;            ///< kTileSize lanes per slot
    std::vector<T*> slots;             ///< each slot's lane array for the current tile
    std::vector<Instruction> code;     ///< with the current row's uniform values patched in
    std::size_t patched_row = ~std::size_t{0};
    JitScratch<T> jit;
};

template <class T>
void run_pass(const Pass<T>& pass, const Tiling& tiling, const EvalOptions& options, const VoxelOptions& engine) {
    const Tape& tape = pass.tape;
    const Grid& grid = pass.grid;
    const std::size_t plane = static_cast<std::size_t>(grid.cols()) * grid.rows();
    const std::size_t tiles = tiling.count();
    std::unique_ptr<CompiledTape<T>> compiled;
    if (engine.compile && double(tape.code.size()) * double(grid.points()) >= engine.compile_above_lane_operations) {
        const std::vector<uint8_t> numbers =
            number_operands(pass.graph, pass.spec, tape, grid,
                            std::is_same_v<T, float> ? Precision::Float32 : Precision::Float64, pass.opaque_inputs);
        compiled = CompiledTape<T>::compile(tape, numbers);
    }

    // Slots of column inputs point into the column values: they need no tile memory
    // (prospero.vm has ~1000 of them).
    std::vector<char> borrowed(tape.slot_count, 0);
    // A tiling's tiles are all of one row or all of whole rows, so the first tile tells.
    const Tile first_tile = tiling.tile(0);
    for (auto [slot, which] : tape.inputs) borrowed[slot] = pass.inputs[which].read_in_place(first_tile);
    const std::size_t own_slots = static_cast<std::size_t>(std::count(borrowed.begin(), borrowed.end(), 0));
    std::vector<Workspace<T>> workspaces(worker_count(tiles, options));
    for (Workspace<T>& ws : workspaces) {
        ws.storage.assign(own_slots * kTileSize, T(0));
        ws.slots.assign(tape.slot_count, nullptr);
        for (uint32_t s = 0, next = 0; s < tape.slot_count; ++s)
            if (!borrowed[s]) ws.slots[s] = ws.storage.data() + static_cast<std::size_t>(next++) * kTileSize;
        for (auto [slot, value] : tape.constants) std::fill_n(ws.slots[slot], kTileSize, T(value));
        if (!tape.uniform_uses.empty()) ws.code = tape.code;
    }

    parallel_for(tiles, options, [&](std::size_t index, int worker) {
        Workspace<T>& ws = workspaces[worker];
        const Tile tile = tiling.tile(index);
        for (auto [slot, axis] : tape.arguments) {
            T* lane_values = ws.slots[slot];
            for (int l = 0; l < tile.lanes; ++l) {
                const std::size_t p = tile.first_point + l;
                lane_values[l] = T(axis == 0 ? grid.x_at(static_cast<int>(p % grid.cols()))
                                 : axis == 1 ? grid.y_at(static_cast<int>((p / grid.cols()) % grid.rows()))
                                             : grid.z_at(static_cast<int>(p / plane)));
            }
        }
        for (auto [slot, which] : tape.inputs) {
            const InputSource<T>& source = pass.inputs[which];
            if (source.hoisted) {
                auto row_start = [&](std::size_t row) {
                    return source.hoisted + row % grid.rows() * source.row_stride +
                           row / grid.rows() * source.slice_stride;
                };
                if (borrowed[slot]) {
                    ws.slots[slot] = const_cast<T*>(row_start(tile.row) + tile.first_col);
                    continue;
                }
                const int row_lanes = tile.lanes / tile.rows;
                for (int r = 0; r < tile.rows; ++r) {
                    const T* values = row_start(tile.row + r);
                    T* lane_values = ws.slots[slot] + r * row_lanes;
                    if (source.per_row_value) std::fill_n(lane_values, row_lanes, values[0]);
                    else std::copy_n(values + tile.first_col, row_lanes, lane_values);
                }
            } else {
                T* lane_values = ws.slots[slot];
                for (int l = 0; l < tile.lanes; ++l) lane_values[l] = T(source.per_point[tile.first_point + l]);
            }
        }
        // The row's values are patched into the code for the lane loops; compiled code takes
        // them straight into its constant pool where it reads none from the code.
        const bool code_read = !compiled || compiled->reads_code_constants();
        const std::size_t uniform_count = pass.spec.uniforms.size();
        const std::span<const T> row_values =
            std::span<const T>(pass.uniforms).subspan(tile.row * uniform_count, uniform_count);
        bool patched = false;
        if (!tape.uniform_uses.empty() && code_read && tile.row != ws.patched_row) {
            for (const UniformUse& use : tape.uniform_uses)
                ws.code[use.instruction].constant[use.operand] = double(row_values[use.uniform]);
            ws.patched_row = tile.row;
            patched = true;
        }
        const std::vector<Instruction>& code = tape.uniform_uses.empty() ? tape.code : ws.code;
        if (compiled) {
            const RowValues<T> row{row_values, tile.row};
            compiled->run(code.data(), code.size(), ws.slots.data(), tile.lanes, ws.jit, patched,
                          tape.uniform_uses.empty() || code_read ? nullptr : &row);
        } else {
            run_code<T>(code, ws.slots.data(), tile.lanes);
        }
        for (std::size_t k = 0; k < pass.outputs.size(); ++k) {
            const T* values = ws.slots[tape.outputs[k]];
            const OutputSink<T>& sink = pass.outputs[k];
            if (sink.as_double) std::copy_n(values, tile.lanes, sink.as_double + tile.first_point);
            else std::copy_n(values, tile.lanes, sink.as_t + tile.first_point);
        }
        return static_cast<std::size_t>(tile.lanes);
    });
}

/// The values of `nodes` at every point of `grid` (a grid of columns or of rows), as T.
template <class T>
std::vector<std::vector<T>> evaluate_nodes(const Graph& graph, const std::vector<NodeId>& nodes, const Grid& grid,
                                           const EvalOptions& options, const VoxelOptions& engine) {
    std::vector<std::vector<T>> values(nodes.size(), std::vector<T>(grid.points()));
    if (nodes.empty()) return values;
    const TapeSpec spec{nodes, {}, {}};
    const Tape tape = compile_tape(graph, spec);
    Pass<T> pass{tape, grid, {}, {}, {}, graph, spec, 0};
    for (std::vector<T>& v : values) pass.outputs.push_back({nullptr, v.data()});
    EvalOptions quiet = options;
    quiet.progress = nullptr;
    run_pass(pass, Tiling::flat(grid.points()), quiet, engine);
    return values;
}

/// Memory for the values of hoisted nodes, per kind (column, row, plane): past it that
/// kind is not hoisted (e.g. thousands of Y-only nodes on a 512³ grid's 262,144 rows).
constexpr std::size_t kMaxHoistedBytes = std::size_t{64} << 20;

/// The hoisting plan for `grid`, without the kinds whose values would not fit: turning a
/// kind off moves its nodes' operands to the other kinds, so the plan is made again until
/// every kind fits.
template <class T>
HoistPlan fitting_plan(const Graph& graph, const TapeSpec& spec, const Grid& grid) {
    const std::size_t cols = grid.cols(), rows = grid.rows(), slices = grid.slices();
    HoistKinds kinds{.columns = true, .rows = true, .xy_planes = slices > 1, .xz_planes = slices > 1};
    for (;;) {
        HoistPlan plan = plan_hoisting(graph, spec.outputs, spec.inputs, kinds);
        auto fits = [](const std::vector<NodeId>& nodes, std::size_t values) {
            return nodes.size() * values * sizeof(T) <= kMaxHoistedBytes;
        };
        // Column values are repeated for tiles of whole rows: up to kTileSize of them.
        const HoistKinds fitting{kinds.columns && fits(plan.column_nodes, std::max<std::size_t>(cols, kTileSize)),
                                 kinds.rows && fits(plan.row_nodes, rows * slices),
                                 kinds.xy_planes && fits(plan.xy_plane_nodes, cols * rows),
                                 kinds.xz_planes && fits(plan.xz_plane_nodes, cols * slices)};
        if (fitting.columns == kinds.columns && fitting.rows == kinds.rows && fitting.xy_planes == kinds.xy_planes &&
            fitting.xz_planes == kinds.xz_planes)
            return plan;
        kinds = fitting;
    }
}

template <class T>
void evaluate(const Graph& graph, NodeId root, Field& field, const EvalOptions& options, const VoxelOptions& engine,
              const NodeValues& reuse) {
    const Grid& grid = field.grid;
    TapeSpec spec{{root}, {}, {}};
    std::vector<OutputSink<T>> outputs{{field.values.data(), nullptr}};
    for (auto [node, values] : reuse.keep) {
        spec.outputs.push_back(node);
        outputs.push_back({values, nullptr});
    }
    std::vector<InputSource<T>> inputs;
    for (auto [node, values] : reuse.known) {
        spec.inputs.push_back(node);
        inputs.push_back({values, nullptr});
    }
    const std::size_t opaque_inputs = inputs.size();

    Tiling tiling = Tiling::flat(grid.points());
    std::vector<std::vector<T>> column_values, row_values, xy_values, xz_values;
    std::vector<T> uniforms;
    if (engine.hoist && grid.cols() >= kMinHoistColumns) {
        const HoistPlan plan = fitting_plan<T>(graph, spec, grid);
        Grid columns = grid;   // one row: the X of each column
        columns.dims = 2;
        columns.y.nodes = columns.z.nodes = 1;
        Grid rows = grid;      // one column: the Y (and Z) of each row
        rows.x.nodes = 1;
        Grid xy = grid;        // one slice: the X and Y of each column and row
        xy.z.nodes = 1;
        Grid xz = grid;        // one row per slice: the X and Z of each column and slice
        xz.y.nodes = 1;
        column_values = evaluate_nodes<T>(graph, plan.column_nodes, columns, options, engine);
        row_values = evaluate_nodes<T>(graph, plan.row_nodes, rows, options, engine);
        xy_values = evaluate_nodes<T>(graph, plan.xy_plane_nodes, xy, options, engine);
        xz_values = evaluate_nodes<T>(graph, plan.xz_plane_nodes, xz, options, engine);
        tiling = Tiling::by_rows(grid);
        const std::size_t cols = grid.cols(), rows_per_tile = tiling.rows_per_tile;
        // Tiles of whole rows read each column's values once per row: repeated that often,
        // they are read in place.
        if (rows_per_tile > 1)
            for (std::vector<T>& v : column_values) {
                v.resize(cols * rows_per_tile);
                for (std::size_t r = 1; r < rows_per_tile; ++r) std::copy_n(v.begin(), cols, v.begin() + r * cols);
            }
        auto read_hoisted = [&](const std::vector<NodeId>& nodes, const std::vector<std::vector<T>>& values,
                                InputSource<T> source) {
            for (std::size_t k = 0; k < nodes.size(); ++k) {
                spec.inputs.push_back(nodes[k]);
                source.hoisted = values[k].data();
                inputs.push_back(source);
            }
        };
        read_hoisted(plan.column_nodes, column_values, {.spans_rows = true});
        read_hoisted(plan.xy_plane_nodes, xy_values, {.row_stride = cols, .spans_rows = true});
        read_hoisted(plan.xz_plane_nodes, xz_values, {.slice_stride = cols});
        // Row values are immediates in tiles of one row, lane arrays in tiles of several.
        if (rows_per_tile > 1) {
            read_hoisted(plan.row_nodes, row_values,
                         {.row_stride = 1, .slice_stride = static_cast<std::size_t>(grid.rows()), .per_row_value = true});
        } else {
            spec.uniforms = plan.row_nodes;
            const std::size_t count = row_values.size(), rows_in_grid = row_values.empty() ? 0 : row_values[0].size();
            uniforms.resize(count * rows_in_grid);
            for (std::size_t u = 0; u < count; ++u) {
                for (std::size_t r = 0; r < rows_in_grid; ++r) uniforms[r * count + u] = row_values[u][r];
                std::vector<T>().swap(row_values[u]);   // one copy of them at a time
            }
        }
    }
    const Tape tape = compile_tape(graph, spec);
    run_pass(Pass<T>{tape, grid, std::move(inputs), std::move(uniforms), std::move(outputs), graph, spec, opaque_inputs},
             tiling, options, engine);
}

}  // namespace

const char* lane_loop_isa() {
#if defined(__AVX512F__)
    return "AVX-512";
#elif defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
    if (__builtin_cpu_supports("x86-64-v4")) return "AVX-512";   // the clone the loader picked
#endif
#if defined(__AVX2__)
    return "AVX2";
#else
    return "SSE2";
#endif
}

std::string_view VoxelEngine::name() const {
    return options_.precision == Precision::Float32 ? "voxel-f32" : "voxel";
}

std::string_view VoxelEngine::summary() const {
    return options_.precision == Precision::Float32
               ? "voxel in float32: about 2x faster, within 1e-5 of the field"
               : "functional-voxel composition, each node once per point";
}

EngineCapabilities VoxelEngine::capabilities() const {
    const bool float32 = options_.precision == Precision::Float32;
    return {.point = true, .gradients = true, .float32 = float32, .known_and_kept = true, .exact = !float32,
            .hoists = options_.hoist};
}

std::unique_ptr<Engine> VoxelEngine::tuned(const EngineSettings& settings) const {
    VoxelOptions options = options_;
    if (settings.precision == Precision::Float32) options.precision = Precision::Float32;
    options.hoist = options.hoist && settings.hoist;
    options.compile = options.compile && settings.compile;
    return std::make_unique<VoxelEngine>(options);
}

Field VoxelEngine::evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid,
                                 const EvalOptions& options, const NodeValues& reuse) const {
    Field field = Field::filled(grid, std::nan(""), options.threads);
    if (options_.precision == Precision::Float32) evaluate<float>(graph, root, field, options, options_, reuse);
    else evaluate<double>(graph, root, field, options, options_, reuse);
    return field;
}

PointValue VoxelEngine::evaluate_point(const ir::Graph& graph, ir::NodeId root, std::array<double, 3> point) const {
    return PointEvaluator(graph, root)(point);
}

PointEvaluator::PointEvaluator(const ir::Graph& graph, ir::NodeId root) : tape_(compile_tape(graph, root)) {}

PointValue PointEvaluator::operator()(std::array<double, 3> point) const {
    std::vector<Dual> values(tape_.slot_count, Dual(0.0));
    std::vector<Dual*> slots(tape_.slot_count);
    for (uint32_t s = 0; s < tape_.slot_count; ++s) slots[s] = &values[s];
    for (auto [slot, value] : tape_.constants) values[slot] = Dual(value);
    for (auto [slot, axis] : tape_.arguments) values[slot] = Dual::variable(point[axis], axis);
    run_lanes<Dual, 1>(tape_.code.data(), tape_.code.size(), slots.data(), 1);
    const Dual& r = values[tape_.root_slot];
    return PointValue{r.v, {r.d[0], r.d[1], r.d[2]}};
}

}  // namespace fortu
