// interp/shaded_view.cpp — the front-to-back region walk (see shaded_view.hpp): tiles of the
// picture on the worker threads, each refined depth-first with the sign renderer's
// interval pass and tape simplification, down to leaves sampled in float32.
#include "interp/shaded_view.hpp"

#include "interp/box_simplify.hpp"
#include "interp/compiled_tape_cache.hpp"
#include "interp/float_gradient.hpp"
#include "interp/interval.hpp"
#include "interp/ir/dual.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/parallel.hpp"
#include "interp/tape.hpp"
#include "interp/written_r_operations.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <memory>

namespace fortu {
namespace {

using Vec = std::array<double, 3>;

constexpr double kPi = 3.14159265358979323846;
/// Leaves: at most 8 × 8 pixels × 4 depth samples, sampled without an interval pass of their
/// own (their parent's, over twice the depth, was just done: a leaf's own pass spared too few
/// samples to pay for itself once the samples ran in float32). bear.vm 1024², one thread, CPU
/// seconds on a loaded machine: 4 × 4 × 32 with the interval pass 6.6-7.2, 8 × 8 × 8 (with the
/// pass) 4.1-4.6, 8 × 8 × 4 without 3.9-4.3; deeper leaves were slower (8 × 8 × 32: 7.9):
/// bear's intervals are loose, so they prune little, but a deep leaf samples every column of
/// the band around the silhouette through its whole depth.
constexpr int kLeafPixels = 8;
constexpr int kLeafDepth = 4;
// Regions split in two, so a level removes little of the tape: shortening it every fifth level
// spent 15-20% less time than every level on bear.vm and the pawn at 512² (one thread, median
// of 5; every 2nd or 3rd level in between), with the same pictures. Leaves use their parent's
// tape: shortening it once more cost more than it saved (4.1-4.7 against 4.1-4.4 s).
constexpr std::size_t kSimplifyEvery = 5;
/// The hits' normals run on the tape of their region at this depth (shortened at 0 and 5), not
/// on their leaf's (at 10): a few more instructions, but hits wait for a batch as long as it
/// is current, about six times as many as under one leaf tape, and a batch pays each
/// instruction's fixed costs once (bear.vm 1024² front: about 45 hits a batch on the leaves' tapes).
constexpr std::size_t kNormalTapeDepth = kSimplifyEvery;
/// The interval pass runs on every second level of the split (besides those above): bear.vm
/// 1024² front, one thread: 132,562 passes on every level, 111,201 on every second one, for
/// 0.03% more leaf samples (every third level: 114,869, its halves' passes pruning more).
constexpr std::size_t kIntervalEvery = 2;
/// Regions of at most this many pixels (a leaf's) shrink to those not hit yet (shrink_to_open):
/// with 16 × 16 the scans made Chainik's 1024² view (a cheap tape) 7% more instructions in all
/// than without shrinking, with 8 × 8 0.4%; bear.vm 512² front 9% fewer either way.
constexpr int kShrinkPixels = 8 * 8;
/// Tiles handed to the workers.
constexpr int kTilePixels = 64;

double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// The orthonormal view frame: right, up, and `into` (the view ray's direction).
struct Camera {
    Vec right, up, into;
    double s0 = 0, t0 = 0, d0 = 0;   ///< view coordinates of pixel (0, 0) and depth sample 0
    double step = 0;                  ///< pixel size = depth sample spacing
    int depth_samples = 0;

