// interp/fv_engine.cpp — FV arithmetic over the tape: per instruction, recover the operands'
// values from their stored M-images, apply the kernel, refit and encode the result's M-images.
#include "interp/fv_engine.hpp"

#include "interp/lane_kernel.hpp"
#include "interp/parallel.hpp"
#include "interp/tape.hpp"
#include "runtime/fv_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>

namespace fortu {
namespace {

using namespace ir;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// How many of its own precision bounds a SQRT operand may lie below 0 and still be taken as
/// 0: the errors of the steps that made it add up. Unquantised, the bound is a few ulps of
/// the plane's terms and the slack generous (at 8 ulps alone Fig. 3a at 800² kept 518
/// invalid nodes); in a palette the bound is already a whole code step.
constexpr double kNegativeSlackUnquantised = 1024, kNegativeSlackPalette = 4;

/// One component as stored: a palette code, or the double itself. An invalid node is stored
/// as code 0 in every image (palette_encode of NaN): its value coefficient then decodes to
/// −1, which no plane has (fv_model.hpp orients every plane so that coefficient is > 0).
/// palette_encode and palette_decode (runtime/palette.hpp), inlined here: they run for
/// every component of every node of every operation.
template <class Code>
class Codec {
public:
    explicit Codec(std::optional<Palette> palette) : top_(palette ? palette_levels(*palette) - 1.0 : 0.0) {
        if (palette == Palette::Grey8)
            for (std::uint32_t m = 0; m < 256; ++m) grey_[m] = palette_decode(m, Palette::Grey8);
    }
    Code encode(double n) const {
        if constexpr (std::is_floating_point_v<Code>) {
            return n;
        } else {
            if (std::isnan(n)) return 0;
            // round() of a value >= 0 as a truncation of it + 0.5: no library call.
            return static_cast<Code>(top_ * (1.0 + std::clamp(n, -1.0, 1.0)) / 2.0 + 0.5);
        }
    }
    double decode(Code m) const {
        if constexpr (std::is_floating_point_v<Code>) return m;
        else if constexpr (sizeof(Code) == 1) return grey_[m];
        else return 2.0 * m / top_ - 1.0;
    }

private:
    double top_;
    double grey_[256] = {};
};

/// The plane (3D: hyperplane) through node (c, r, s) and its stencil neighbours, with each
/// neighbour whose value is not finite replaced by the node's own value: where the exact
/// stencil meets an invalid point, the node keeps its value (flat towards the invalid
/// side) instead of becoming invalid itself, so invalid regions do not grow by a node per
/// operation. fv_node()'s stencil otherwise.
std::array<double, 5> plane_beside_invalid(const Field& field, int c, int r, int s) {
    const Grid& g = field.grid;
    const double v = field.values[g.index(c, r, s)];
    std::array<double, 5> out;
    out.fill(kNaN);
    if (!std::isfinite(v)) return out;
    auto neighbour = [](int i, int step, int nodes) {
        if (nodes <= 1) return -1;
        return i + step >= 0 && i + step < nodes ? i + step : i - step;
    };
    const int cx = neighbour(c, +1, g.cols()), ry = neighbour(r, -1, g.rows());
    const int sz = g.dims == 3 ? neighbour(s, +1, g.slices()) : -1;
    auto value_or_own = [&](int col, int row, int slice) {
        const double w = field.values[g.index(col, row, slice)];
        return std::isfinite(w) ? w : v;
    };
    const double x = g.x_at(c), y = g.y_at(r), z = g.z_at(s);
    const double px = cx < 0 ? x + 1 : g.x_at(cx), vx = cx < 0 ? v : value_or_own(cx, r, s);
    const double py = ry < 0 ? y + 1 : g.y_at(ry), vy = ry < 0 ? v : value_or_own(c, ry, s);
    if (g.dims != 3) {
        const auto n = fv_plane({x, y, v}, {px, y, vx}, {x, py, vy});
        std::copy(n.begin(), n.end(), out.begin());
        return out;
    }
    const double pz = sz < 0 ? z + 1 : g.z_at(sz), vz = sz < 0 ? v : value_or_own(c, r, sz);
    return fv_hyperplane({x, y, z, v}, {px, y, z, vx}, {x, py, z, vy}, {x, y, pz, vz});
}

/// One evaluation: the M-image store of every tape slot, and the value field of the node
/// being computed (the one full-grid array of doubles besides the stores).
template <class Code>
class FvRun {
public:
    FvRun(const Grid& grid, const Tape& tape, std::optional<Palette> palette, const EvalOptions& options)
        : grid_(grid), tape_(tape), codec_(palette),
          resolution_(palette ? 1.0 / (palette_levels(*palette) - 1.0) : 8 * std::numeric_limits<double>::epsilon()),
          negative_slack_(palette ? kNegativeSlackPalette : kNegativeSlackUnquantised),
          threads_(grid.points() >= (1u << 15) ? options.threads : 1), options_(options), stencil_(grid),
          components_(grid.dims == 3 ? 5 : 4), points_(grid.points()),
          lines_(static_cast<std::size_t>(grid.rows()) * grid.slices()), stores_(tape.slot_count) {
        current_.grid = grid;
        current_.values.assign(points_, 0.0);
        zeros_.assign(static_cast<std::size_t>(grid.cols()), 0.0);
    }

