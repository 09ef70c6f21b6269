// interp/sign_render.cpp — the quadtree/octree walk, per-box tape simplification, and the
// point-wise evaluation of the small boxes left undecided.
#include "interp/sign_render.hpp"

#include "interp/interval.hpp"
#include "interp/ir/kernels.hpp"
#include "interp/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

namespace fortu {
namespace {

using namespace ir;  // kernel names are used unqualified inside ops.def expressions

/// One operation of a box's tape; operands are indices of earlier operations (SSA).
struct BoxOp {
    Op op;
    uint32_t in[kMaxArity];
    double imm;
};

struct BoxTape {
    std::vector<BoxOp> ops;
    uint32_t root = 0;
};

/// A box of grid nodes, inclusive index ranges per axis (col, row, slice).
struct Box {
    int lo[3];
    int hi[3];
    std::size_t points() const {
        return std::size_t(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    }
};

/// Leaf boxes hold at most 16×16 points in 2D, 4×4×4 in 3D: small enough that a box
/// straddling the boundary wastes little, large enough that the lane loops run long and the
/// most numerous boxes, the smallest, need no interval pass. Measured (one thread, min of 7):
/// prospero.vm 1024² 15 ms with 8×8 leaves, 13 ms with 16×16, 16 ms with 32×32; in 3D, 6³
/// leaves were slower than 4³ on bear.vm 128³ (129 against 117 ms).
constexpr int kLeafLanes = 256;

constexpr int32_t kKeep = -1;
constexpr int32_t kPlusOne = -2;
constexpr int32_t kMinusOne = -3;

/// Whether the sign of op's result depends only on the signs of operand k (so that
/// operand may be replaced by anything with the same sign).
bool passes_sign(Op op, int k) {
    switch (op) {
    case Op::Neg:
    case Op::Min:
    case Op::Max:
    case Op::RAnd:
    case Op::ROr: return true;
    case Op::Select: return k > 0;  // SELECT(c, x, y): the signs of x and y, not of c
    default: return false;
    }
}

struct Scratch {
    std::vector<Interval> intervals;
    std::vector<uint8_t> live;
    std::vector<uint8_t> sign_only;
    std::vector<int32_t> replace;
    std::vector<uint32_t> renumber;
    std::vector<double> lanes;
    std::vector<std::unique_ptr<BoxTape>> tapes;  ///< one per recursion depth
};

class Renderer {
public:
    Renderer(const Grid& grid, Field& field, int leaf_extent) : grid_(grid), field_(field), leaf_extent_(leaf_extent) {}

    /// Evaluates the box's intervals: the sign of the whole box when they decide it;
    /// otherwise simplifies `tape` into `simplified` and returns nullopt.
    std::optional<double> decide(const Box& box, const BoxTape& tape, Scratch& s, BoxTape& simplified,
                                 SignRenderStats& st) const {
        ++st.boxes;
        evaluate_intervals(box, tape, s);
        const Interval& r = s.intervals[tape.root];
        if (r.positive() || r.negative() || (r.lo == 0 && r.hi == 0 && !r.maybe_nan)) {
            st.decided_points += box.points();
            return r.positive() ? 1.0 : r.negative() ? -1.0 : 0.0;
        }
        simplify(tape, s, simplified);
        return std::nullopt;
    }

    bool is_leaf(const Box& box) const {
        for (int a = 0; a < 3; ++a)
            if (box.hi[a] - box.lo[a] + 1 > leaf_extent_) return false;
        return true;
    }

    /// Halves every axis longer than one node.
    static std::vector<Box> split(const Box& box) {
        std::vector<Box> parts{box};
        for (int a = 0; a < 3; ++a) {
            if (box.hi[a] == box.lo[a]) continue;
            const int mid = (box.lo[a] + box.hi[a]) / 2;
            std::vector<Box> next;
            for (Box b : parts) {
                Box low = b, high = b;
                low.hi[a] = mid;
                high.lo[a] = mid + 1;
                next.push_back(low);
                next.push_back(high);
            }
            parts = std::move(next);
        }
        return parts;
    }

