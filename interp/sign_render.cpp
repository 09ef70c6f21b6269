// interp/sign_render.cpp — the quadtree/octree walk: each box's intervals decide it or
// shorten its tape (box_simplify.hpp); the small boxes left undecided run their shortened
// tape with the lane kernel the voxel engine uses (lane_kernel.hpp).
#include "interp/sign_render.hpp"

#include "interp/box_halving.hpp"
#include "interp/box_intervals.hpp"
#include "interp/box_simplify.hpp"
#include "interp/float32_bound.hpp"
#include "interp/interval.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/parallel.hpp"
#include "interp/quadrant_intervals.hpp"
#include "interp/stored_sign.hpp"
#include "interp/tape.hpp"
#include "interp/written_r_operations.hpp"
#include "runtime/spread_thread.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace fortu {
namespace {

/// A box of grid nodes, inclusive index ranges per axis (col, row, slice).
struct Box {
    int lo[3];
    int hi[3];
    std::size_t points() const {
        return std::size_t(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    }
};

/// Leaf boxes hold at most 16×16 points in 2D, 8×8×8 in 3D: small enough that a box
/// straddling the boundary wastes little, large enough that the lane loops run long and the
/// most numerous boxes, the smallest, need no interval pass. Measured (one thread, min of 7):
/// prospero.vm 1024² 15 ms with 8×8 leaves, 13 ms with 16×16, 16 ms with 32×32. In 3D, 4³
/// leaves were best while leaves ran in float64 (6³ slower on bear.vm 128³: 129 against
/// 117 ms); with float32 leaves, whose bound pass costs a tape's length per leaf, 8³ leaves
/// skip the interval pass of the most numerous boxes (tanglecube.vm 256³: 2,441 boxes, not
/// 7,561), and a leaf whose bound fails still splits to 4³ (kSplitLeafExtent3d).
constexpr int kLeafLanes = 256;
constexpr int kLeafExtent3d = 8;
constexpr int kLeafLanes3d = kLeafExtent3d * kLeafExtent3d * kLeafExtent3d;
/// Lanes per slot in the leaves' arrays: the larger leaf.
constexpr int kLaneStride = std::max(kLeafLanes, kLeafLanes3d);

/// 3D leaves whose float32 bound is not finite split down to this extent before float64.
constexpr int kSplitLeafExtent3d = 4;
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

/// A 3D leaf's float32 bound that reaches the largest |value| its interval allows helps no
/// point, so the leaf splits as if it had none: a finite but loose bound across a pole
/// (bear.vm's exp(−30.6·max(…, |0.1/x|)) is within [0, 1] in both precisions) would
/// otherwise send the whole 8³ leaf to float64 instead of its 4³ parts to tighter intervals.
double useful_bound(double bound, const Interval& root) {
    return bound < std::max(std::abs(root.lo), std::abs(root.hi)) ? bound : kUnbounded;
}

/// One level of the 2D walk: the four quadrants' intervals and choices, and the tape of the
/// quadrant being walked.
struct QuadrantLevel {
    QuadrantScratch intervals;
    std::array<std::vector<uint8_t>, 4> choices;
    std::array<Interval, 4> roots;
    Tape tape;
};

struct Scratch {
    std::vector<Interval> ranges;
    std::vector<uint8_t> choices;   ///< per instruction of the box's tape (box_choice.hpp)
    BoxScratch box;
    std::vector<double> lanes;
    std::vector<double*> slots;
    std::vector<float> lanes32;
    std::vector<float*> slots32;
    std::vector<Interval> leaf_ranges;
    std::vector<double> errors;
    std::vector<std::size_t> close_points;    ///< grid indices rechecked in float64
    std::vector<std::unique_ptr<Tape>> tapes;  ///< one per recursion depth
    std::vector<std::unique_ptr<QuadrantLevel>> quadrant_levels;  ///< one per recursion depth (2D)
    Tape leaf_tape;                             ///< a long leaf tape in max-live slots
    SlotScratch slot_scratch;
};

/// Leaf tapes with more SSA slots than this run in reallocated slots: lanes cost slots ×
/// points, so a deep model no box shortens would cost gigabytes a worker, while the
/// short tapes of most leaves are not worth the extra pass.
constexpr uint32_t kReallocateAboveSlots = 4096;

/// A sign as stored: a float64 value (a Field) or an int8 (a SignVolume).
template <class Value>
Value stored_sign(double sign) {
    if constexpr (std::is_same_v<Value, double>) return sign;
    else return SignVolume::code_of(sign != sign ? SignVolume::kNaN : static_cast<int8_t>(sign));
}

/// The signs start as outside (−1) and boxes decided outside are not written again: most of a
/// domain is usually outside, and rewriting it row by row cost more than its intervals
/// (tanglecube.vm 256³: a quarter of the evaluation's instructions, in rows of 4–16 bytes).
constexpr double kBackgroundSign = -1.0;

/// A 2D sign image (int8) has its pages faulted in before the render up to 2048²: rows of at
/// most 2 KiB, two or more to a page, so the render writes most pages.
constexpr std::size_t kPopulateSignImageUpTo = std::size_t(4) << 20;
constexpr std::size_t kPopulateSignRowUpTo = 2048;

template <class Signs>
class Renderer {
public:
    using Value = typename Signs::value_type;