    Vec point(double col, double row, double k) const {
        const double s = s0 + col * step, t = t0 - row * step, d = d0 + k * step;
        return {s * right[0] + t * up[0] + d * into[0], s * right[1] + t * up[1] + d * into[1],
                s * right[2] + t * up[2] + d * into[2]};
    }
};

Camera make_camera(const std::array<AxisRange, 3>& box, const ViewDirection& view, int width, int height) {
    const double az = view.azimuth * kPi / 180, el = view.elevation * kPi / 180;
    Camera c;
    const Vec eye{std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el)};
    c.right = {std::cos(az), std::sin(az), 0.0};
    c.up = {eye[1] * c.right[2] - eye[2] * c.right[1], eye[2] * c.right[0] - eye[0] * c.right[2],
            eye[0] * c.right[1] - eye[1] * c.right[0]};
    c.into = {-eye[0], -eye[1], -eye[2]};
    // The frame above has Z up; a rotation (a cyclic or quarter turn, right-handed) stands
    // it on the chosen axis.
    const auto stand = [&view](const Vec& v) -> Vec {
        if (view.up == 1) return {v[0], v[2], -v[1]};
        if (view.up == 0) return {v[2], v[0], v[1]};
        return v;
    };
    c.right = stand(c.right), c.up = stand(c.up), c.into = stand(c.into);
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int corner = 0; corner < 8; ++corner) {
        const Vec p{corner & 1 ? box[0].max : box[0].min, corner & 2 ? box[1].max : box[1].min,
                    corner & 4 ? box[2].max : box[2].min};
        const double v[3] = {dot(p, c.right), dot(p, c.up), dot(p, c.into)};
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
    }
    c.step = std::max((hi[0] - lo[0]) / std::max(1, width - 1), (hi[1] - lo[1]) / std::max(1, height - 1));
    if (!(c.step > 0)) c.step = 1;
    c.s0 = (lo[0] + hi[0]) / 2 - c.step * (width - 1) / 2.0;
    c.t0 = (lo[1] + hi[1]) / 2 + c.step * (height - 1) / 2.0;
    c.d0 = lo[2];
    c.depth_samples = std::max(2, static_cast<int>(std::ceil((hi[2] - lo[2]) / c.step)) + 1);
    return c;
}

Interval scaled(double k, double lo, double hi) {
    const double a = k * lo, b = k * hi;
    return {std::min(a, b), std::max(a, b), false};
}

/// A region: pixels [c0, c1] × [r0, r1], depth samples [k0, k1] (inclusive).
struct Region {
    int c0, c1, r0, r1, k0, k1;
};

/// A pixel's hit whose normal is still to compute.
struct Hit {
    std::size_t pixel;
    Vec at;
    int k;              ///< the first sample at or inside the surface
    double kk;          ///< the hit's depth in samples, in (k - 1, k]
    bool bracketed;     ///< kk is interpolated from the sample before (else that one is in another leaf)
};

/// A leaf's pixel not hit yet: samples up to `last` are in front of its hit so far.
struct OpenPixel {
    int col, row, last;
};

/// Lane arrays of one scalar type: slot k's lanes at slots[k].
template <class T>
struct Lanes {
    std::vector<T> values;
    std::vector<T*> slots;
    void prepare(std::size_t slot_count, int lanes) {
        if (values.size() < slot_count * lanes) values.resize(slot_count * lanes);
        slots.resize(slot_count);
        for (std::size_t k = 0; k < slot_count; ++k) slots[k] = values.data() + k * lanes;
    }
};

/// A tape and its number (Scratch::tapes_written; 0: the model's), which tells whether a
/// reallocated copy of it is still current.
struct NumberedTape {
    const Tape* tape;
    std::size_t number;
};

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

struct Scratch {
    std::vector<Hit> hits;
    std::vector<OpenPixel> open;
    Lanes<float> float_lanes;
    std::size_t tapes_written = 0;   ///< numbers the simplified tapes (0: the model's)
    std::size_t leaf_tape_of = ~std::size_t{0};   ///< the number of the tape leaf_tape reallocates
    std::size_t normal_tape_of = ~std::size_t{0}; ///< the number of the tape normal_tape reallocates
    std::vector<Interval> ranges;
    BoxScratch box;
    std::vector<std::unique_ptr<Tape>> tapes;
    Tape leaf_tape;          ///< the leaf's tape in max-live slots (reallocate_slots)
    Tape normal_tape;        ///< the tape the waiting hits' normals run on, in max-live slots
    SlotScratch slot_scratch;
    std::vector<ir::Dual> duals;
    std::vector<ir::Dual*> dual_slots;
    bool normal_float_gradient = false;   ///< normal_tape has float32 derivative rules for every instruction
    FloatGradientScratch float_gradient;
    std::vector<float> points;           ///< the hits' coordinates, values and gradients in float32
    std::vector<Hit> dual_hits;          ///< the hits whose float32 gradient was not finite
    CompiledTapeCache<float> compiled;   ///< the leaf tapes seen more than once, as machine code
    const CompiledTape<float>* leaf_code = nullptr;   ///< leaf_tape's, or null: the lane loops
    bool leaf_code_fresh = false;        ///< leaf_code has not run with these constants yet
    JitScratch<float> jit;
    ShadedViewStats stats;               ///< leaves and compiled_leaves
};

