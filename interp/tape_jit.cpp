// interp/tape_jit.cpp — the tape compiler (see tape_jit.hpp): asmjit's assembler writes one
// function per tape, a loop over the tile's chunks for each short block of instructions.
#include "interp/tape_jit.hpp"

#include "interp/constant_divisor.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/tape_jit_math.hpp"
#include "interp/vector_math.hpp"
#include "interp/vector_math_functions.hpp"

#include <asmjit/x86.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <tuple>
#include <type_traits>

namespace fortu {
namespace {

using namespace asmjit;

/// Vectors per chunk: four independent chains of each operation, so that the core has
/// work while one waits for its operand (a fused multiply-add takes 4 cycles, and two issue
/// a cycle).
constexpr int kVectors = 4;
/// Bytes of one vector: ymm (AVX2) or zmm (AVX-512).
template <bool kWide>
constexpr int kVectorBytesOf = kWide ? 64 : 32;
/// Machine code per block (about a dozen instructions). With only the last result in
/// registers, prospero.vm ran 5.6 s with the whole tape as one loop over the chunks, 2.4 s
/// with blocks of 16 KB, 1.0 s with 4 KB, 0.63 s with 1 KB and 0.40 s with 256 bytes
/// (float32, 1024², one thread, CPU time). With three results held, a block's end costs the
/// stores and loads of what they hold: medians of 5, 0.35 s at 256 bytes, 0.33 s at 512,
/// 0.31 s at 1 KB, 0.32 s at 2 KB, 0.47 s at 4 KB (float64: 0.72 s at 1 KB, 0.90 s at 2 KB).
constexpr std::size_t kBlockBytes = 1024;

/// Where an operand's lanes are: the chunk's own slots (`internal`), the caller's slot
/// arrays at the chunk's offset (`external`), or a constant (`constant`, a pool entry).
enum class Place : uint8_t { internal, external, constant };

struct OperandRef {
    Place place = Place::external;
    uint32_t index = 0;   ///< internal: chunk slot; external: tape slot; constant: pool entry
};

/// The process's executable memory; asmjit's runtime is safe to share between threads, the
/// lock covers our add/release pairs with compilation on several threads.
JitRuntime& runtime() {
    static JitRuntime rt;
    return rt;
}
std::mutex& runtime_mutex() {
    static std::mutex m;
    return m;
}

/// In CompiledTape::Compiled::operand_constants: the pool entry holds the constant negated.
constexpr uint8_t kNegated = 0x80;

/// Fixed pool entries, before the operands' constants.
/// kDivideLow and kDivideHigh bound |x| where x / c runs by the corrected reciprocal
/// (constant_divisor.hpp).
enum Fixed : uint32_t { kSignBit, kAbsMask, kZero, kOne, kMinusOne, kDivideLow, kDivideHigh, kFixedCount };

}  // namespace

template <class T>
struct CompiledTape<T>::Site {
    uint32_t index;           ///< the instruction in the code
    OperandRef refs[4];       ///< out, then the three operands
    /// With a twin: code[index + 1] is the sin or cos of the same operand (sincos_twins),
    /// run with it as one sincos, its result written to `twin_out`.
    bool twin = false;
    OperandRef twin_out{};
};

template <class T>
struct CompiledTape<T>::Compiled {
    using Function = void (*)(const void* context);
    Function function = nullptr;
    int chunk_lanes = 0;    ///< four vectors' lanes
    int vector_bytes = 0;   ///< 32 (ymm) or 64 (zmm): also each pool entry's size
    JitWidth width = JitWidth::avx2;
    std::vector<Site> sites;
    uint32_t internal_slots = 0;
    /// Bytes from one chunk's slots to the next's: a cache line more than they take, so the
    /// same slot of consecutive chunks is never a multiple of 4 KiB apart (4K aliasing).
    std::size_t chunk_stride = 0;
    /// Pool entries read from the code's constant operands: (instruction, operand).
    std::vector<std::pair<uint32_t, uint8_t>> operand_constants;
    std::vector<T> fixed_constants;   ///< entries before and after: masks, instructions' own factors
    uint32_t slot_count = 0;
    std::vector<uint32_t> external_slots;   ///< the slots read from and written to the caller's arrays
    std::vector<uint32_t> output_slots;     ///< the tape's outputs
    /// Pool entries of the uniforms' operands: (entry, uniform, negated).
    std::vector<std::tuple<uint32_t, uint32_t, bool>> uniform_entries;
    bool sites_read_uniforms = false;   ///< an operation handed back to the lane kernel reads one
    /// Divisions compiled as multiplications: (instruction, pool entry of the reciprocal, how).
    std::vector<std::tuple<uint32_t, uint32_t, ConstantDivisor<T>>> divisor_entries;