    Renderer(const Grid& grid, Signs& signs, int leaf_extent)
        : grid_(grid), signs_(signs), leaf_extent_(leaf_extent) {
        for (int c = 0; c < grid.cols(); ++c) x_.push_back(grid.x_at(c));
        for (int j = 0; j < grid.rows(); ++j) y_.push_back(grid.y_at(j));
        for (int k = 0; k < grid.slices(); ++k) z_.push_back(grid.z_at(k));
        x32_.assign(x_.begin(), x_.end());
        y32_.assign(y_.begin(), y_.end());
        z32_.assign(z_.begin(), z_.end());
    }

    /// Evaluates the box's intervals: the sign of the whole box when they decide it;
    /// otherwise simplifies `tape` into `simplified` and returns nullopt.
    std::optional<double> decide(const Box& box, const Tape& tape, Scratch& s, Tape& simplified,
                                 SignRenderStats& st) const {
        if (const std::optional<double> sign = interval_sign(box, tape, s, st)) return sign;
        simplify_for_sign(tape, s.choices, s.box, simplified);
        return std::nullopt;
    }

    /// The box's intervals (into s.ranges): the sign of the whole box when they decide it.
    std::optional<double> interval_sign(const Box& box, const Tape& tape, Scratch& s, SignRenderStats& st) const {
        ++st.boxes;
        evaluate_box_intervals(tape, {axis_interval(box, 0), axis_interval(box, 1), axis_interval(box, 2)}, s.ranges,
                               s.choices);
        return counted_sign(box, s.ranges[tape.root_slot], st);
    }

    /// decided_sign of a box whose root ranges over `r`, its points counted as decided.
    static std::optional<double> counted_sign(const Box& box, const Interval& r, SignRenderStats& st) {
        const std::optional<double> sign = decided_sign(r);
        if (sign) st.decided_points += box.points();
        return sign;
    }

    /// The sign of a whole box whose root ranges over `r`, where the range decides it.
    static std::optional<double> decided_sign(const Interval& r) {
        if (r.positive() || r.negative() || (r.lo == 0 && r.hi == 0 && !r.maybe_nan))
            return r.positive() ? 1.0 : r.negative() ? -1.0 : 0.0;
        return std::nullopt;
    }

    bool is_leaf(const Box& box) const {
        for (int a = 0; a < 3; ++a)
            if (box.hi[a] - box.lo[a] + 1 > leaf_extent_) return false;
        return true;
    }

    /// Halves every axis longer than one node.
    static std::vector<Box> split(const Box& box) {
        return halve_axes(box, [&box](int a) { return box.hi[a] != box.lo[a]; });
    }

    /// The parts of split(box), in the same order, without allocating (the depth-first walk
    /// splits every undecided box; split allocates three vectors each time).
    struct Parts {
        Box box[8];
        int count = 0;
        const Box* begin() const { return box; }
        const Box* end() const { return box + count; }
    };
    static Parts split_in_place(const Box& box) {
        Parts parts;
        parts.box[0] = box;
        parts.count = 1;
        for (int a = 0; a < 3; ++a) {
            if (box.hi[a] == box.lo[a]) continue;
            const int mid = (box.lo[a] + box.hi[a]) / 2;
            for (int i = parts.count; i-- > 0;) {   // backwards: part i becomes parts 2i, 2i + 1
                Box low = parts.box[i], high = parts.box[i];
                low.hi[a] = mid;
                high.lo[a] = mid + 1;
                parts.box[2 * i] = low;
                parts.box[2 * i + 1] = high;
            }
            parts.count *= 2;
        }
        return parts;
    }