    /// The M-images of the coordinates and of constant outputs.
    void store_leaves() {
        for (auto [slot, axis] : tape_.arguments) {
            for (std::size_t p = 0; p < points_; ++p) {
                const int col = static_cast<int>(p % grid_.cols());
                const int row = static_cast<int>((p / grid_.cols()) % grid_.rows());
                const int slice = static_cast<int>(p / (static_cast<std::size_t>(grid_.cols()) * grid_.rows()));
                current_.values[p] = axis == 0 ? grid_.x_at(col) : axis == 1 ? grid_.y_at(row) : grid_.z_at(slice);
            }
            fit_and_store(slot);
        }
        for (auto [slot, value] : tape_.constants) {
            std::fill(current_.values.begin(), current_.values.end(), value);
            fit_and_store(slot);
        }
    }

    /// out := op(operands), every grid node, from and to M-images.
    void run(const Instruction& ins) {
        const int cols = grid_.cols();
        const int arity = op_arity(ins.op);
        std::vector<std::vector<double>> scratch(static_cast<std::size_t>(worker_count(lines_, threads_)),
                                                 std::vector<double>(3 * static_cast<std::size_t>(cols)));
        std::vector<std::vector<double*>> slots(scratch.size(), std::vector<double*>(tape_.slot_count, zeros_.data()));
        parallel_for(lines_, threads_, options_.cancel, [&](std::size_t line, int worker) {
            std::vector<double*>& slot = slots[worker];
            for (int k = 0; k < arity; ++k) {
                if (ins.constant_operands & (1u << k)) continue;
                double* values = scratch[worker].data() + k * static_cast<std::size_t>(cols);
                recover_line(ins.in[k], line, values, ins.op == Op::Sqrt);
                slot[ins.in[k]] = values;
            }
            slot[ins.out] = current_.values.data() + line * cols;
            run_lanes<double, 0>(&ins, 1, slot.data(), cols);
            for (int k = 0; k < arity; ++k) slot[ins.in[k]] = zeros_.data();
        });
        fit_and_store(ins.out);
    }

    /// The values every node of `slot`'s M-images give back (its local function at the node).
    Field values(uint32_t slot) const {
        Field field = Field::filled(grid_, kNaN, threads_);
        parallel_for(lines_, threads_, nullptr, [&](std::size_t line, int) {
            recover_line(slot, line, field.values.data() + line * grid_.cols());
        });
        return field;
    }