    ~Compiled() {
        if (function) {
            std::lock_guard lock(runtime_mutex());
            runtime().release(function);
        }
    }
};

namespace {

/// What the compiled function reads: its one argument.
template <class T>
struct Context {
    T* const* slots;
    T* scratch;
    const T* constants;
    const Instruction* code;
    std::size_t end;   ///< bytes of whole chunks in the caller's arrays
};

template <class T>
using SiteOf = typename CompiledTape<T>::Site;

/// The lane kernel for one instruction of the chunk (kLanes lanes): the operations not
/// compiled inline.
template <class T, int kLanes>
void run_site(const Context<T>* context, const SiteOf<T>* site, std::size_t external_offset,
              std::size_t internal_offset) {
    T* lanes[4];
    for (int k = 0; k < 4; ++k) {
        // A constant operand's index is a pool entry, no slot: the kernel reads the
        // instruction's own constant instead of its lanes.
        const OperandRef& ref = site->refs[k];
        lanes[k] = ref.place == Place::constant ? nullptr
                   : ref.place == Place::internal
                       ? context->scratch + internal_offset / sizeof(T) + std::size_t(ref.index) * kLanes
                       : context->slots[ref.index] + external_offset / sizeof(T);
    }
    Instruction ins[2] = {context->code[site->index], {}};
    ins[0].out = 0;
    ins[0].in[0] = 1, ins[0].in[1] = 2, ins[0].in[2] = 3;
    if (!site->twin) {
        run_lanes<T, kLanes>(ins, 1, lanes, kLanes);
        return;
    }
    // The pair as the lane kernel runs it in a tape: one sincos (lane_kernel.hpp).
    T* pair_lanes[5] = {lanes[0], lanes[1], lanes[2], lanes[3], nullptr};
    const OperandRef& twin_ref = site->twin_out;
    pair_lanes[4] = twin_ref.place == Place::internal
                        ? context->scratch + internal_offset / sizeof(T) + std::size_t(twin_ref.index) * kLanes
                        : context->slots[twin_ref.index] + external_offset / sizeof(T);
    ins[1] = context->code[site->index + 1];
    ins[1].out = 4;
    ins[1].in[0] = 1, ins[1].in[1] = 2, ins[1].in[2] = 3;
    run_lanes<T, kLanes>(ins, 2, pair_lanes, kLanes);
}

/// The one-vector function for a float32 operation (SLEEF's or fortu's own) that
/// vector_math's kernels of the code's width call (vector_math.def), or nullptr. Only while
/// vector_math runs the kernels of that width: SLEEF's AVX2 and AVX-512 functions need not
/// round the same, and the compiled code must give the lane loops' values.
void* float_vector_function(ir::Op op, bool wide) {
    const vector_math::Isa isa = wide ? vector_math::Isa::avx512 : vector_math::Isa::avx2;
    if (vector_math::active_isa() != isa) return nullptr;
    return vector_math::one_vector_function(isa, op);
}

/// A float32 function compiled inline from vector_math_functions.hpp's template, where the
/// lane loops run that template (vector_math.def's library column), on AVX2 or AVX-512 alike
/// (the template's values do not depend on the width): exp and ln. False: call or hand it on.
template <class E>
bool inline_math(E& e, std::size_t i, ir::Op op, const OperandRef* refs,
                 const std::function<x86::Mem(uint32_t)>& pool_constant) {
    using Code = tape_jit_math::Code;
    namespace f = vector_math::functions;
    if (!vector_math::runs_fortu_function(op) || vector_math::active_isa() == vector_math::Isa::none) return false;
    // For chunks with a lane the narrow path leaves: fortu's own function at the code's width.
    void* function = vector_math::one_vector_function(E::kWide ? vector_math::Isa::avx512 : vector_math::Isa::avx2, op);
    if (!function) return false;
    // The registers each function needs, measured once.
    switch (op) {
    case ir::Op::Exp: {
        static const int registers = E::registers_needed(f::exp_needs_wide<Code>, f::exp_narrow<Code>);
        e.inline_function(i, refs, f::exp_needs_wide<Code>, f::exp_narrow<Code>, registers, function, pool_constant);
        return true;
    }
    case ir::Op::Ln: {
        static const int registers = E::registers_needed(f::log_needs_wide<Code>, f::log_narrow<Code>);
        e.inline_function(i, refs, f::log_needs_wide<Code>, f::log_narrow<Code>, registers, function, pool_constant);
        return true;
    }
    default: return false;
    }
}

/// Whether an instruction is compiled inline (Emitter::emit) rather than handed to the lane kernel.
bool compiles_inline(const Instruction& ins) {
    using ir::Op;
    switch (ins.op) {
    case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Min: case Op::Max: case Op::Neg:
    case Op::Abs: case Op::Square: case Op::Sqrt: case Op::Sign: case Op::RAnd: case Op::ROr:
        return true;
    case Op::Select: return (ins.constant_operands & 1) == 0;   // a constant condition is folded away in practice
    default: return false;
    }
}

/// The code generator, for ymm registers (AVX2) or zmm (kWide: AVX-512, comparisons into
/// k1..k3 and blends under them): registers rbx = slot pointers, r12 = chunk slots, r13 = constants,
/// r14 = the chunk's byte offset in the caller's arrays, r15 = its offset in the chunk slots,
/// rbp = context. The register groups keep the last results made in a block (three in AVX2,
/// seven in AVX-512's 32 registers: bear.vm's 128³ float32 field 99 → 93 ms) (read
/// from there, not from memory: a store and a load on every link of a chain of dependent
/// instructions would make it wait for store forwarding); a result goes to memory only when
/// its group is needed for another while it still has readers, or where the block ends or
/// a call comes, and only if it has readers after that. Constants are memory operands into
/// the pool, one vector per constant.
template <class T, bool kWideCode>
class Emitter {
public:
    static constexpr bool kDouble = std::is_same_v<T, double>;
    static constexpr bool kWide = kWideCode;
    static constexpr int kVectorBytes = kVectorBytesOf<kWide>;
    static constexpr int kLanes = kVectors * kVectorBytes / int(sizeof(T));
    /// Register groups that hold one value of the chunk each (its four vectors): 0..3, 4..7,
    /// 12..15 and, on AVX-512 (32 registers), 16..19 up to 28..31; 8..11 are temporaries.
    static constexpr int kGroups = kWide ? 7 : 3;
    static constexpr int kGroupBase[7] = {0, 4, 12, 16, 20, 24, 28};

    /// `last_read[i]`: the last instruction that reads instruction i's result (i if none).
    /// `cold_paths`: code written after the function's end, reached only from the code before it.
    Emitter(x86::Assembler& a, const std::vector<std::size_t>& last_read, std::vector<std::function<void()>>& cold_paths)
        : a_(a), last_read_(last_read), cold_paths_(cold_paths) {}

    InstId id(InstId single, InstId dbl) const { return kDouble ? dbl : single; }

    /// Stores the held results that instructions after `after` read, and forgets them all
    /// (before a call, at the end of a block).
    void flush(std::size_t after) {
        for (int g = 0; g < kGroups; ++g) spill(g, after);
        for (Held& h : held_) h.used = false;
    }

    x86::Mem chunk_slot(uint32_t index, int v) const {
        return x86::ptr(x86::r12, x86::r15, 0, int32_t(index * kLanes * sizeof(T) + v * kVectorBytes), kVectorBytes);
    }

    /// The group holding `ref`'s value, or -1.
    int group_of(const OperandRef& ref) const {
        for (int g = 0; g < kGroups; ++g)
            if (held_[g].used && held_[g].ref.place == ref.place && held_[g].ref.index == ref.index) return g;
        return -1;
    }
    static x86::Vec vec(int reg) {
        if constexpr (kWide) return x86::zmm(reg);
        else return x86::ymm(reg);
    }
    static x86::Vec group_register(int g, int v) { return vec(kGroupBase[g] + v); }

    /// Mask n (1..3) for a comparison's result: k1..k3, or in AVX2 a temporary (ymm8, ymm9,
    /// ymm11), which the operation must then leave alone.
    static x86::Reg mask(int n) {
        if constexpr (kWide) return x86::k(n);
        else return x86::ymm(n == 1 ? 8 : n == 2 ? 9 : 11);
    }
    /// m = x <predicate> y.
    void compare(const x86::Reg& m, const x86::Vec& x, const Operand_& y, int predicate) {
        a_.emit(id(x86::Inst::kIdVcmpps, x86::Inst::kIdVcmppd), m, x, y, Imm(predicate));
    }
    /// r = m ? if_true : if_false, lane by lane.
    void blend(const x86::Vec& r, const x86::Vec& if_false, const Operand_& if_true, const x86::Reg& m) {
        if constexpr (kWide)
            a_.k(m.as<x86::KReg>()).emit(id(x86::Inst::kIdVblendmps, x86::Inst::kIdVblendmpd), r, if_false, if_true);
        else
            a_.emit(id(x86::Inst::kIdVblendvps, x86::Inst::kIdVblendvpd), r, if_false, if_true, m);
    }
    /// d = a | b of two masks.
    void mask_or(const x86::Reg& d, const x86::Reg& a, const x86::Reg& b) {
        if constexpr (kWide) a_.korw(d.as<x86::KReg>(), a.as<x86::KReg>(), b.as<x86::KReg>());
        else a_.emit(id(x86::Inst::kIdVorps, x86::Inst::kIdVorpd), d, a, b);
    }
    void jump_if_any(const x86::Reg& m, const Label& target) {
        if constexpr (kWide) a_.kortestw(m.as<x86::KReg>(), m.as<x86::KReg>());
        else a_.emit(id(x86::Inst::kIdVtestps, x86::Inst::kIdVtestpd), m, m);
        a_.jnz(target);
    }
    /// A bitwise operation on floats: on zmm its integer form (vandps on zmm needs AVX512DQ,
    /// vpandd only AVX512F; the same bits).
    InstId bitwise(InstId single, InstId dbl, InstId wide_single, InstId wide_double) const {
        if constexpr (kWide) return id(wide_single, wide_double);
        else return id(single, dbl);
    }