    /// Depth-first: the box with its parent's tape.
    void render(const Box& box, const Tape& tape, Scratch& s, std::size_t depth, SignRenderStats& st) {
        if (s.tapes.size() <= depth) s.tapes.push_back(std::make_unique<Tape>());
        Tape& simplified = *s.tapes[depth];
        if (const std::optional<double> sign = interval_sign(box, tape, s, st)) {
            if (*sign != kBackgroundSign) fill(box, *sign);
            return;
        }
        double parent_bound = 0.0;
        if (grid_.slices() > 1 && is_leaf(box) && evaluate_points_unsimplified(box, tape, s, st, parent_bound)) return;
        simplify_for_sign(tape, s.choices, s.box, simplified);
        if (is_leaf(box)) {
            // A 3D leaf whose float32 bound is not finite over the whole box: its parts have
            // tighter intervals (bear.vm's sums of exponentials), so they try again; the
            // float64 lanes that remain, 64 where they were 512, carry libm's scalar calls.
            // Where the parent's tape had no finite bound over this box, its shortened tape
            // is not tried first: it rarely has one (bear.vm 128³: 3% fewer instructions).
            const bool splits = grid_.slices() > 1 && box.hi[0] - box.lo[0] + 1 > kSplitLeafExtent3d;
            double bound = splits && !(parent_bound < kUnbounded) ? kUnbounded : float32_bound(box, simplified, s);
            if (splits && bound < kUnbounded) bound = useful_bound(bound, s.leaf_ranges[simplified.root_slot]);
            if (!(bound < kUnbounded) && splits) {
                for (const Box& child : split_in_place(box)) render(child, simplified, s, depth + 1, st);
                return;
            }
            evaluate_points(box, simplified, bound, s, st);
            return;
        }
        if (grid_.slices() == 1) {
            render_quadrants(box, simplified, s, depth + 1, st);
            return;
        }
        for (const Box& child : split_in_place(box)) render(child, simplified, s, depth + 1, st);
    }

    /// The intervals and choices of the four quadrants `parts` over `tape`, in one walk, into
    /// the quadrant scratch of `depth` (made on first use).
    QuadrantLevel& walk_quadrants(const Parts& parts, const Tape& tape, Scratch& s, std::size_t depth,
                                  SignRenderStats& st) const {
        while (s.quadrant_levels.size() <= depth) s.quadrant_levels.push_back(std::make_unique<QuadrantLevel>());
        QuadrantLevel& level = *s.quadrant_levels[depth];
        std::array<std::array<Interval, 3>, 4> axes;
        for (int q = 0; q < 4; ++q)
            for (int a = 0; a < 3; ++a) axes[q][a] = axis_interval(parts.box[q], a);
        evaluate_quadrant_intervals(tape, axes, level.intervals, level.choices, level.roots);
        st.boxes += 4;
        return level;
    }

    /// A box of the breadth-first levels (2D) and a tape valid over it (the domain's, or one
    /// shortened for the box, whose intervals did not decide it): its parts, split as
    /// render_quadrants splits them, decided into `decided` or with their shortened tapes into
    /// `undecided` (the box's own tape where a part barely shortens it: the copy is not worth it).
    struct Part {
        Box box;
        std::shared_ptr<const Tape> tape;
    };
    void split_step(const Box& box, const std::shared_ptr<const Tape>& tape, Scratch& s, SignRenderStats& st,
                    std::vector<std::pair<Box, double>>& decided, std::vector<Part>& undecided) {
        const Parts parts = split_in_place(box);
        auto keep = [&](const Box& child, std::shared_ptr<Tape> shortened) {
            if (shortened->code.size() * 8 > tape->code.size() * 7) undecided.push_back({child, tape});
            else undecided.push_back({child, std::move(shortened)});
        };
        if (parts.count != 4) {
            for (const Box& child : parts) {
                if (const std::optional<double> sign = interval_sign(child, *tape, s, st)) {
                    decided.emplace_back(child, *sign);
                    continue;
                }
                auto shortened = std::make_shared<Tape>();
                simplify_for_sign(*tape, s.choices, s.box, *shortened);
                keep(child, std::move(shortened));
            }
            return;
        }
        const QuadrantLevel& level = walk_quadrants(parts, *tape, s, 0, st);
        for (int q = 0; q < 4; ++q) {
            if (const std::optional<double> sign = counted_sign(parts.box[q], level.roots[q], st)) {
                decided.emplace_back(parts.box[q], *sign);
                continue;
            }
            auto shortened = std::make_shared<Tape>();
            simplify_for_sign(*tape, level.choices[q], s.box, *shortened);
            keep(parts.box[q], std::move(shortened));
        }
    }