    /// Depth-first: the box with its parent's tape.
    void render(const Box& box, const BoxTape& tape, Scratch& s, std::size_t depth, SignRenderStats& st) {
        if (s.tapes.size() <= depth) s.tapes.push_back(std::make_unique<BoxTape>());
        BoxTape& simplified = *s.tapes[depth];
        if (const std::optional<double> sign = decide(box, tape, s, simplified, st)) {
            fill(box, *sign);
            return;
        }
        if (is_leaf(box)) {
            evaluate_points(box, simplified, s, st);
            return;
        }
        for (const Box& child : split(box)) render(child, simplified, s, depth + 1, st);
    }

    void evaluate_points(const Box& box, const BoxTape& tape, Scratch& s, SignRenderStats& st) {
        const int n = static_cast<int>(box.points());
        s.lanes.resize(tape.ops.size() * kLeafLanes);
        double* v = s.lanes.data();
        for (std::size_t i = 0; i < tape.ops.size(); ++i) {
            const BoxOp& o = tape.ops[i];
            double* out = v + i * kLeafLanes;
            if (o.op == Op::Const) {
                std::fill_n(out, n, o.imm);
                continue;
            }
            if (o.op == Op::Arg) {
                const int axis = static_cast<int>(o.imm);
                int l = 0;
                for (int k = box.lo[2]; k <= box.hi[2]; ++k)
                    for (int j = box.lo[1]; j <= box.hi[1]; ++j)
                        for (int c = box.lo[0]; c <= box.hi[0]; ++c)
                            out[l++] = axis == 0 ? grid_.x_at(c) : axis == 1 ? grid_.y_at(j) : grid_.z_at(k);
                continue;
            }
            const double* A = v + std::size_t(o.in[0]) * kLeafLanes;
            const double* B = v + std::size_t(o.in[1]) * kLeafLanes;
            const double* C = v + std::size_t(o.in[2]) * kLeafLanes;
            [[maybe_unused]] const double imm = o.imm;
            using T = double;
            switch (o.op) {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, expr)          \
    case Op::name:                                                         \
        for (int l = 0; l < n; ++l) {                                      \
            [[maybe_unused]] const T a = A[l];                             \
            [[maybe_unused]] const T b = B[l];                             \
            [[maybe_unused]] const T c = C[l];                             \
            [[maybe_unused]] auto get_a = value_of(a);                     \
            [[maybe_unused]] auto get_b = value_of(b);                     \
            out[l] = (expr);                                               \
        }                                                                  \
        break;
#include "interp/ir/ops.def"
#undef FORTU_OP
            }
        }
        const double* result = v + std::size_t(tape.root) * kLeafLanes;
        int l = 0;
        for (int k = box.lo[2]; k <= box.hi[2]; ++k)
            for (int j = box.lo[1]; j <= box.hi[1]; ++j)
                for (int c = box.lo[0]; c <= box.hi[0]; ++c, ++l)
                    field_.values[grid_.index(c, j, k)] = k_sign(result[l]);
        st.leaf_points += n;
        st.leaf_operations += std::size_t(n) * tape.ops.size();
    }

    void fill(const Box& box, double sign) {
        for (int k = box.lo[2]; k <= box.hi[2]; ++k)
            for (int j = box.lo[1]; j <= box.hi[1]; ++j) {
                double* row = field_.values.data() + grid_.index(box.lo[0], j, k);
                std::fill_n(row, box.hi[0] - box.lo[0] + 1, sign);
            }
    }

private:
    Interval axis_interval(const Box& box, int axis) const {
        auto at = [&](int i) { return axis == 0 ? grid_.x_at(i) : axis == 1 ? grid_.y_at(i) : grid_.z_at(i); };
        const double p = at(box.lo[axis]), q = at(box.hi[axis]);
        return {std::min(p, q), std::max(p, q), false};
    }

    void evaluate_intervals(const Box& box, const BoxTape& tape, Scratch& s) const {
        s.intervals.resize(tape.ops.size());
        for (std::size_t i = 0; i < tape.ops.size(); ++i) {
            const BoxOp& o = tape.ops[i];
            if (o.op == Op::Const) s.intervals[i] = {o.imm, o.imm, false};
            else if (o.op == Op::Arg) s.intervals[i] = axis_interval(box, static_cast<int>(o.imm));
            else {
                const int arity = op_arity(o.op);
                const Interval& a = s.intervals[o.in[0]];
                const Interval& b = arity > 1 ? s.intervals[o.in[1]] : a;
                const Interval& c = arity > 2 ? s.intervals[o.in[2]] : a;
                s.intervals[i] = interval_op(o.op, a, b, c, o.imm);
            }
        }
    }