    /// Operand k's vector v as an operand: a register (a held result) or memory.
    Operand_ source(const OperandRef& ref, int k, int v) const {
        if (const int g = group_of(ref); g >= 0 && ref.place != Place::constant) return group_register(g, v);
        return memory(ref, k, v);
    }

    /// Operand k's vector v where it is in memory (the result's, for k = 0): what no register
    /// holds, and the same whenever the code using it is written (cold paths are written last).
    x86::Mem memory(const OperandRef& ref, int k, int v) const {
        if (ref.place == Place::constant) return pool_entry(ref.index);
        if (ref.place == Place::internal) return chunk_slot(ref.index, v);
        return x86::ptr(pointer_reg(k), x86::r14, 0, v * kVectorBytes, kVectorBytes);
    }

    static x86::Gp pointer_reg(int k) {
        static const x86::Gp regs[4] = {x86::rsi, x86::rax, x86::rcx, x86::rdx};
        return regs[k];
    }

    /// Loads what an instruction's operands need before its vectors: external arrays'
    /// pointers (the result's too: a result in the caller's arrays is stored at once).
    void prepare(const OperandRef* refs, int count) {
        for (int k = 0; k < count; ++k) {
            const OperandRef& ref = refs[k];
            if (ref.place == Place::external && (k == 0 || group_of(ref) < 0))
                a_.mov(pointer_reg(k), x86::ptr(x86::rbx, int32_t(ref.index * sizeof(T*))));
        }
    }

    /// A pool entry: a constant in every lane of a vector (read as a memory operand, so that
    /// constants take no registers).
    static x86::Mem pool_entry(uint32_t entry) { return x86::ptr(x86::r13, int32_t(entry * kVectorBytes), kVectorBytes); }

    /// Operand k's vector v in a register: a constant's, the last result's, or loaded into
    /// `scratch` (never the result register, which may hold another operand).
    x86::Vec in_register(const OperandRef& ref, int k, int v, const x86::Vec& scratch) {
        const Operand_ src = source(ref, k, v);
        if (src.isReg()) return src.as<x86::Vec>();
        a_.vmovups(scratch, src.as<x86::Mem>());
        return scratch;
    }

    void store(const OperandRef& out, int v, const x86::Vec& value) { a_.vmovups(memory(out, 0, v), value); }