    /// `slot`'s M-images decoded, one array per component.
    std::vector<std::vector<double>> components(uint32_t slot) const {
        std::vector<std::vector<double>> out(components_, std::vector<double>(points_));
        const Code* codes = stores_[slot].data();
        for (int k = 0; k < components_; ++k)
            for (std::size_t p = 0; p < points_; ++p) {
                const double n = codec_.decode(codes[k * points_ + p]);
                out[k][p] = valid(codes, p) ? n : kNaN;
            }
        return out;
    }

private:
    bool valid(const Code* codes, std::size_t p) const {
        return codec_.decode(codes[(components_ - 2) * points_ + p]) > 0;   // n3 (3D: n4) > 0
    }

    /// The values of one line of `slot`; with `to_zero`, a value within the precision its
    /// M-images hold it of 0 is made exactly 0 (what SQRT's operand needs: fv_engine.hpp).
    void recover_line(uint32_t slot, std::size_t line, double* out, bool to_zero = false) const {
        const Code* codes = stores_[slot].data();
        const int row = static_cast<int>(line % grid_.rows()), slice = static_cast<int>(line / grid_.rows());
        const std::size_t first = line * grid_.cols();
        const double y = grid_.y_at(row), z = grid_.z_at(slice);
        double n[5];
        for (int c = 0; c < grid_.cols(); ++c) {
            const std::size_t p = first + c;
            for (int k = 0; k < components_; ++k) n[k] = codec_.decode(codes[k * points_ + p]);
            const double x = grid_.x_at(c), value_coefficient = n[components_ - 2];
            out[c] = value_coefficient > 0 ? local_value(std::span<const double>(n, components_), x, y, z) : kNaN;
            if (to_zero) {
                // The recovered value is a sum of terms n_k·coordinate over n3 (3D: n4); each
                // n_k is known to within `resolution_`, so the value to within this bound.
                double terms = std::abs(n[components_ - 1]) + std::abs(n[0] * x) + std::abs(n[1] * y);
                if (components_ == 5) terms += std::abs(n[2] * z);
                const double bound = resolution_ * (terms + std::abs(out[c] * value_coefficient)) / value_coefficient;
                // A negative operand also carries the errors of the steps before this one:
                // below 0 by up to kNegativeSlack bounds it is taken as 0, not as invalid.
                if (std::abs(out[c]) <= bound || (out[c] < 0 && -out[c] <= negative_slack_ * bound)) out[c] = 0.0;
            }
        }
    }

    void fit_and_store(uint32_t slot) {
        std::vector<Code>& store = stores_[slot];
        store.resize(components_ * points_);
        const int cols = grid_.cols();
        std::vector<std::vector<double>> scratch(static_cast<std::size_t>(worker_count(lines_, threads_)),
                                                 std::vector<double>(5 * static_cast<std::size_t>(cols)));
        parallel_for(lines_, threads_, options_.cancel, [&](std::size_t line, int worker) {
            const int row = static_cast<int>(line % grid_.rows()), slice = static_cast<int>(line / grid_.rows());
            double* n[5];
            for (int k = 0; k < 5; ++k) n[k] = scratch[worker].data() + k * static_cast<std::size_t>(cols);
            stencil_.row(current_, row, slice, n);
            const std::size_t first = line * cols;
            for (int c = 0; c < cols; ++c) {
                if (!std::isfinite(n[components_ - 2][c]) && std::isfinite(current_.values[first + c])) {
                    const auto fixed = plane_beside_invalid(current_, c, row, slice);
                    for (int k = 0; k < components_; ++k) n[k][c] = fixed[k];
                }
                for (int k = 0; k < components_; ++k) store[k * points_ + first + c] = codec_.encode(n[k][c]);
            }
        });
    }

