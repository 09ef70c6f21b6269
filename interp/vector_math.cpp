// interp/vector_math.cpp — chooses the kernel table of vector_math.def for this CPU once,
// and maps IR operations to its entries.
#include "interp/vector_math.hpp"

#include "interp/vector_math_kernels.hpp"

#include <array>

namespace fortu::vector_math {
namespace {

constexpr std::array<int, ir::kOpCount> slot_of_op() {
    std::array<int, ir::kOpCount> slot{};
    slot.fill(-1);
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) slot[static_cast<int>(ir::Op::op)] = k##op;
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) slot[static_cast<int>(ir::Op::op)] = k##op;
#include "interp/vector_math.def"
    return slot;
}
constexpr std::array<int, ir::kOpCount> kSlotOfOp = slot_of_op();

Isa detect() {
#if defined(FORTU_VECTOR_MATH_AVX512)
    if (__builtin_cpu_supports("avx512f")) return Isa::avx512;
#endif
#if defined(FORTU_VECTOR_MATH_AVX2)
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return Isa::avx2;
#endif
    return Isa::none;
}

const Kernel* table_of(Isa isa) {
    switch (isa) {
#if defined(FORTU_VECTOR_MATH_AVX512)
    case Isa::avx512: return kAvx512Kernels;
#endif
#if defined(FORTU_VECTOR_MATH_AVX2)
    case Isa::avx2: return kAvx2Kernels;
#endif
    default: return nullptr;
    }
}

SinCosKernel sincos_of(Isa isa) {
    switch (isa) {
#if defined(FORTU_VECTOR_MATH_AVX512)
    case Isa::avx512: return kAvx512SinCos;
#endif
#if defined(FORTU_VECTOR_MATH_AVX2)
    case Isa::avx2: return kAvx2SinCos;
#endif
    default: return nullptr;
    }
}

struct Choice {
    Isa best = detect();
    Isa active = best;
    const Kernel* table = table_of(best);
    SinCosKernel sincos = sincos_of(best);
};

Choice& choice() {
    static Choice c;
    return c;
}

}  // namespace

Isa best_isa() { return choice().best; }
Isa active_isa() { return choice().active; }

void use_isa(Isa isa) {
    Choice& c = choice();
    c.active = static_cast<int>(isa) < static_cast<int>(c.best) ? isa : c.best;
    c.table = table_of(c.active);
    c.sincos = sincos_of(c.active);
}

const char* isa_name(Isa isa) {
    switch (isa) {
    case Isa::avx512: return "AVX-512";
    case Isa::avx2: return "AVX2";
    case Isa::none: break;
    }
    return "none";
}

bool run_float(ir::Op op, const float* a, const float* b, float ka, float kb, unsigned constant_mask,
               float* out, int lanes) {
    const Kernel* table = choice().table;
    const int slot = kSlotOfOp[static_cast<int>(op)];
    if (table == nullptr || slot < 0) return false;
    table[slot](a, b, ka, kb, constant_mask, out, lanes);
    return true;
}

bool run_float_sincos(const float* a, float* sin_out, float* cos_out, int lanes) {
    const SinCosKernel kernel = choice().sincos;
    if (kernel == nullptr) return false;
    kernel(a, sin_out, cos_out, lanes);
    return true;
}

std::string libraries_text() {
    std::string fortu_ops;
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) \
    if (runs_fortu_function(ir::Op::op)) fortu_ops += std::string(fortu_ops.empty() ? "" : ", ") + std::string(ir::op_name(ir::Op::op));
#define FORTU_VECTOR_MATH_2 FORTU_VECTOR_MATH_1
#include "interp/vector_math.def"
    return fortu_ops.empty() ? "SLEEF" : "SLEEF; " + fortu_ops + ": fortu";
}

void* one_vector_function(Isa isa, ir::Op op) {
    const int slot = kSlotOfOp[static_cast<int>(op)];
    if (slot < 0) return nullptr;
    switch (isa) {
#if defined(FORTU_VECTOR_MATH_AVX512)
    case Isa::avx512: return kAvx512VectorFunctions[slot];
#endif
#if defined(FORTU_VECTOR_MATH_AVX2)
    case Isa::avx2: return kAvx2VectorFunctions[slot];
#endif
    default: return nullptr;
    }
}

}  // namespace fortu::vector_math