    /// Instruction i inline (compiles_inline), its result left in a register group.
    /// `numbers`: bit k set if operand k is never NaN. `factors`: the first of the
    /// instruction's own pool entries (an R-operation's 2α and 1 + α, a divisor's reciprocal);
    /// `divisor`: how a division by a constant runs (constant_divisor.hpp).
    void emit(std::size_t i, const Instruction& ins, const OperandRef* refs, uint32_t factors, uint8_t numbers,
              const ConstantDivisor<T>& divisor) {
        using ir::Op;
        const OperandRef& out = refs[0];
        const OperandRef* in = refs + 1;
        for (int k = 0; k < ir::op_arity(ins.op); ++k)
            if (const int g = group_of(in[k]); g >= 0) held_[g].stamp = ++clock_;
        const int group = result_group(i);
        const bool store_out = out.place == Place::external;
        const auto each_vector = [&](auto body) {
            for (int v = 0; v < kVectors; ++v) body(v, group_register(group, v));
            if (store_out)
                for (int v = 0; v < kVectors; ++v) store(out, v, group_register(group, v));
        };
        const x86::Vec t8 = vec(8), t10 = vec(10), t11 = vec(11);
        // Operand k in a register, in t10 if it is not held; a constant is loaded once for the
        // four vectors (the instruction must leave t10 alone).
        const auto in_t10 = [&](int k, int v) {
            if (in[k].place == Place::constant && v > 0) return t10;
            return in_register(in[k], k + 1, v, t10);
        };
        const auto first = [&](int v) { return in_t10(0, v); };
        const InstId add = id(x86::Inst::kIdVaddps, x86::Inst::kIdVaddpd);
        const InstId sub = id(x86::Inst::kIdVsubps, x86::Inst::kIdVsubpd);
        const InstId mul = id(x86::Inst::kIdVmulps, x86::Inst::kIdVmulpd);
        const InstId div = id(x86::Inst::kIdVdivps, x86::Inst::kIdVdivpd);
        const InstId sqrt = id(x86::Inst::kIdVsqrtps, x86::Inst::kIdVsqrtpd);
        const auto binary = [&](InstId op) {
            prepare(refs, 3);
            each_vector([&](int v, const x86::Vec& r) { a_.emit(op, r, first(v), source(in[1], 2, v)); });
        };
        // a + b and a × b are b + a and b × a (which NaN of two comes out aside): the operand
        // held in registers goes first, the other is read from memory by the instruction.
        const auto commutative = [&](InstId op) {
            prepare(refs, 3);
            const bool swap = group_of(in[0]) < 0 && (group_of(in[1]) >= 0 ||
                                                      (in[1].place == Place::constant && in[0].place != Place::constant));
            const int x = swap ? 1 : 0, y = 1 - x;
            each_vector([&](int v, const x86::Vec& r) { a_.emit(op, r, in_t10(x, v), source(in[y], y + 1, v)); });
        };
        const auto with_mask = [&](InstId op, uint32_t mask) {  // r = mask op a
            prepare(refs, 2);
            each_vector([&](int v, const x86::Vec& r) {
                a_.emit(op, r, in_register(in[0], 1, v, t10), pool_entry(mask));
            });
        };
        // k_min / k_max: (a < b || a != a) ? a : b; vminps gives (a < b) ? a : b, the same
        // unless a is NaN.
        const auto min_max = [&](InstId op) {
            prepare(refs, 3);
            each_vector([&](int v, const x86::Vec& r) {
                const x86::Vec x = first(v);
                if (numbers & 1u) {
                    a_.emit(op, r, x, source(in[1], 2, v));
                    return;
                }
                a_.emit(op, t8, x, source(in[1], 2, v));
                compare(mask(2), x, x, 3);   // unordered: x is NaN
                blend(r, t8, x, mask(2));
            });
        };
        const InstId min = id(x86::Inst::kIdVminps, x86::Inst::kIdVminpd);
        const InstId max = id(x86::Inst::kIdVmaxps, x86::Inst::kIdVmaxpd);
        switch (ins.op) {
        case Op::Add: commutative(add); break;
        case Op::Sub: binary(sub); break;
        case Op::Mul: commutative(mul); break;
        case Op::Div:
            if (divisor.kind == DivisorKind::exact_reciprocal) {
                prepare(refs, 3);
                each_vector([&](int v, const x86::Vec& r) { a_.emit(mul, r, first(v), pool_entry(factors)); });
            } else if (divisor.kind == DivisorKind::corrected_reciprocal) {
                divide_by_corrected_reciprocal(refs, group, factors, store_out);
            } else {
                binary(div);
            }
            break;
        case Op::Min: min_max(min); break;
        case Op::Max: min_max(max); break;
        case Op::Neg:
            with_mask(bitwise(x86::Inst::kIdVxorps, x86::Inst::kIdVxorpd, x86::Inst::kIdVpxord, x86::Inst::kIdVpxorq), kSignBit);
            break;
        case Op::Abs:
            with_mask(bitwise(x86::Inst::kIdVandps, x86::Inst::kIdVandpd, x86::Inst::kIdVpandd, x86::Inst::kIdVpandq), kAbsMask);
            break;
        case Op::Square:
            prepare(refs, 2);
            each_vector([&](int v, const x86::Vec& r) {
                const x86::Vec x = in_register(in[0], 1, v, t10);
                a_.emit(mul, r, x, x);
            });
            break;
        case Op::Sqrt:
            prepare(refs, 2);
            each_vector([&](int v, const x86::Vec& r) { a_.emit(sqrt, r, source(in[0], 1, v)); });
            break;
        case Op::Sign:   // a > 0 ? 1 : a < 0 ? -1 : a
            prepare(refs, 2);
            each_vector([&](int v, const x86::Vec& r) {
                const x86::Vec x = in_register(in[0], 1, v, t10);
                compare(mask(1), x, pool_entry(kZero), 0x1E);   // x > 0, ordered
                compare(mask(2), x, pool_entry(kZero), 0x11);   // x < 0, ordered
                blend(t11, x, pool_entry(kOne), mask(1));
                blend(r, t11, pool_entry(kMinusOne), mask(2));
            });
            break;
        case Op::Select:   // c > 0 ? a : (c != c ? c : b), operands c, a, b
            prepare(refs, 4);
            each_vector([&](int v, const x86::Vec& r) {
                const x86::Vec c = in_register(in[0], 1, v, t10);
                const x86::Vec a = in_register(in[1], 2, v, t11);
                const x86::Vec b = in_register(in[2], 3, v, vec(9));
                compare(mask(1), c, pool_entry(kZero), 0x1E);
                if (numbers & 1u) {
                    blend(r, b, a, mask(1));
                    return;
                }
                blend(t11, b, a, mask(1));
                compare(mask(1), c, c, 3);
                blend(r, t11, c, mask(1));
            });
            break;
        case Op::RAnd:
        case Op::ROr: {
            const bool conjunction = ins.op == Op::RAnd;
            const double alpha = ins.imm;
            if (alpha == 1.0) {
                min_max(conjunction ? min : max);
                break;
            }
            // R0: (a + b) ∓ sqrt(a*a + b*b); Rα: ((a + b) ∓ sqrt((a*a + b*b) - 2α*(a*b))) / (1 + α)
            prepare(refs, 3);
            each_vector([&](int v, const x86::Vec& r) {
                const x86::Vec a = in_register(in[0], 1, v, t10);
                const x86::Vec b = in_register(in[1], 2, v, t11);
                const x86::Vec t9 = vec(9);
                a_.emit(mul, t8, a, a);
                a_.emit(mul, t9, b, b);
                a_.emit(add, t8, t8, t9);
                if (alpha != 0.0) {
                    a_.emit(mul, t9, a, b);
                    a_.emit(mul, t9, t9, pool_entry(factors));   // T(2α) * (a * b); finite T(2α): commutes exactly
                    a_.emit(sub, t8, t8, t9);
                }
                a_.emit(sqrt, t8, t8);
                a_.emit(add, r, a, b);
                a_.emit(conjunction ? sub : add, r, r, t8);
                if (alpha != 0.0) a_.emit(div, r, r, pool_entry(factors + 1));   // T(1 + α)
            });
            break;
        }
        default: break;
        }
        // The slot's earlier value, if held, is overwritten: no later instruction reads it.
        for (int g = 0; g < kGroups; ++g)
            if (g != group && group_of(out) == g) held_[g].used = false;
        held_[group] = Held{true, !store_out, out, i, ++clock_};
    }

    /// x / c as RN(q0 + (x − q0·c)·y), q0 = RN(x·y), y = RN(1/c) (constant_divisor.hpp), for
    /// the chunk's four vectors, unless a lane's |x| is out of the range where that is exact:
    /// then, out of line, by division.
    void divide_by_corrected_reciprocal(const OperandRef* refs, int group, uint32_t reciprocal, bool store_out) {
        const OperandRef* in = refs + 1;
        const x86::Vec t8 = vec(8), t9 = vec(9), t10 = vec(10), t11 = vec(11);
        const x86::Mem divisor = pool_entry(in[1].index);
        prepare(refs, 3);
        const Label cold = a_.newLabel(), done = a_.newLabel();
        // Lanes out of range, in mask(1): each vector's in mask(2) (above) and mask(3) (below;
        // in AVX2 that is t11, which held |x|).
        for (int v = 0; v < kVectors; ++v) {
            const x86::Vec x = in_register(in[0], 1, v, t10);
            a_.emit(bitwise(x86::Inst::kIdVandps, x86::Inst::kIdVandpd, x86::Inst::kIdVpandd, x86::Inst::kIdVpandq), t11, x,
                    pool_entry(kAbsMask));
            compare(mask(2), t11, pool_entry(kDivideHigh), 0x1E);   // >, ordered
            compare(mask(3), t11, pool_entry(kDivideLow), 0x11);    // <, ordered
            mask_or(v == 0 ? mask(1) : mask(3), mask(3), mask(2));
            if (v > 0) mask_or(mask(1), mask(1), mask(3));
        }
        jump_if_any(mask(1), cold);
        std::array<Operand_, kVectors> sources;
        for (int v = 0; v < kVectors; ++v) {
            sources[v] = source(in[0], 1, v);
            const x86::Vec x = in_register(in[0], 1, v, t10);
            const x86::Vec r = group_register(group, v);
            const x86::Vec q = x.id() == r.id() ? t8 : r;
            a_.emit(id(x86::Inst::kIdVmulps, x86::Inst::kIdVmulpd), q, x, pool_entry(reciprocal));
            a_.emit(id(x86::Inst::kIdVmovaps, x86::Inst::kIdVmovapd), t9, q);
            a_.emit(id(x86::Inst::kIdVfmsub132ps, x86::Inst::kIdVfmsub132pd), t9, x, divisor);   // q0·c − x
            a_.emit(id(x86::Inst::kIdVfnmadd231ps, x86::Inst::kIdVfnmadd231pd), q, t9, pool_entry(reciprocal));
            if (q.id() != r.id()) a_.emit(id(x86::Inst::kIdVmovaps, x86::Inst::kIdVmovapd), r, q);
        }
        a_.bind(done);
        if (store_out)
            for (int v = 0; v < kVectors; ++v) store(refs[0], v, group_register(group, v));
        // Out of line, the registers are as at the jump: held operands are still there.
        cold_paths_.push_back([this, cold, done, sources, divisor, group] {
            a_.bind(cold);
            for (int v = 0; v < kVectors; ++v) {
                x86::Vec x = vec(10);
                if (sources[v].isReg()) x = sources[v].template as<x86::Vec>();
                else a_.vmovups(x, sources[v].template as<x86::Mem>());
                a_.emit(id(x86::Inst::kIdVdivps, x86::Inst::kIdVdivpd), group_register(group, v), x, divisor);
            }
            a_.jmp(done);
        });
    }