    const Grid& grid_;
    const Tape& tape_;
    Codec<Code> codec_;
    /// How well a stored component is known: a palette's half step 1/(P−1), or a few ulps.
    double resolution_;
    double negative_slack_;
    /// Small grids on one thread: an instruction's two passes would otherwise start threads
    /// for a few microseconds of work each (prospero.vm has 7866 instructions).
    int threads_;
    const EvalOptions& options_;
    FvStencil stencil_;
    int components_;
    std::size_t points_, lines_;
    std::vector<std::vector<Code>> stores_;   ///< by tape slot: components_ arrays of points_ codes
    Field current_;                           ///< the values of the node being computed
    std::vector<double> zeros_;               ///< what the kernel's unused operands read
};

template <class Code>
Field evaluate(const Graph& graph, NodeId root, const Grid& grid, std::optional<Palette> palette,
               const EvalOptions& options) {
    // The step definitions are outputs of the tape, so their stores live to the end and each
    // is complete after the last instruction that writes its slot.
    TapeSpec spec{{root}, {}, {}};
    if (options.on_step)
        for (const auto& [name, node] : options.steps) spec.outputs.push_back(node);
    const Tape tape = compile_tape(graph, spec);
    FvRun<Code> run(grid, tape, palette, options);
    run.store_leaves();

    // Each step after the instruction that completes it (-1: a leaf, complete from the start).
    std::multimap<long, std::size_t> steps_after;
    for (std::size_t k = 1; k < tape.outputs.size(); ++k) {
        long last = -1;
        for (std::size_t i = 0; i < tape.code.size(); ++i)
            if (tape.code[i].out == tape.outputs[k]) last = static_cast<long>(i);
        steps_after.emplace(last, k - 1);
    }
    int step_index = 0;
    auto emit_steps = [&](long instruction) {
        auto [first, last] = steps_after.equal_range(instruction);
        for (auto it = first; it != last; ++it) {
            const uint32_t slot = tape.outputs[it->second + 1];
            const Field values = run.values(slot);
            const auto components = run.components(slot);
            options.on_step(EvalStep{++step_index, options.steps[it->second].first, values, components, palette});
        }
    };
    emit_steps(-1);
    const std::size_t count = tape.code.size();
    for (std::size_t i = 0; i < count; ++i) {
        if (options.cancel && options.cancel->load()) break;
        run.run(tape.code[i]);
        emit_steps(static_cast<long>(i));
        if (options.progress) options.progress(grid.points() * (i + 1) / count - grid.points() * i / count);
    }
    if (count == 0 && options.progress) options.progress(grid.points());
    return run.values(tape.root_slot);
}

}  // namespace

std::string storage_text(MimageStorage storage) {
    switch (storage) {
        case MimageStorage::Grey8: return "P = 256";
        case MimageStorage::Rgb24: return "P = 2^24";
        case MimageStorage::Float: return "unquantised";
    }
    return "";
}

std::string_view FvEngine::summary() const {
    return "the papers' FV method: each node from its operands' M-images (--palette)";
}

std::string FvEngine::description() const { return fmt::format("fv, {}", storage_text(options_.storage)); }

EngineCapabilities FvEngine::capabilities() const { return {.palette = true, .steps = true}; }

std::unique_ptr<Engine> FvEngine::tuned(const EngineSettings& settings) const {
    FvOptions options = options_;
    if (settings.storage) options.storage = *settings.storage;
    return std::make_unique<FvEngine>(options);
}

Field FvEngine::evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                              const NodeValues& reuse) const {
    if (!reuse.empty()) throw std::invalid_argument("the fv engine neither reads nor keeps node values");
    switch (options_.storage) {
        case MimageStorage::Grey8: return evaluate<std::uint8_t>(graph, root, grid, Palette::Grey8, options);
        case MimageStorage::Rgb24: return evaluate<std::uint32_t>(graph, root, grid, Palette::Rgb24, options);
        case MimageStorage::Float: break;
    }
    return evaluate<double>(graph, root, grid, std::nullopt, options);
}

}  // namespace fortu