    /// The box's tape: dead code dropped, won min/max replaced by the winner, and nodes
    /// needed only for their sign collapsed (see the header).
    void simplify(const BoxTape& tape, Scratch& s, BoxTape& out) const {
        const std::size_t n = tape.ops.size();
        s.live.assign(n, 0);
        s.sign_only.assign(n, 1);
        s.replace.assign(n, kKeep);
        s.renumber.resize(n);
        s.live[tape.root] = 1;
        for (std::size_t i = n; i-- > 0;) {
            if (!s.live[i]) continue;
            const BoxOp& o = tape.ops[i];
            if (op_flags(o.op) & kLeaf) continue;
            const bool so = s.sign_only[i];
            const Interval& r = s.intervals[i];
            if (so && r.positive()) { s.replace[i] = kPlusOne; continue; }
            if (so && r.negative()) { s.replace[i] = kMinusOne; continue; }
            const int32_t choice = choose_operand(o, s.intervals, so);
            if (choice != kKeep) {
                s.replace[i] = choice;
                s.live[choice] = 1;
                s.sign_only[choice] &= so;
                continue;
            }
            const int arity = op_arity(o.op);
            for (int k = 0; k < arity; ++k) {
                s.live[o.in[k]] = 1;
                s.sign_only[o.in[k]] &= (so && passes_sign(o.op, k)) ? 1 : 0;
            }
        }
        out.ops.clear();
        for (std::size_t i = 0; i < n; ++i) {
            if (!s.live[i]) continue;
            const int32_t rep = s.replace[i];
            if (rep >= 0) { s.renumber[i] = s.renumber[rep]; continue; }
            BoxOp o = tape.ops[i];
            if (rep == kPlusOne || rep == kMinusOne) o = BoxOp{Op::Const, {0, 0, 0}, rep == kPlusOne ? 1.0 : -1.0};
            else
                for (int k = 0; k < op_arity(o.op); ++k) o.in[k] = s.renumber[o.in[k]];
            s.renumber[i] = static_cast<uint32_t>(out.ops.size());
            out.ops.push_back(o);
        }
        out.root = s.renumber[tape.root];
    }

    /// The operand that op equals (for the value, or for the sign when only the sign is
    /// demanded) over the whole box; kKeep when neither.
    static int32_t choose_operand(const BoxOp& o, const std::vector<Interval>& iv, bool sign_only) {
        const bool is_min = o.op == Op::Min || (o.op == Op::RAnd && o.imm == 1.0);
        const bool is_max = o.op == Op::Max || (o.op == Op::ROr && o.imm == 1.0);
        const bool conj = is_min || o.op == Op::RAnd;
        const bool disj = is_max || o.op == Op::ROr;
        if (o.op == Op::Select) {
            const Interval& c = iv[o.in[0]];
            if (c.positive()) return static_cast<int32_t>(o.in[1]);
            if (c.hi <= 0 && !c.maybe_nan) return static_cast<int32_t>(o.in[2]);
            return kKeep;
        }
        if (!conj && !disj) return kKeep;
        const int32_t ia = static_cast<int32_t>(o.in[0]), ib = static_cast<int32_t>(o.in[1]);
        const Interval& a = iv[ia];
        const Interval& b = iv[ib];
        const bool numbers = !a.maybe_nan && !b.maybe_nan;
        // Exact: one operand is the minimum (maximum) at every point.
        if (is_min && numbers) {
            if (a.hi < b.lo) return ia;
            if (b.hi < a.lo) return ib;
        }
        if (is_max && numbers) {
            if (a.lo > b.hi) return ia;
            if (b.lo > a.hi) return ib;
        }
        if (!sign_only) return kKeep;
        // sign(a & b) = sign(min(a, b)); sign(a | b) = sign(max(a, b)).
        if (conj) {
            if (a.positive()) return ib;
            if (b.positive()) return ia;
            if (a.negative() && !b.maybe_nan) return ia;
            if (b.negative() && !a.maybe_nan) return ib;
        } else {
            if (a.negative()) return ib;
            if (b.negative()) return ia;
            if (a.positive() && !b.maybe_nan) return ia;
            if (b.positive() && !a.maybe_nan) return ib;
        }
        return kKeep;
    }

