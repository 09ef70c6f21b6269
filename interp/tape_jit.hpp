// interp/tape_jit.hpp — a tape compiled to x86-64 machine code (AVX2 on ymm registers, or
// AVX-512 on zmm), run a short chunk of lanes at a time.
//
// Why: the lane kernel (lane_kernel.hpp) runs one instruction over a whole tile before the
// next, so every instruction streams its operands' 1024-lane arrays through L2, and shorter
// tiles pay its per-instruction dispatch more often (1024 lanes were the fastest). Compiled
// code has no dispatch: a tile is cut into chunks of four vectors, and each block of about a
// dozen instructions runs over all the chunks before the next block. Short blocks keep the
// code in the instruction cache (which, not the data, set the speed: README "Compiled
// tapes"), and the block's last three results stay in registers for the instructions after.
//
// The values are the lane kernel's, bit for bit (a NaN stays a NaN; which NaN, its sign and
// payload, is the compiler's choice as between any two builds): arithmetic, square roots, min, max, select,
// sign and the R-operations are emitted as the same IEEE operations in the same order (MIN,
// MAX and SELECT without their NaN case where that operand is never NaN: number_operands.hpp)
// (-ffp-contract=off keeps the C++ side unfused); float32 transcendentals call the SLEEF
// functions the lane kernel calls; every other operation calls the lane kernel itself for the
// chunk. Lanes are independent, so running the tape chunk by chunk instead of
// instruction by instruction changes no value, and AVX2 and AVX-512 code give the same
// values (the same IEEE operations on more lanes at once) where both call the same
// transcendentals: fortu's own exp and ln are the same on every width, SLEEF's need not be
// (tape_jit_width() says which runs).
//
// Why two widths: on a core whose 512-bit units are as wide as their operations (Intel's
// AVX-512 cores), a zmm fused multiply-add does twice an ymm one's lanes in the same time
// (a chain of four: 42 against 17-19 G lanes a second, one core of the 2026-12-02 Xeon);
// AMD's Zen 4 splits each into two 256-bit halves, yet there too the AVX-512 code, four zmm
// vectors a chunk with seven results held in registers, runs bear.vm's float32 field about
// a tenth faster and prospero.vm's no slower (docs/performance.md): half the instructions
// for the same lanes.
#pragma once

#include "interp/tape.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace fortu {

/// One worker's memory for running a CompiledTape: the chunk's internal slots, the constant
/// operands converted to T, and the external slots of the tail that is not a whole chunk.
template <class T>
struct JitScratch {
    std::vector<T> slots;
    std::vector<T> constants;
    std::vector<T*> tail_slots;
    std::vector<T> tail_lanes;   ///< a padded tail's external slots, a chunk each
    const Instruction* constants_of = nullptr;   ///< the code `constants` was read from
    std::size_t uniforms_row = ~std::size_t{0};  ///< the row RowValues last put in `constants`
    /// False if a divisor of `constants_of` is not one the code was compiled to multiply by
    /// (constant_divisor.hpp): the lane kernel then runs instead.
    bool divisors_fit = true;
};

/// One row's values of the tape's uniforms (TapeSpec::uniforms): `values[u]`.
template <class T>
struct RowValues {
    std::span<const T> values;
    std::size_t row = 0;   ///< which row: the values are put in only when it changes
};

/// The vectors compiled tapes are written for.
enum class JitWidth : uint8_t { avx2, avx512 };

/// The width CompiledTape::compile writes: AVX-512 where the CPU has it, else AVX2; or as
/// set by use_tape_jit_width.
JitWidth tape_jit_width();
/// Sets the width (--isa, tests), AVX-512 only where the CPU has it (else AVX2).
void use_tape_jit_width(JitWidth width);
/// Whether this CPU can run AVX-512 compiled tapes (AVX-512F).
bool tape_jit_avx512_available();
/// "AVX2" or "AVX-512".
inline const char* jit_width_name(JitWidth width) { return width == JitWidth::avx512 ? "AVX-512" : "AVX2"; }

template <class T>
class CompiledTape {
public:
    /// The tape compiled for this CPU at tape_jit_width(); nullptr where there is no AVX2 or
    /// code cannot be made.
    /// `numbers[i]` (when given): bit k set if operand k of instruction i is never NaN
    /// (number_operands.hpp), so MIN, MAX and SELECT need not handle a NaN there.
    static std::unique_ptr<CompiledTape> compile(const Tape& tape, std::span<const uint8_t> numbers = {});
    ~CompiledTape();
    CompiledTape(const CompiledTape&) = delete;
    CompiledTape& operator=(const CompiledTape&) = delete;

    /// As run_lanes(code, count, slots, lanes): `code` is the tape's code or a copy with other
    /// constant operands (the voxel engine patches per-row values in); pass
    /// `constants_changed` when its constants differ from those of the previous call with
    /// the same scratch. Slots the tape only uses inside (neither arguments, inputs,
    /// constants nor outputs) are not written.
    ///
    /// With `row`, the uniforms' constant operands are taken from it instead of from `code`,
    /// which then need not be patched for the row, unless reads_code_constants().
    void run(const Instruction* code, std::size_t count, T* const* slots, int lanes, JitScratch<T>& scratch,
             bool constants_changed, const RowValues<T>* row = nullptr) const;

    /// Whether run() reads the uniforms' values from `code`: for an operation handed back
    /// to the lane kernel.
    bool reads_code_constants() const;

    /// Divisions by a constant the code multiplies by the reciprocal instead (constant_divisor.hpp).
    std::size_t divisions_by_reciprocal() const;

    /// Lanes per chunk: four vectors (32 float32 lanes in AVX2, 64 in AVX-512).
    int chunk_lanes() const;
    JitWidth width() const;

    struct Site;        ///< an instruction the compiled code hands back to the lane kernel
    struct Compiled;    ///< the machine code and what it reads

private:
    CompiledTape() = default;
    std::unique_ptr<Compiled> compiled_;
};

/// Whether CompiledTape::compile can succeed on this CPU (AVX2).
bool tape_jit_available();

}  // namespace fortu