    /// A float32 operation a vector function computes: one call per vector, operands in ymm0
    /// (and ymm1), the result in ymm0, stored at once (the call may change every other
    /// register). Reads and writes memory only, so a cold path written later may use it too.
    void call_vector_function(const OperandRef* refs, int arity, void* function) {
        const OperandRef* in = refs + 1;
        for (int v = 0; v < kVectors; ++v) {
            for (int k = arity - 1; k >= 0; --k) {
                if (in[k].place == Place::external)
                    a_.mov(pointer_reg(k + 1), x86::ptr(x86::rbx, int32_t(in[k].index * sizeof(T*))));
                a_.vmovups(vec(k), memory(in[k], k + 1, v));
            }
            a_.mov(x86::rax, Imm(reinterpret_cast<uint64_t>(function)));
            a_.call(x86::rax);
            if (refs[0].place == Place::external)
                a_.mov(pointer_reg(0), x86::ptr(x86::rbx, int32_t(refs[0].index * sizeof(T*))));
            store(refs[0], v, vec(0));
        }
    }

    /// A float32 function of vector_math_functions.hpp written inline (tape_jit_math.hpp):
    /// `narrow` for the chunk's four vectors, unless `needs_wide` marks a lane of one of them;
    /// then, out of line (`cold`, written after the function's end), call_vector_function
    /// calls `function` per vector and its results are reloaded. The written code gets the
    /// temporaries and the register groups for the `registers` it needs (registers_needed:
    /// exp one group, ln two); the operand is read
    /// where it is held, and the other held values stay in their registers (the cold path
    /// stores and reloads them around its calls).
    template <class NeedsWide, class Narrow>
    void inline_function(std::size_t i, const OperandRef* refs, NeedsWide needs_wide, Narrow narrow, int registers_used,
                         void* function, const std::function<x86::Mem(uint32_t)>& pool_constant) {
        namespace math = tape_jit_math;
        const OperandRef out = refs[0], in = refs[1];
        prepare(refs, 2);
        int input_group = in.place == Place::constant ? -1 : group_of(in);
        if (input_group >= 0) held_[input_group].stamp = ++clock_;
        const int group = result_group(i);
        for (int g = 0; g < kGroups; ++g)   // values nothing reads again: forgotten
            if (g != group && g != input_group && held_[g].used && last_read_[held_[g].writer] <= i) held_[g].used = false;
        // The groups the written code needs besides the four temporaries: free ones first, then
        // the least recently used, stored if still read; the operand's last (read from memory).
        const int needed = (registers_used - 4 + kVectors - 1) / kVectors;
        std::vector<int> registers{8, 9, 10, 11};
        bool scratch[kGroups] = {};
        for (int taken = 0; taken < needed; ++taken) {
            int pick = -1;
            for (int g = 0; g < kGroups; ++g) {
                if (g == group || scratch[g]) continue;
                const auto rank = [&](int k) { return std::tuple(k == input_group, held_[k].used, held_[k].stamp); };
                if (pick < 0 || rank(g) < rank(pick)) pick = g;
            }
            spill(pick, pick == input_group ? i - 1 : i);
            held_[pick].used = false;
            if (pick == input_group) input_group = -1;
            scratch[pick] = true;
            for (int v = 0; v < kVectors; ++v) registers.push_back(kGroupBase[pick] + v);
        }
        const auto operand = [&](math::Writer& writer, int v) {
            return input_group >= 0 ? writer.borrow(kGroupBase[input_group] + v) : writer.load(memory(in, 1, v));
        };
        const Label cold = a_.newLabel(), done = a_.newLabel();
        {
            math::Writer writer(a_, registers, pool_constant, kWide);
            math::Value any;
            for (int v = 0; v < kVectors; ++v) {
                const math::Value lanes = needs_wide(operand(writer, v));
                any = v == 0 ? lanes : math::Code::or_mask(any, lanes);
            }
            writer.jump_if_any(any, cold);
        }
        {
            math::Writer writer(a_, registers, pool_constant, kWide);
            for (int v = 0; v < kVectors; ++v) a_.vmovaps(group_register(group, v), narrow(operand(writer, v)).vec());
        }
        a_.bind(done);
        // The call reads the operand from memory and may change every register: what is held
        // and not stored is stored first, and the other held values reloaded after.
        struct GroupValue {
            int group;
            OperandRef ref;
        };
        std::vector<GroupValue> stored, kept;
        for (int g = 0; g < kGroups; ++g) {
            if (!held_[g].used || scratch[g]) continue;
            if (held_[g].dirty && (g != group || g == input_group)) stored.push_back({g, held_[g].ref});
            if (g != group) kept.push_back({g, held_[g].ref});
        }
        cold_paths_.push_back([this, cold, done, operands = std::array{out, in}, group, function, stored, kept] {
            a_.bind(cold);
            for (const GroupValue& held : stored)
                for (int v = 0; v < kVectors; ++v) a_.vmovups(chunk_slot(held.ref.index, v), group_register(held.group, v));
            call_vector_function(operands.data(), 1, function);
            for (int v = 0; v < kVectors; ++v) a_.vmovups(group_register(group, v), memory(operands[0], 0, v));
            for (const GroupValue& held : kept) {
                const bool external = held.ref.place == Place::external;   // its pointer in r11 (the call changed rsi..rdx)
                if (external) a_.mov(x86::r11, x86::ptr(x86::rbx, int32_t(held.ref.index * sizeof(T*))));
                for (int v = 0; v < kVectors; ++v)
                    a_.vmovups(group_register(held.group, v), external ? x86::ptr(x86::r11, x86::r14, 0, v * kVectorBytes, kVectorBytes)
                                                                      : chunk_slot(held.ref.index, v));
            }
            a_.jmp(done);
        });
        if (out.place == Place::external)
            for (int v = 0; v < kVectors; ++v) store(out, v, group_register(group, v));
        for (int g = 0; g < kGroups; ++g)
            if (g != group && group_of(out) == g) held_[g].used = false;
        held_[group] = Held{true, out.place != Place::external, out, i, ++clock_};
    }