    const Grid& grid_;
    Field& field_;
    int leaf_extent_;
};

BoxTape tape_of(const Graph& graph, NodeId root) {
    BoxTape tape;
    std::vector<uint32_t> index(graph.size(), 0);
    for (NodeId id : graph.reachable(root)) {
        const Node& n = graph.node(id);
        BoxOp o{n.op, {0, 0, 0}, n.imm};
        for (int k = 0; k < op_arity(n.op); ++k) o.in[k] = index[n.args[k]];
        index[id] = static_cast<uint32_t>(tape.ops.size());
        tape.ops.push_back(o);
    }
    tape.root = index[root];
    return tape;
}

}  // namespace

Field sign_render(const Graph& graph, NodeId root, const Grid& grid, const EvalOptions& options,
                  SignRenderStats* stats) {
    Field field;
    field.grid = grid;
    // Allocating the result (page faults: ~3 ms for 1024²) runs on its own thread while
    // the first levels of the tree only decide boxes; their fills wait for it.
    std::exception_ptr allocation_failure;
    std::jthread allocation([&] {  // joined on any exit, so an exception cannot leave it running
        try {
            field.values.assign(grid.points(), std::nan(""));
        } catch (...) {
            allocation_failure = std::current_exception();
        }
    });
    Renderer renderer(grid, field, grid.slices() > 1 ? 4 : 16);
    const int threads = resolve_threads(options.threads);
    std::vector<Scratch> scratch(threads);
    std::vector<SignRenderStats> worker_stats(threads);
    EvalOptions quiet = options;
    quiet.progress = nullptr;

    // Breadth-first, level by level, until there are enough boxes to share between
    // workers; then each worker takes whole boxes depth-first.
    struct Item {
        Box box;
        std::shared_ptr<const BoxTape> tape;
    };
    struct Decided {
        Box box;
        double sign;
    };
    std::vector<Item> items{{Box{{0, 0, 0}, {grid.cols() - 1, grid.rows() - 1, grid.slices() - 1}},
                             std::make_shared<const BoxTape>(tape_of(graph, root))}};
    std::vector<Decided> decided;
    const std::size_t enough = std::size_t(16) * threads;
    for (bool split_any = true; split_any && items.size() < enough;) {
        std::vector<std::vector<Item>> children(items.size());
        std::vector<std::optional<double>> signs(items.size());
        parallel_for(items.size(), quiet, [&](std::size_t i, int worker) {
            const Item& item = items[i];
            if (renderer.is_leaf(item.box)) {
                children[i].push_back(item);
                return std::size_t{0};
            }
            auto simplified = std::make_shared<BoxTape>();
            signs[i] = renderer.decide(item.box, *item.tape, scratch[worker], *simplified, worker_stats[worker]);
            if (!signs[i])
                for (const Box& child : Renderer::split(item.box)) children[i].push_back({child, simplified});
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
    allocation.join();
    if (allocation_failure) std::rethrow_exception(allocation_failure);
    std::size_t decided_points = 0;
    for (const Decided& d : decided) {
        renderer.fill(d.box, d.sign);
        decided_points += d.box.points();
    }
    if (options.progress && decided_points > 0) options.progress(decided_points);

    parallel_for(items.size(), options, [&](std::size_t i, int worker) {
        renderer.render(items[i].box, *items[i].tape, scratch[worker], 0, worker_stats[worker]);
        return items[i].box.points();
    });
    if (stats) {
        SignRenderStats total;
        for (const SignRenderStats& w : worker_stats) {
            total.boxes += w.boxes;
            total.decided_points += w.decided_points;
            total.leaf_points += w.leaf_points;
            total.leaf_operations += w.leaf_operations;
        }
        *stats = total;
    }
    return field;
}

Field SignEngine::evaluate_grid(const Graph& graph, NodeId root, const Grid& grid, const EvalOptions& options,
                               const NodeValues& reuse) const {
    if (!reuse.empty()) throw std::invalid_argument("the sign renderer takes no known or kept node values");
    return sign_render(graph, root, grid, options);
}

}  // namespace fortu