class ViewRenderer {
public:
    ViewRenderer(const Camera& camera, const std::array<AxisRange, 3>& box, SurfaceImage& image, bool compile)
        : cam_(camera), box_(box), image_(image), compile_(compile) {
        for (int a = 0; a < 3; ++a) {
            // Samples this close outside the box still count as in it (rounding of the frame).
            const double pad = 1e-9 * (box[a].max - box[a].min);
            lo_[a] = box[a].min - pad;
            hi_[a] = box[a].max + pad;
        }
    }

    /// `normal` is the tape the hits' normals run on: the one in use below kNormalTapeDepth.
    void render(Region r, const Tape& tape, Scratch& s, std::size_t depth, std::size_t generation, NumberedTape normal) {
        if (!shrink_to_open(r)) return;
        // The region's box in model coordinates (the parallelepiped's bounds), clipped to the domain.
        const double s_lo = cam_.s0 + r.c0 * cam_.step, s_hi = cam_.s0 + r.c1 * cam_.step;
        const double t_lo = cam_.t0 - r.r1 * cam_.step, t_hi = cam_.t0 - r.r0 * cam_.step;
        const double d_lo = cam_.d0 + r.k0 * cam_.step, d_hi = cam_.d0 + r.k1 * cam_.step;
        std::array<Interval, 3> axes;
        for (int a = 0; a < 3; ++a) {
            const Interval x = scaled(cam_.right[a], s_lo, s_hi), y = scaled(cam_.up[a], t_lo, t_hi),
                           z = scaled(cam_.into[a], d_lo, d_hi);
            Interval sum{x.lo + y.lo + z.lo, x.hi + y.hi + z.hi, false};
            sum.lo = std::nextafter(sum.lo, -1e300);
            sum.hi = std::nextafter(sum.hi, 1e300);
            sum.lo = std::max(sum.lo, box_[a].min);
            sum.hi = std::min(sum.hi, box_[a].max);
            if (sum.lo > sum.hi) return;   // outside the domain
            axes[a] = sum;
        }
        if (is_leaf(r)) {
            evaluate_leaf(r, tape, generation, normal, s);
            return;
        }
        // Split the longest of (columns, rows, depth) in leaf units; depth front half first.
        const int w = r.c1 - r.c0 + 1, h = r.r1 - r.r0 + 1, d = r.k1 - r.k0 + 1;
        Region a = r, b = r;
        if (d * kLeafPixels >= w * kLeafDepth && d * kLeafPixels >= h * kLeafDepth && d > 1) {
            a.k1 = (r.k0 + r.k1) / 2;
            b.k0 = a.k1 + 1;
        } else if (w >= h && w > 1) {
            a.c1 = (r.c0 + r.c1) / 2;
            b.c0 = a.c1 + 1;
        } else {
            a.r1 = (r.r0 + r.r1) / 2;
            b.r0 = a.r1 + 1;
        }
        // Every other level only splits: the interval pass there pruned one region in six, and
        // its two halves' passes prune the same space (levels that shorten the tape, and the
        // leaves' parents, always run it).
        if (depth % kIntervalEvery != 0 && depth % kSimplifyEvery != 0 && !is_leaf(a) && !is_leaf(b)) {
            render(a, tape, s, depth + 1, generation, normal);
            render(b, tape, s, depth + 1, generation, normal);
            return;
        }
        evaluate_intervals(tape, axes, s.ranges);
        const Interval& v = s.ranges[tape.root_slot];
        if (v.negative()) return;
        const Tape* next = &tape;
        // Not where the region is all inside: the shortened tape would be the constant 1, whose
        // gradient (the hits' normals, Newton) is zero.
        if (depth % kSimplifyEvery == 0 && !v.positive()) {
            while (s.tapes.size() <= depth) s.tapes.push_back(std::make_unique<Tape>());
            simplify_for_sign(tape, s.ranges, s.box, *s.tapes[depth]);
            next = s.tapes[depth].get();
            generation = ++s.tapes_written;
        }
        if (depth <= kNormalTapeDepth) normal = {next, generation};
        // Two leaves side by side (not one behind the other) run as one: the same samples, one
        // pass over the tape instead of two (bear.vm 256²: 3% fewer instructions).
        if (a.k0 == b.k0 && is_leaf(a) && is_leaf(b)) {
            evaluate_leaf(r, *next, generation, normal, s);
            return;
        }
        render(a, *next, s, depth + 1, generation, normal);
        render(b, *next, s, depth + 1, generation, normal);
    }

private:
    static bool is_leaf(const Region& r) {
        return r.c1 - r.c0 < kLeafPixels && r.r1 - r.r0 < kLeafPixels && r.k1 - r.k0 < kLeafDepth;
    }