    /// A box of the breadth-first levels (2D) whose tape is valid over it and whose intervals
    /// do not decide it (or were not taken: an image of one leaf), to the end: a leaf's
    /// points, or its quadrants.
    void render_undecided(const Box& box, const Tape& tape, Scratch& s, SignRenderStats& st) {
        if (is_leaf(box)) evaluate_points(box, tape, float32_bound(box, tape, s), s, st);
        else render_quadrants(box, tape, s, 0, st);
    }

    /// Depth-first in 2D: the four quadrants of `box` on the box's shortened tape, their
    /// intervals in one walk of it (quadrant_intervals.hpp); each undecided quadrant is
    /// shortened from its choices and walked the same way, down to the leaves.
    void render_quadrants(const Box& box, const Tape& tape, Scratch& s, std::size_t depth, SignRenderStats& st) {
        const Parts parts = split_in_place(box);
        if (parts.count != 4) {   // a box one node wide or high: its halves one by one
            for (const Box& child : parts) render(child, tape, s, depth, st);
            return;
        }
        QuadrantLevel& level = walk_quadrants(parts, tape, s, depth, st);
        for (int q = 0; q < 4; ++q) {
            const Box& child = parts.box[q];
            if (const std::optional<double> sign = counted_sign(child, level.roots[q], st)) {
                if (*sign != kBackgroundSign) fill(child, *sign);
                continue;
            }
            simplify_for_sign(tape, level.choices[q], s.box, level.tape);
            if (is_leaf(child)) {
                evaluate_points(child, level.tape, float32_bound(child, level.tape, s), s, st);
                continue;
            }
            render_quadrants(child, level.tape, s, depth + 1, st);
        }
    }

    /// Calls body(width) with the box's width as a compile-time constant for the leaves'
    /// usual widths (16 in 2D, kLeafExtent3d in 3D), so their row loops unroll; 0 otherwise.
    template <class Body>
    static void with_width(const Box& box, Body body) {
        const int width = box.hi[0] - box.lo[0] + 1;
        if (width == 16) body(std::integral_constant<int, 16>{});
        else if (width == kLeafExtent3d) body(std::integral_constant<int, kLeafExtent3d>{});
        else body(std::integral_constant<int, 0>{});
    }

    /// The argument lanes of a box: X fastest, then Y, then Z, as the grid stores them, so a
    /// row is a copy of the column coordinates or one repeated Y or Z.
    template <int kWidth, class F>
    void fill_arguments(const Box& box, const Tape& tape, F* const* slots, const std::vector<F>& xs,
                        const std::vector<F>& ys, const std::vector<F>& zs) const {
        const int width = kWidth > 0 ? kWidth : box.hi[0] - box.lo[0] + 1;
        for (auto [slot, axis] : tape.arguments) {
            F* out = slots[slot];
            const F* x = xs.data() + box.lo[0];
            for (int k = box.lo[2]; k <= box.hi[2]; ++k)
                for (int j = box.lo[1]; j <= box.hi[1]; ++j, out += width) {
                    if (axis == 0) std::copy_n(x, width, out);
                    else std::fill_n(out, width, axis == 1 ? ys[j] : zs[k]);
                }
        }
    }

    /// The signs of a leaf's lane results (in the box's order) into the grid.
    template <int kWidth, class F>
    void store_signs(const Box& box, const F* result) {
        const int width = kWidth > 0 ? kWidth : box.hi[0] - box.lo[0] + 1;
        for (int k = box.lo[2]; k <= box.hi[2]; ++k)
            for (int j = box.lo[1]; j <= box.hi[1]; ++j, result += width)
                store_sign_row<kWidth>(signs_.data() + grid_.index(box.lo[0], j, k), result, width);
    }