    /// The most registers an inline function's check or narrow path (of one vector, held in a
    /// register of its own) holds at once, found by writing them into code that is thrown away.
    template <class NeedsWide, class Narrow>
    static int registers_needed(NeedsWide needs_wide, Narrow narrow) {
        namespace math = tape_jit_math;
        int most = 0;
        const auto peak = [&](auto function) {
            CodeHolder code;
            code.init(runtime().environment());
            x86::Assembler a(&code);
            std::vector<int> all(16);
            for (int r = 0; r < 16; ++r) all[r] = r;
            math::Writer writer(a, all, [](uint32_t) { return x86::ptr(x86::r13, 0, kVectorBytes); }, kWide);
            function(writer.load(x86::ptr(x86::rsi, 0, kVectorBytes)));
            most = std::max(most, writer.peak());
        };
        peak(needs_wide);
        peak(narrow);
        return most;
    }

    /// An instruction left to the lane kernel: a call with the registers it may clobber
    /// reloaded by the next instructions (they reload everything they use).
    void call_site(const SiteOf<T>* site) {
        a_.vzeroupper();
        a_.mov(x86::rdi, x86::rbp);
        a_.mov(x86::rsi, Imm(reinterpret_cast<uint64_t>(site)));
        a_.mov(x86::rdx, x86::r14);
        a_.mov(x86::rcx, x86::r15);
        a_.mov(x86::rax, Imm(reinterpret_cast<uint64_t>(&run_site<T, kLanes>)));
        a_.call(x86::rax);
    }

private:
    struct Held {
        bool used = false;
        bool dirty = false;     ///< not stored yet
        OperandRef ref;
        std::size_t writer = 0;  ///< the instruction that made it
        std::size_t stamp = 0;   ///< when it was last made or read
    };

    /// Stores group g's result if an instruction after `after` reads it and it is not stored.
    void spill(int g, std::size_t after) {
        Held& h = held_[g];
        if (!h.used || !h.dirty || last_read_[h.writer] <= after) return;
        for (int v = 0; v < kVectors; ++v) a_.vmovups(chunk_slot(h.ref.index, v), group_register(g, v));
        h.dirty = false;
    }

    /// The group for instruction i's result: one whose value nothing after i reads (an operand
    /// dying here: each vector is read before it is overwritten), else a free one, else the
    /// least recently used, stored first if still needed.
    int result_group(std::size_t i) {
        for (int g = 0; g < kGroups; ++g)
            if (held_[g].used && last_read_[held_[g].writer] <= i) return g;
        for (int g = 0; g < kGroups; ++g)
            if (!held_[g].used) return g;
        int oldest = 0;
        for (int g = 1; g < kGroups; ++g)
            if (held_[g].stamp < held_[oldest].stamp) oldest = g;
        spill(oldest, i);
        return oldest;
    }

    x86::Assembler& a_;
    const std::vector<std::size_t>& last_read_;
    std::vector<std::function<void()>>& cold_paths_;
    Held held_[kGroups];
    std::size_t clock_ = 0;
};

}  // namespace

bool tape_jit_available() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx");
    return available;
#else
    return false;
#endif
}

bool tape_jit_avx512_available() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool available = tape_jit_available() && __builtin_cpu_supports("avx512f");
    return available;
#else
    return false;
#endif
}

namespace {

std::atomic<JitWidth>& chosen_width() {
    static std::atomic<JitWidth> width{tape_jit_avx512_available() ? JitWidth::avx512 : JitWidth::avx2};
    return width;
}

}  // namespace

JitWidth tape_jit_width() { return chosen_width().load(std::memory_order_relaxed); }

void use_tape_jit_width(JitWidth width) {
    chosen_width().store(width == JitWidth::avx512 && !tape_jit_avx512_available() ? JitWidth::avx2 : width,
                         std::memory_order_relaxed);
}