    /// Shrinks the region's pixels to the bounding box of those not hit in front of it; false
    /// when every pixel is. Why: along a silhouette or a slope part of a region is hit early,
    /// and the box of the rest, smaller, is more often proved outside (bear.vm 1024² front:
    /// 4% fewer leaf samples, 8% fewer interval passes).
    bool shrink_to_open(Region& r) const {
        // Large regions (near the top of the split) are only checked for an open pixel: their
        // box shrinks little, and scanning all their pixels at every level costs more.
        if ((r.c1 - r.c0 + 1) * (r.r1 - r.r0 + 1) > kShrinkPixels) {
            for (int row = r.r0; row <= r.r1; ++row)
                for (int col = r.c0; col <= r.c1; ++col)
                    if (hit_sample(col, row) > r.k0) return true;
            return false;
        }
        int c0 = r.c1 + 1, c1 = r.c0 - 1, r0 = r.r1 + 1, r1 = r.r0 - 1;
        for (int row = r.r0; row <= r.r1; ++row)
            for (int col = r.c0; col <= r.c1; ++col)
                if (hit_sample(col, row) > r.k0) {
                    c0 = std::min(c0, col), c1 = std::max(c1, col);
                    r0 = std::min(r0, row), r1 = std::max(r1, row);
                }
        if (c0 > c1) return false;
        r.c0 = c0, r.c1 = c1, r.r0 = r0, r.r1 = r1;
        return true;
    }

    /// The depth sample of the pixel's hit, or past the last sample when none yet.
    int hit_sample(int col, int row) const {
        const std::size_t i = std::size_t(row) * image_.width + col;
        return image_.hit[i] == SurfaceImage::Hit::None ? cam_.depth_samples : hit_k_[i];
    }

    bool in_box(const Vec& p) const {
        for (int a = 0; a < 3; ++a)
            if (p[a] < lo_[a] || p[a] > hi_[a]) return false;
        return true;
    }