    /// The float32 error bound of `tape` over the box (float32_bound.hpp); kUnbounded for
    /// tapes too long to run in SSA slots.
    double float32_bound(const Box& box, const Tape& tape, Scratch& s) const {
        if (tape.slot_count > kReallocateAboveSlots) return kUnbounded;
        evaluate_box_intervals(tape, {axis_interval(box, 0), axis_interval(box, 1), axis_interval(box, 2)},
                               s.leaf_ranges, s.choices);
        return float32_error_bound(tape, s.leaf_ranges, s.errors);
    }

    /// The leaf in float32 (twice the lanes per vector, SLEEF's transcendentals): done when
    /// every point's |value| exceeds the bound on its distance to the float64 value
    /// (float32_bound.hpp), so its sign is the float64 sign; false leaves it to float64.
    bool evaluate_points_float32(const Box& box, const Tape& tape, double bound, Scratch& s) {
        if (!(bound < kUnbounded)) return false;
        const int n = static_cast<int>(box.points());
        prepare_lanes(tape, s.lanes32, s.slots32);
        run_leaf(box, tape, s.slots32.data(), x32_, y32_, z32_);
        const float* result = s.slots32[tape.root_slot];
        // Rounded up, so |value| > limit implies |value| > bound.
        const float limit = std::nextafter(static_cast<float>(bound), std::numeric_limits<float>::infinity());
        int close = 0;
        for (int l = 0; l < n; ++l) close += !(std::abs(result[l]) > limit);  // NaN counts as close
        if (close * 4 > n) return false;   // most points again: the whole box in float64
        with_width(box, [&](auto width) { store_signs<width()>(box, result); });
        if (close > 0) recheck_float64(box, tape, s, limit);
        return true;
    }

    /// The points of a float32 leaf whose |value| is within the bound (or NaN) evaluated again
    /// in float64, packed into the first lanes.
    void recheck_float64(const Box& box, const Tape& tape, Scratch& s, float limit) {
        prepare_lanes(tape, s.lanes, s.slots);
        const float* result = s.slots32[tape.root_slot];
        s.close_points.clear();
        const int width = box.hi[0] - box.lo[0] + 1, height = box.hi[1] - box.lo[1] + 1;
        for (int l = 0; l < int(box.points()); ++l) {
            if (std::abs(result[l]) > limit) continue;
            const int c = box.lo[0] + l % width, j = box.lo[1] + (l / width) % height, k = box.lo[2] + l / (width * height);
            const int lane = static_cast<int>(s.close_points.size());
            for (auto [slot, axis] : tape.arguments) s.slots[slot][lane] = axis == 0 ? x_[c] : axis == 1 ? y_[j] : z_[k];
            s.close_points.push_back(grid_.index(c, j, k));
        }
        const int n = static_cast<int>(s.close_points.size());
        for (auto [slot, value] : tape.constants) std::fill_n(s.slots[slot], n, value);
        run_lanes<double, 0>(tape.code.data(), tape.code.size(), s.slots.data(), n);
        for (int lane = 0; lane < n; ++lane)
            signs_[s.close_points[lane]] = stored_sign_of<Value>(s.slots[tape.root_slot][lane]);
    }

    /// Lane arrays of kLaneStride for every slot of `tape`, in either precision.
    template <class F>
    static void prepare_lanes(const Tape& tape, std::vector<F>& lanes, std::vector<F*>& slots) {
        if (lanes.size() < std::size_t(tape.slot_count) * kLaneStride) {
            lanes.resize(std::size_t(tape.slot_count) * kLaneStride);
            slots.clear();
        }
        if (slots.size() < tape.slot_count) {
            slots.resize(lanes.size() / kLaneStride);
            for (std::size_t k = 0; k < slots.size(); ++k) slots[k] = lanes.data() + k * kLaneStride;
        }
    }

    /// A leaf's points through the lane kernel, in either precision: arguments and constants
    /// filled, the usual leaf sizes with a fixed lane count.
    template <class F>
    void run_leaf(const Box& box, const Tape& tape, F* const* slots, const std::vector<F>& xs,
                  const std::vector<F>& ys, const std::vector<F>& zs) const {
        const int n = static_cast<int>(box.points());
        with_width(box, [&](auto width) { fill_arguments<width()>(box, tape, slots, xs, ys, zs); });
        for (auto [slot, value] : tape.constants) std::fill_n(slots[slot], n, F(value));
        if (n == kLeafLanes) run_lanes<F, kLeafLanes>(tape.code.data(), tape.code.size(), slots, n);
        else if (n == kLeafLanes3d) run_lanes<F, kLeafLanes3d>(tape.code.data(), tape.code.size(), slots, n);
        else run_lanes<F, 0>(tape.code.data(), tape.code.size(), slots, n);
    }