namespace {

/// The tape's machine code at one width (CompiledTape::compile), or nullptr.
template <class T, bool kWide>
std::unique_ptr<typename CompiledTape<T>::Compiled> compiled_code(const Tape& tape, std::span<const uint8_t> numbers) {
    using Compiled = typename CompiledTape<T>::Compiled;
    using Site = typename CompiledTape<T>::Site;
    using Emit = Emitter<T, kWide>;
    constexpr int kChunkLanes = Emit::kLanes;
    auto compiled = std::make_unique<Compiled>();
    Compiled& c = *compiled;
    c.slot_count = tape.slot_count;
    c.chunk_lanes = kChunkLanes;
    c.vector_bytes = Emit::kVectorBytes;
    c.width = kWide ? JitWidth::avx512 : JitWidth::avx2;

    // Which slots the caller sees: arguments, inputs, constants, outputs and the zero slot.
    std::vector<char> external(tape.slot_count, 0);
    external[tape.zero_slot] = 1;
    for (auto [slot, axis] : tape.arguments) external[slot] = 1;
    for (auto [slot, which] : tape.inputs) external[slot] = 1;
    for (auto [slot, value] : tape.constants) external[slot] = 1;
    for (uint32_t slot : tape.outputs) external[slot] = 1;
    std::vector<uint32_t> chunk_slot(tape.slot_count, 0);
    for (uint32_t s = 0; s < tape.slot_count; ++s) {
        if (!external[s]) chunk_slot[s] = c.internal_slots++;
        else c.external_slots.push_back(s);
    }
    c.output_slots = tape.outputs;
    // A tape this wide or long stays with the lane kernel: its chunk slots would take over
    // 32 MiB a worker (1 MiB a chunk), its code over about 100 MB.
    c.chunk_stride = std::size_t(c.internal_slots) * kChunkLanes * sizeof(T) + 64;
    if (c.chunk_stride > (std::size_t{1} << 20) || tape.code.size() > (std::size_t{1} << 20)) return nullptr;

    // The pool: fixed entries, then one per constant operand, then the instructions' own factors.
    c.fixed_constants.resize(kFixedCount);
    const auto bits = [](std::uint64_t pattern) {
        T value;
        if constexpr (sizeof(T) == 8) std::memcpy(&value, &pattern, 8);
        else {
            const auto narrow = static_cast<std::uint32_t>(pattern);
            std::memcpy(&value, &narrow, 4);
        }
        return value;
    };
    c.fixed_constants[kSignBit] = bits(sizeof(T) == 8 ? 0x8000000000000000ull : 0x80000000ull);
    c.fixed_constants[kAbsMask] = bits(sizeof(T) == 8 ? 0x7fffffffffffffffull : 0x7fffffffull);
    c.fixed_constants[kZero] = T(0), c.fixed_constants[kOne] = T(1), c.fixed_constants[kMinusOne] = T(-1);
    c.fixed_constants[kDivideLow] = std::ldexp(T(1), -CorrectedRange<T>::kExponent);
    c.fixed_constants[kDivideHigh] = std::ldexp(T(1), CorrectedRange<T>::kExponent);

    std::vector<std::array<OperandRef, 4>> refs(tape.code.size());
    std::vector<uint32_t> factors(tape.code.size(), 0);
    std::vector<ConstantDivisor<T>> divisors(tape.code.size());
    std::vector<uint8_t> uniform_operands(tape.code.size(), 0);   // bit k: operand k reads a uniform
    for (const UniformUse& use : tape.uniform_uses) uniform_operands[use.instruction] |= uint8_t(1u << use.operand);
    std::vector<T> factor_values;
    for (std::size_t i = 0; i < tape.code.size(); ++i) {
        const Instruction& ins = tape.code[i];
        const auto place_of = [&](uint32_t slot) {
            return external[slot] ? OperandRef{Place::external, slot} : OperandRef{Place::internal, chunk_slot[slot]};
        };
        refs[i][0] = place_of(ins.out);
        for (int k = 0; k < ir::kMaxArity; ++k) {
            if (ins.constant_operands & (1u << k)) {
                refs[i][k + 1] = {Place::constant, uint32_t(kFixedCount + c.operand_constants.size())};
                // a − c is compiled as a + (−c), exactly the same (IEEE subtraction is the
                // addition of the negation), so that a can be read from memory by the addition.
                const bool negated = ins.op == ir::Op::Sub && k == 1;
                c.operand_constants.emplace_back(uint32_t(i), uint8_t(k | (negated ? kNegated : 0)));
            } else {
                refs[i][k + 1] = place_of(ins.in[k]);
            }
        }
        if ((ins.op == ir::Op::RAnd || ins.op == ir::Op::ROr) && ins.imm != 0.0 && ins.imm != 1.0) {
            factors[i] = uint32_t(factor_values.size());
            factor_values.push_back(T(2.0 * ins.imm));
            factor_values.push_back(T(1.0 + ins.imm));
        }
        if (ins.op == ir::Op::Div && (ins.constant_operands & 2u) && !(uniform_operands[i] & 2u)) {
            divisors[i] = plan_constant_divisor(T(ins.constant[1]));
            if (divisors[i].kind != DivisorKind::divide) {
                factors[i] = uint32_t(factor_values.size());
                factor_values.push_back(divisors[i].reciprocal);
            }
        }
    }
    for (const UniformUse& use : tape.uniform_uses) {
        const uint32_t entry = refs[use.instruction][use.operand + 1].index;
        const bool negated = c.operand_constants[entry - kFixedCount].second & kNegated;
        c.uniform_entries.emplace_back(entry, use.uniform, negated);
    }
    const uint32_t factor_base = uint32_t(kFixedCount + c.operand_constants.size());
    for (uint32_t& f : factors) f += factor_base;
    for (std::size_t i = 0; i < divisors.size(); ++i)
        if (divisors[i].kind != DivisorKind::divide) c.divisor_entries.emplace_back(uint32_t(i), factors[i], divisors[i]);
    c.fixed_constants.insert(c.fixed_constants.end(), factor_values.begin(), factor_values.end());

    CodeHolder code;
    code.init(runtime().environment());
    x86::Assembler a(&code);
    // Callee-saved registers (System V): six pushes and 8 bytes keep calls 16-byte aligned.
    const x86::Gp saved[] = {x86::rbp, x86::rbx, x86::r12, x86::r13, x86::r14, x86::r15};
    for (const x86::Gp& r : saved) a.push(r);
    a.sub(x86::rsp, 8);
    a.mov(x86::rbp, x86::rdi);
    a.mov(x86::rbx, x86::ptr(x86::rdi, offsetof(Context<T>, slots)));
    a.mov(x86::r12, x86::ptr(x86::rdi, offsetof(Context<T>, scratch)));
    a.mov(x86::r13, x86::ptr(x86::rdi, offsetof(Context<T>, constants)));
    // Blocks of instructions, each run over every chunk before the next: a block's code stays
    // in the instruction cache, and the values it makes and uses in the data cache.
    const auto begin_block = [&](Label& next) {
        a.xor_(x86::r14d, x86::r14d);
        a.xor_(x86::r15d, x86::r15d);
        next = a.newLabel();
        a.bind(next);
    };
    const auto end_block = [&](const Label& next) {
        a.add(x86::r14, kChunkLanes * int(sizeof(T)));
        a.add(x86::r15, int32_t(c.chunk_stride));
        a.cmp(x86::r14, x86::ptr(x86::rbp, offsetof(Context<T>, end)));
        a.jb(next);
    };
    // The last reader of each instruction's result: a result held in registers is stored
    // only if read after the point where its registers are needed or forgotten.
    std::vector<std::size_t> last_read(tape.code.size());
    {
        std::vector<std::size_t> writer(tape.slot_count, SIZE_MAX);
        for (std::size_t i = 0; i < tape.code.size(); ++i) {
            const Instruction& ins = tape.code[i];
            for (int k = 0; k < ir::op_arity(ins.op); ++k) {
                if (ins.constant_operands & (1u << k)) continue;
                if (const std::size_t w = writer[ins.in[k]]; w != SIZE_MAX) last_read[w] = i;
            }
            last_read[i] = i;
            writer[ins.out] = i;
        }
    }
    std::vector<std::function<void()>> cold_paths;
    Emit e(a, last_read, cold_paths);
    // Constants of the inline functions (tape_jit_math.hpp): pool entries after the others.
    std::map<uint32_t, uint32_t> math_constants;
    const std::function<x86::Mem(uint32_t)> pool_constant = [&](uint32_t bits) {
        auto [it, added] = math_constants.try_emplace(
            bits, uint32_t(c.operand_constants.size() + c.fixed_constants.size()));
        if (added) {
            T value{};
            if constexpr (sizeof(T) == 4) std::memcpy(&value, &bits, 4);
            c.fixed_constants.push_back(value);
        }
        return Emit::pool_entry(it->second);
    };
    // Sites are addressed by the code, so their vector must not move.
    c.sites.reserve(tape.code.size());
    Label block;
    begin_block(block);
    std::size_t block_start = a.offset();
    for (std::size_t i = 0; i < tape.code.size(); ++i) {
        if (a.offset() - block_start >= kBlockBytes) {
            e.flush(i - 1);
            end_block(block);
            begin_block(block);
            block_start = a.offset();
        }
        if (compiles_inline(tape.code[i])) {
            Instruction emitted = tape.code[i];
            if (emitted.op == ir::Op::Sub && (emitted.constant_operands & 2u)) emitted.op = ir::Op::Add;   // kNegated
            e.emit(i, emitted, refs[i].data(), factors[i], numbers.empty() ? 0 : numbers[i], divisors[i]);
            continue;
        }
        if constexpr (std::is_same_v<T, float>)
            if (inline_math(e, i, tape.code[i].op, refs[i].data(), pool_constant)) continue;
        e.flush(i - 1);   // the call reads its operands from memory and may change every register
        if constexpr (std::is_same_v<T, float>) {
            // A sin and cos of one operand: one site for both, as the lane kernel runs them.
            if (i + 1 < tape.code.size() && sincos_twins(tape.code[i], tape.code[i + 1])) {
                c.sites.push_back(Site{uint32_t(i), {refs[i][0], refs[i][1], refs[i][2], refs[i][3]}, true, refs[i + 1][0]});
                e.call_site(&c.sites.back());
                ++i;
                continue;
            }
            if (void* function = float_vector_function(tape.code[i].op, kWide)) {
                e.call_vector_function(refs[i].data(), ir::op_arity(tape.code[i].op), function);
                continue;
            }
        }
        c.sites.push_back(Site{uint32_t(i), {refs[i][0], refs[i][1], refs[i][2], refs[i][3]}});
        c.sites_read_uniforms = c.sites_read_uniforms || uniform_operands[i] != 0;
        e.call_site(&c.sites.back());
    }
    e.flush(tape.code.size());
    end_block(block);
    a.vzeroupper();
    a.add(x86::rsp, 8);
    for (int k = 5; k >= 0; --k) a.pop(saved[k]);
    a.ret();
    for (const std::function<void()>& cold : cold_paths) cold();

    {
        std::lock_guard lock(runtime_mutex());
        if (runtime().add(&c.function, &code) != kErrorOk) return nullptr;
    }
    return compiled;
}

}  // namespace