    /// The leaf's samples run in float32 (SLEEF's vector exp/log, vector_math.hpp) only to
    /// find, per pixel, the first sample at or inside the surface and the values there and
    /// before it; the hit, interpolated between them, is then refined by one Newton step along
    /// the ray in float64 (normals), from the value and gradient the normal needs anyway.
    void evaluate_leaf(const Region& r, const Tape& ssa, std::size_t generation, NumberedTape normal, Scratch& s) {
        // Lanes cost slots × 256 points: SSA slots would cost a deep model gigabytes. Sibling
        // leaves share their parent's tape, so it is reallocated once for all of them.
        if (s.leaf_tape_of != generation || generation == 0) {
            reallocate_slots(ssa, s.leaf_tape, s.slot_scratch);
            s.leaf_tape_of = generation;
            s.leaf_code = compile_ ? s.compiled.find(s.leaf_tape) : nullptr;
            s.leaf_code_fresh = true;
        }
        if (s.normal_tape_of != normal.number || normal.number == 0) {
            finish(s);   // the hits waiting for normals belong to the tape about to be replaced
            reallocate_slots(*normal.tape, s.normal_tape, s.slot_scratch);
            s.normal_float_gradient = float_gradient_supported(s.normal_tape);
            s.normal_tape_of = normal.number;
        }
        const Tape& tape = s.leaf_tape;
        // The pixels not hit in front of the leaf, each with its last sample to look at.
        std::vector<OpenPixel>& open = s.open;
        open.clear();
        for (int row = r.r0; row <= r.r1; ++row)
            for (int col = r.c0; col <= r.c1; ++col) {
                const int last = std::min(r.k1, hit_sample(col, row) - 1);
                if (last >= r.k0) open.push_back({col, row, last});
            }
        std::vector<Hit>& hits = s.hits;
        if (open.empty()) return;
        const int depth = r.k1 - r.k0 + 1;
        const int n = static_cast<int>(open.size()) * depth;
        // Compiled code runs whole chunks; the lanes past n repeat the last sample, so a tail
        // does not go through the lane loops instruction by instruction (their results are
        // not read).
        const int chunk = s.leaf_code ? s.leaf_code->chunk_lanes() : 1;
        const int lanes = (n + chunk - 1) / chunk * chunk;
        Lanes<float>& f = s.float_lanes;
        f.prepare(tape.slot_count, lanes);
        // Lane order: pixel-major, depth within a pixel.
        for (auto [slot, axis] : tape.arguments) {
            float* out = f.slots[slot];
            for (const OpenPixel& o : open) {
                const double across = (cam_.s0 + o.col * cam_.step) * cam_.right[axis] +
                                      (cam_.t0 - o.row * cam_.step) * cam_.up[axis];
                for (int k = r.k0; k <= r.k1; ++k)
                    *out++ = static_cast<float>(across + (cam_.d0 + k * cam_.step) * cam_.into[axis]);
            }
            std::fill(out, f.slots[slot] + lanes, out[-1]);
        }
        for (auto [slot, value] : tape.constants) std::fill_n(f.slots[slot], lanes, static_cast<float>(value));
        ++s.stats.leaves;
        if (s.leaf_code) {
            ++s.stats.compiled_leaves;
            s.leaf_code->run(tape.code.data(), tape.code.size(), f.slots.data(), lanes, s.jit, s.leaf_code_fresh);
            s.leaf_code_fresh = false;
        } else {
            run_lanes<float, 0>(tape.code.data(), tape.code.size(), f.slots.data(), n);
        }
        const float* value = f.slots[tape.root_slot];
        // Per pixel: the first sample ≥ 0 in the box is its hit.
        for (std::size_t i = 0; i < open.size(); ++i) {
            const OpenPixel& o = open[i];
            const float* column = value + i * depth - r.k0;   // column[k]: sample k
            for (int k = r.k0; k <= o.last; ++k) {
                if (!(column[k] >= 0) || !in_box(cam_.point(o.col, o.row, k))) continue;
                place_hit(r, o.col, o.row, k, k > r.k0 ? column[k - 1] : kNoValue, column[k], hits);
                break;
            }
        }
    }

public:
    /// Computes the normals of the hits found so far (they wait so that the leaves sharing a
    /// tape run their normals in one batch: per-instruction costs are paid once).
    void finish(Scratch& s) {
        normals(s.hits, s.normal_tape, s);
        s.hits.clear();
    }

private:

    /// Sample k of the pixel is the first at or inside the surface (value `at`), `before` is
    /// the previous sample's value when it is in this leaf (else kNoValue): the hit goes where
    /// the values cross zero between them (refined by normals), or is a cut by the domain's face.
    void place_hit(const Region& r, int col, int row, int k, double before, double at, std::vector<Hit>& hits) {
        const std::size_t pixel = std::size_t(row) * image_.width + col;
        double kk = k;
        bool cut = true;
        if (k > r.k0) {
            if (std::isfinite(before) && before < 0 && in_box(cam_.point(col, row, k - 1))) {
                kk = k - 1 + (-before) / (at - before);
                cut = false;
            }
        } else if (k > 0 && in_box(cam_.point(col, row, k - 1))) {
            cut = false;   // the previous sample is in another leaf: Newton starts from k (normals)
        }
        hit_k_[pixel] = k;
        image_.hit[pixel] = cut ? SurfaceImage::Hit::Cut : SurfaceImage::Hit::Surface;
        image_.depth[pixel] = static_cast<float>(kk / (cam_.depth_samples - 1));
        if (!cut) hits.push_back({pixel, cam_.point(col, row, kk), k, kk, k > r.k0});
        else image_.normal[pixel] = {0.0f, 0.0f, 1.0f};
    }

    /// The unit normals (outward: against the gradient, which points inside) at the hits, and
    /// their depths refined. float32 forward-mode gradients (float_gradient.hpp) where the tape
    /// has their rules and the result is finite, else ir::Dual in float64.
    void normals(const std::vector<Hit>& hits, const Tape& tape, Scratch& s) {
        if (hits.empty()) return;
        const std::vector<Hit>* exact = &hits;
        if (s.normal_float_gradient) {
            const int n = static_cast<int>(hits.size());
            s.points.resize(std::size_t(7) * n);
            float* p = s.points.data();
            for (int a = 0; a < 3; ++a)
                for (int i = 0; i < n; ++i) p[a * n + i] = static_cast<float>(hits[i].at[a]);
            float* value = p + 3 * n;
            const std::array<float*, 3> grad{p + 4 * n, p + 5 * n, p + 6 * n};
            float_gradients(tape, {p, p + n, p + 2 * n}, n, value, grad, s.float_gradient);
            s.dual_hits.clear();
            for (int i = 0; i < n; ++i) {
                const Vec g{grad[0][i], grad[1][i], grad[2][i]};
                if (std::isfinite(value[i]) && std::isfinite(g[0]) && std::isfinite(g[1]) && std::isfinite(g[2]) &&
                    (g[0] != 0 || g[1] != 0 || g[2] != 0))
                    place_normal(hits[i], value[i], g);
                else
                    s.dual_hits.push_back(hits[i]);
            }
            exact = &s.dual_hits;
            if (exact->empty()) return;
        }
        const int n = static_cast<int>(exact->size());
        s.duals.assign(std::size_t(tape.slot_count) * n, ir::Dual(0.0));
        s.dual_slots.resize(tape.slot_count);
        for (std::size_t k = 0; k < tape.slot_count; ++k) s.dual_slots[k] = s.duals.data() + k * n;
        for (auto [slot, axis] : tape.arguments)
            for (int i = 0; i < n; ++i) s.dual_slots[slot][i] = ir::Dual::variable((*exact)[i].at[axis], axis);
        for (auto [slot, value] : tape.constants)
            for (int i = 0; i < n; ++i) s.dual_slots[slot][i] = ir::Dual(value);
        run_lanes<ir::Dual, 0>(tape.code.data(), tape.code.size(), s.dual_slots.data(), n);
        const ir::Dual* g = s.dual_slots[tape.root_slot];
        for (int i = 0; i < n; ++i) place_normal((*exact)[i], g[i].v, {g[i].d[0], g[i].d[1], g[i].d[2]});
    }