    /// A 3D leaf on its parent's tape, in float32, with the bound from the ranges its interval
    /// pass left in s.ranges: no shortening and no second interval pass. Why: a leaf's own
    /// shortening and the intervals of its shortened tape cost about as much per operation as
    /// running the operation on its points in float32, so they pay only where they remove
    /// almost all of the parent's tape: they do in 2D (prospero.vm 1024², render instructions
    /// 73 M with them, 80 M without), not in 3D (tanglecube.vm 256³ 18.1 M → 15.9 M, bear.vm
    /// 128³ 1,197 M → 1,174 M). False (nothing written) when the bound is not finite or most
    /// points fall within it: the shortened path then decides. `bound`: the bound found.
    bool evaluate_points_unsimplified(const Box& box, const Tape& tape, Scratch& s, SignRenderStats& st,
                                      double& bound) {
        bound = kUnbounded;
        if (tape.slot_count > kReallocateAboveSlots) return false;
        bound = useful_bound(float32_error_bound(tape, s.ranges, s.errors), s.ranges[tape.root_slot]);
        if (!evaluate_points_float32(box, tape, bound, s)) return false;
        st.leaf_points += box.points();
        st.leaf_operations += box.points() * tape.code.size();
        return true;
    }

    /// The leaf's points: in float32 where `bound` (float32_bound) allows, else in float64.
    void evaluate_points(const Box& box, const Tape& ssa, double bound, Scratch& s, SignRenderStats& st) {
        if (ssa.slot_count <= kReallocateAboveSlots && evaluate_points_float32(box, ssa, bound, s)) {
            st.leaf_points += box.points();
            st.leaf_operations += box.points() * ssa.code.size();
            return;
        }
        ++st.float64_leaves;
        if (ssa.slot_count > kReallocateAboveSlots) reallocate_slots(ssa, s.leaf_tape, s.slot_scratch);
        const Tape& tape = ssa.slot_count > kReallocateAboveSlots ? s.leaf_tape : ssa;
        const int n = static_cast<int>(box.points());
        prepare_lanes(tape, s.lanes, s.slots);
        run_leaf(box, tape, s.slots.data(), x_, y_, z_);
        const double* result = s.slots[tape.root_slot];
        with_width(box, [&](auto width) { store_signs<width()>(box, result); });
        st.leaf_points += n;
        st.leaf_operations += std::size_t(n) * tape.code.size();
    }

    void fill(const Box& box, double sign) {
        for (int k = box.lo[2]; k <= box.hi[2]; ++k)
            for (int j = box.lo[1]; j <= box.hi[1]; ++j) {
                Value* row = signs_.data() + grid_.index(box.lo[0], j, k);
                std::fill_n(row, box.hi[0] - box.lo[0] + 1, stored_sign<Value>(sign));
            }
    }

private:
    Interval axis_interval(const Box& box, int axis) const {
        const std::vector<double>& at = axis == 0 ? x_ : axis == 1 ? y_ : z_;
        const double p = at[box.lo[axis]], q = at[box.hi[axis]];
        return {std::min(p, q), std::max(p, q), false};
    }