template <class T>
std::unique_ptr<CompiledTape<T>> CompiledTape<T>::compile(const Tape& tape, std::span<const uint8_t> numbers) {
    if (!tape_jit_available()) return nullptr;
    std::unique_ptr<Compiled> compiled = tape_jit_width() == JitWidth::avx512 ? compiled_code<T, true>(tape, numbers)
                                                                             : compiled_code<T, false>(tape, numbers);
    if (!compiled) return nullptr;
    std::unique_ptr<CompiledTape> result(new CompiledTape());
    result->compiled_ = std::move(compiled);
    return result;
}

template <class T>
CompiledTape<T>::~CompiledTape() = default;

template <class T>
bool CompiledTape<T>::reads_code_constants() const {
    return compiled_->sites_read_uniforms;
}

template <class T>
int CompiledTape<T>::chunk_lanes() const {
    return compiled_->chunk_lanes;
}

template <class T>
JitWidth CompiledTape<T>::width() const {
    return compiled_->width;
}

template <class T>
std::size_t CompiledTape<T>::divisions_by_reciprocal() const {
    return compiled_->divisor_entries.size();
}

template <class T>
void CompiledTape<T>::run(const Instruction* code, std::size_t count, T* const* slots, int lanes,
                          JitScratch<T>& scratch, bool constants_changed, const RowValues<T>* row) const {
    const Compiled& c = *compiled_;
    // The pool's entries start on a cache line (a 64-byte entry is one line, not two), so it
    // has a line more than they take.
    const std::size_t pool_size = (c.fixed_constants.size() + c.operand_constants.size()) * c.vector_bytes / sizeof(T) +
                                  64 / sizeof(T);
    if (scratch.constants.size() != pool_size) {
        scratch.constants.assign(pool_size, T(0));   // may move: every entry is written below
        constants_changed = true;
    }
    const auto cache_line_aligned = [](T* p) { return p + (64 - reinterpret_cast<std::uintptr_t>(p) % 64) % 64 / sizeof(T); };
    T* const pool_base = cache_line_aligned(scratch.constants.data());
    const int per_vector = c.vector_bytes / int(sizeof(T));
    if (constants_changed || scratch.constants_of != code) {
        T* pool = pool_base;
        const auto put = [&pool, per_vector](T value) { pool = std::fill_n(pool, per_vector, value); };
        for (std::size_t k = 0; k < kFixedCount; ++k) put(c.fixed_constants[k]);
        for (auto [instruction, operand] : c.operand_constants) {
            const T value = T(code[instruction].constant[operand & ~kNegated]);
            put(operand & kNegated ? -value : value);
        }
        for (std::size_t k = kFixedCount; k < c.fixed_constants.size(); ++k) put(c.fixed_constants[k]);
        // Other code than the compiled one may have other divisors (tests change them).
        scratch.divisors_fit = true;
        for (const auto& [instruction, entry, planned] : c.divisor_entries) {
            const ConstantDivisor<T> now = plan_constant_divisor(T(code[instruction].constant[1]));
            scratch.divisors_fit = scratch.divisors_fit && now.kind == planned.kind;
            std::fill_n(pool_base + std::size_t(entry) * per_vector, per_vector, now.reciprocal);
        }
        scratch.constants_of = code;
        scratch.uniforms_row = ~std::size_t{0};
    }
    // A row's values straight into the pool: patching them into the code first would touch
    // a cache line of the code per use (prospero.vm: about 5% of its time).
    if (row && scratch.uniforms_row != row->row) {
        for (auto [entry, uniform, negated] : c.uniform_entries) {
            const T value = row->values[uniform];
            std::fill_n(pool_base + std::size_t(entry) * per_vector, per_vector, negated ? -value : value);
        }
        scratch.uniforms_row = row->row;
    }
    // (The voxel engine never gets here: the only constants it changes are the uniforms, and
    // divisions by those are compiled as divisions.)
    if (!scratch.divisors_fit) {
        run_lanes<T, 0>(code, count, slots, lanes);
        return;
    }
    const int chunk_lanes = c.chunk_lanes;
    const std::size_t chunks = std::size_t(lanes) / chunk_lanes;
    const int done = int(chunks) * chunk_lanes;
    const int rest = lanes - done;
    const std::size_t needed = ((chunks + (rest > 0 ? 1 : 0)) * c.chunk_stride + 64) / sizeof(T);
    if (scratch.slots.size() < needed) scratch.slots.assign(needed, T(0));
    T* const chunk_scratch = cache_line_aligned(scratch.slots.data());
    const Context<T> context{slots, chunk_scratch, pool_base, code, chunks * chunk_lanes * sizeof(T)};
    if (chunks > 0) c.function(&context);
    if (rest == 0) return;
    // The tail: one more chunk of the code, its external slots copied into arrays a chunk
    // long (the lanes past the tail repeat its last value), its outputs copied back. Why: the
    // lane kernel took several times as long a lane (rows of 800 lanes in AVX-512 chunks of
    // 64: floz64.vm's 800² float32 field 19.1 -> 18.0 ms; bear.vm's 129³ tiles of 903 lanes,
    // a tail of 7, 95 -> 85 ms).
    std::vector<T*>& tail = scratch.tail_slots;
    tail.assign(c.slot_count, nullptr);
    if (scratch.tail_lanes.size() < c.external_slots.size() * chunk_lanes)
        scratch.tail_lanes.resize(c.external_slots.size() * chunk_lanes);
    for (std::size_t e = 0; e < c.external_slots.size(); ++e) {
        const uint32_t s = c.external_slots[e];
        T* padded = scratch.tail_lanes.data() + e * chunk_lanes;
        std::copy_n(slots[s] + done, rest, padded);
        std::fill(padded + rest, padded + chunk_lanes, padded[rest - 1]);
        tail[s] = padded;
    }
    const Context<T> tail_context{tail.data(), chunk_scratch, pool_base, code, chunk_lanes * sizeof(T)};
    c.function(&tail_context);
    for (uint32_t s : c.output_slots) std::copy_n(tail[s], rest, slots[s] + done);
}

template class CompiledTape<float>;
template class CompiledTape<double>;

}  // namespace fortu