    /// The hit's normal from the model's gradient there, and its depth refined by one Newton
    /// step along the ray from `value`.
    void place_normal(const Hit& h, double value, const Vec& gradient) {
        const Vec grad{-gradient[0], -gradient[1], -gradient[2]};
        const double x = dot(grad, cam_.right), y = dot(grad, cam_.up), z = -dot(grad, cam_.into);
        const double len = std::sqrt(x * x + y * y + z * z);
        // Newton along the ray (df/dk = ∇f · into × step), kept only inside the bracket. A hit
        // at its leaf's first sample starts a whole sample away, where Newton may overshoot
        // a little: its step is clamped to the sample before.
        double kk = h.kk - value / (-dot(grad, cam_.into) * cam_.step);
        if (!h.bracketed && std::isfinite(kk)) kk = std::clamp(kk, h.k - 1.0, double(h.k));
        if (std::isfinite(kk) && kk >= h.k - 1 && kk <= h.k)
            image_.depth[h.pixel] = static_cast<float>(kk / (cam_.depth_samples - 1));
        image_.normal[h.pixel] = len > 0 && std::isfinite(len)
                                     ? std::array<float, 3>{float(x / len), float(y / len), float(z / len)}
                                     : std::array<float, 3>{0.0f, 0.0f, 1.0f};
    }

public:
    std::vector<int> hit_k_;

private:
    const Camera& cam_;
    std::array<AxisRange, 3> box_;
    SurfaceImage& image_;
    bool compile_;   ///< leaf tapes seen more than once run as machine code
    double lo_[3], hi_[3];
};

}  // namespace

std::optional<ViewDirection> parse_view_direction(const std::string& text) {
    if (text == "top") return ViewDirection{0, 90};
    if (text == "front") return ViewDirection{0, 0};
    if (text == "side") return ViewDirection{90, 0};
    if (text == "iso") return ViewDirection{45, 35.264389682754654};
    const std::size_t comma = text.find(',');
    if (comma == std::string::npos) return std::nullopt;
    double v[2];
    const std::string parts[2] = {text.substr(0, comma), text.substr(comma + 1)};
    for (int i = 0; i < 2; ++i) {
        const char* end = parts[i].data() + parts[i].size();
        auto [ptr, ec] = std::from_chars(parts[i].data(), end, v[i]);
        if (ec != std::errc() || ptr != end || parts[i].empty() || !std::isfinite(v[i])) return std::nullopt;
    }
    if (v[1] < -90 || v[1] > 90) return std::nullopt;
    return ViewDirection{v[0], v[1]};
}

SurfaceImage render_shaded_view(const ir::Graph& graph, ir::NodeId root, const std::array<AxisRange, 3>& box,
                                const ViewDirection& view, int width, int height, const EvalOptions& options,
                                bool compile, ShadedViewStats* stats) {
    SurfaceImage image;
    image.width = width;
    image.height = height;
    const std::size_t pixels = std::size_t(width) * height;
    image.hit.assign(pixels, SurfaceImage::Hit::None);
    image.depth.assign(pixels, 1.0f);
    image.normal.assign(pixels, {0.0f, 0.0f, 1.0f});
    const Camera camera = make_camera(box, view, width, height);
    ViewRenderer renderer(camera, box, image, compile);
    renderer.hit_k_.assign(pixels, camera.depth_samples);
    const Tape tape = pruning_tape(graph, root);
    const int tiles_x = (width + kTilePixels - 1) / kTilePixels, tiles_y = (height + kTilePixels - 1) / kTilePixels;
    std::vector<Scratch> scratch(resolve_threads(options.threads));
    EvalOptions quiet = options;
    quiet.progress = nullptr;
    parallel_for(std::size_t(tiles_x) * tiles_y, quiet, [&](std::size_t i, int worker) {
        const int tx = static_cast<int>(i % tiles_x), ty = static_cast<int>(i / tiles_x);
        const Region r{tx * kTilePixels, std::min(width, (tx + 1) * kTilePixels) - 1, ty * kTilePixels,
                       std::min(height, (ty + 1) * kTilePixels) - 1, 0, camera.depth_samples - 1};
        renderer.render(r, tape, scratch[worker], 0, 0, {&tape, 0});
        renderer.finish(scratch[worker]);
        return std::size_t{0};
    });
    if (stats) {
        *stats = {};
        for (const Scratch& worker : scratch) {
            stats->leaves += worker.stats.leaves;
            stats->compiled_leaves += worker.stats.compiled_leaves;
            stats->tapes_compiled += worker.compiled.compiled();
        }
    }
    return image;
}

}  // namespace fortu