    const Grid& grid_;
    Signs& signs_;
    int leaf_extent_;
    std::vector<double> x_, y_, z_;   ///< the grid's coordinates per column, row, slice
    std::vector<float> x32_, y32_, z32_;  ///< the same rounded to float32
};

/// The render into `signs` (grid.points() of them, allocated here).
template <class Signs>
void render_signs(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                  SignRenderStats* stats, Signs& signs) {
    using Value = typename Signs::value_type;
    // A Field's background, one sequential pass (page faults: ~3 ms for 1024²), is written on
    // its own thread while the first levels of the tree only decide boxes; their fills wait
    // for it. A SignVolume's codes start as outside in the fresh pages' zero bytes, so it is
    // only mapped, here. A 2D image of narrow rows has its pages faulted in at once
    // (zeroed_pages.hpp); a 3D volume's or a larger image's fault in as they are written,
    // since many are not. A cancelled render reads NaN everywhere, so no unreached node
    // passes for outside.
    std::exception_ptr allocation_failure;
    std::optional<SpreadThread> allocation;   // joined on any exit, so an exception cannot leave it running
    if constexpr (std::is_same_v<Value, double>) {
        allocation.emplace([&] {
            try {
                signs.assign(grid.points(), kBackgroundSign);
            } catch (...) {
                allocation_failure = std::current_exception();
            }
        });
    } else {
        signs.resize(grid.points());
        const std::size_t bytes = signs.size() * sizeof(Value);
        const bool narrow_rows = std::size_t(grid.cols()) * sizeof(Value) <= kPopulateSignRowUpTo;
        if (grid.slices() == 1 && narrow_rows && bytes <= kPopulateSignImageUpTo)
            populate_for_writing(signs.data(), bytes);
    }
    Renderer<Signs> renderer(grid, signs, grid.slices() > 1 ? kLeafExtent3d : 16);
    const int threads = resolve_threads(options.threads);
    std::vector<Scratch> scratch(threads);
    std::vector<SignRenderStats> worker_stats(threads);
    EvalOptions quiet = options;
    quiet.progress = nullptr;

    // Breadth-first, level by level, until there are enough boxes to share between
    // workers; then each worker takes whole boxes depth-first.
    struct Item {
        Box box;
        std::shared_ptr<const Tape> tape;
    };
    struct Decided {
        Box box;
        double sign;
    };
    std::vector<Item> items{{Box{{0, 0, 0}, {grid.cols() - 1, grid.rows() - 1, grid.slices() - 1}},
                             std::make_shared<const Tape>(pruning_tape(graph, root))}};
    std::vector<Decided> decided;
    const std::size_t enough = std::size_t(16) * threads;
    // 2D: each level's quadrants in one walk of their box's tape (render_quadrants), so the
    // items carry tapes already shortened for their box. The whole domain's own intervals are
    // not taken first: they rarely decide an image, and its tape shortened for the whole
    // domain is nearly the tape itself (prospero.vm: that pass and copy were 2.6% of the
    // render's instructions).
    const bool quadrants = grid.slices() == 1;
    for (bool split_any = true; quadrants && split_any && !items.empty() && items.size() < enough;) {
        std::vector<std::vector<std::pair<Box, double>>> decided_parts(items.size());
        std::vector<std::vector<typename Renderer<Signs>::Part>> parts(items.size());
        parallel_for(items.size(), quiet, [&](std::size_t i, int worker) {
            if (renderer.is_leaf(items[i].box)) parts[i].push_back({items[i].box, items[i].tape});
            else renderer.split_step(items[i].box, items[i].tape, scratch[worker], worker_stats[worker], decided_parts[i], parts[i]);
            return std::size_t{0};
        });
        std::vector<Item> next;
        split_any = false;
        for (std::size_t i = 0; i < items.size(); ++i) {
            for (const auto& [box, sign] : decided_parts[i]) decided.push_back({box, sign});
            split_any |= !renderer.is_leaf(items[i].box);
            for (const auto& part : parts[i]) next.push_back({part.box, part.tape});
        }
        items = std::move(next);
        if (options.cancel && options.cancel->load()) break;
    }
    for (bool split_any = true; !quadrants && split_any && items.size() < enough;) {
        std::vector<std::vector<Item>> children(items.size());
        std::vector<std::optional<double>> signs(items.size());
        parallel_for(items.size(), quiet, [&](std::size_t i, int worker) {
            const Item& item = items[i];
            if (renderer.is_leaf(item.box)) {
                children[i].push_back(item);
                return std::size_t{0};
            }
            auto simplified = std::make_shared<Tape>();
            signs[i] = renderer.decide(item.box, *item.tape, scratch[worker], *simplified, worker_stats[worker]);
            // A tape the box barely shortens is not copied: the parent's serves the children.
            std::shared_ptr<const Tape> tape = simplified;
            if (simplified->code.size() * 8 > item.tape->code.size() * 7) tape = item.tape;
            if (!signs[i])
                for (const Box& child : Renderer<Signs>::split(item.box)) children[i].push_back({child, tape});
            return std::size_t{0};
        });
        std::vector<Item> next;
        split_any = false;
        for (std::size_t i = 0; i < items.size(); ++i) {
            if (signs[i]) decided.push_back({items[i].box, *signs[i]});
            split_any |= children[i].size() > 1;
            next.insert(next.end(), children[i].begin(), children[i].end());
        }
        items = std::move(next);
        if (options.cancel && options.cancel->load()) break;
    }
    if (allocation) allocation->join();
    if (allocation_failure) std::rethrow_exception(allocation_failure);
    std::size_t decided_points = 0;
    for (const Decided& d : decided) {
        if (d.sign != kBackgroundSign) renderer.fill(d.box, d.sign);
        decided_points += d.box.points();
    }
    if (options.progress && decided_points > 0) options.progress(decided_points);

    parallel_for(items.size(), options, [&](std::size_t i, int worker) {
        if (quadrants) renderer.render_undecided(items[i].box, *items[i].tape, scratch[worker], worker_stats[worker]);
        else renderer.render(items[i].box, *items[i].tape, scratch[worker], 0, worker_stats[worker]);
        return items[i].box.points();
    });
    if (options.cancel && options.cancel->load())
        std::fill(signs.begin(), signs.end(), stored_sign<Value>(std::nan("")));
    if (stats) {
        SignRenderStats total;
        for (const SignRenderStats& w : worker_stats) {
            total.boxes += w.boxes;
            total.decided_points += w.decided_points;
            total.leaf_points += w.leaf_points;
            total.leaf_operations += w.leaf_operations;
            total.float64_leaves += w.float64_leaves;
        }
        *stats = total;
    }
}

}  // namespace

Field sign_render(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                  SignRenderStats* stats) {
    Field field;
    field.grid = grid;
    render_signs(graph, root, grid, options, stats, field.values);
    return field;
}

SignVolume sign_render_volume(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                              SignRenderStats* stats) {
    SignVolume volume;
    volume.grid = grid;
    render_signs(graph, root, grid, options, stats, volume.codes);
    return volume;
}

Field SignVolume::expanded() const {
    Field field;
    field.grid = grid;
    field.values.resize(codes.size());
    for (std::size_t i = 0; i < codes.size(); ++i) field.values[i] = sign(i) == kNaN ? std::nan("") : sign(i);
    return field;
}

FieldStats SignVolume::stats() const {
    // Counted in blocks with one byte counter per lane, which the compiler turns into vector
    // compares: the plain loop took longer than rendering tanglecube.vm's 256³ signs.
    constexpr std::size_t kLanes = 64, kRounds = 255;  // a byte counter holds 255
    std::size_t positive = 0, zero = 0, invalid = 0, i = 0;
    const int8_t* v = codes.data();
    const std::size_t n = codes.size();
    constexpr int8_t kPositive = code_of(1), kZero = code_of(0), kInvalid = code_of(kNaN);
    for (; i + kLanes * kRounds <= n; i += kLanes * kRounds) {
        uint8_t pos[kLanes] = {}, zer[kLanes] = {}, nan[kLanes] = {};
        for (std::size_t r = 0; r < kRounds; ++r)
            for (std::size_t l = 0; l < kLanes; ++l) {
                const int8_t x = v[i + r * kLanes + l];
                pos[l] += x == kPositive;
                zer[l] += x == kZero;
                nan[l] += x == kInvalid;
            }
        for (std::size_t l = 0; l < kLanes; ++l) {
            positive += pos[l];
            zero += zer[l];
            invalid += nan[l];
        }
    }
    for (; i < n; ++i) {
        positive += v[i] == kPositive;
        zero += v[i] == kZero;
        invalid += v[i] == kInvalid;
    }
    FieldStats s;
    s.points = n;
    s.positive = positive;
    s.zero = zero;
    s.invalid = invalid;
    s.negative = n - positive - zero - invalid;
    const std::size_t finite = s.points - s.invalid;
    if (finite > 0) {
        s.min = s.negative > 0 ? -1.0 : s.zero > 0 ? 0.0 : 1.0;
        s.max = s.positive > 0 ? 1.0 : s.zero > 0 ? 0.0 : -1.0;
        s.mean = (double(s.positive) - double(s.negative)) / double(finite);
    }
    return s;
}

Field SignEngine::evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                               const NodeValues& reuse) const {
    if (!reuse.empty()) throw std::invalid_argument("the sign renderer takes no known or kept node values");
    return sign_render(graph, root, grid, options);
}

}  // namespace fortu
