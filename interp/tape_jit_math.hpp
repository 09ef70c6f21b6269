// interp/tape_jit_math.hpp — the vector functions of vector_math_functions.hpp (float32 exp
// and ln) written into a compiled tape's code: `Code`, the W its templates take, makes each
// of their operations an AVX2 instruction (ymm) or an AVX-512 one (zmm, comparisons into k
// registers) instead of running it.
//
// Why: the same template the lane loops run, so the compiled code computes the same IEEE
// operations in the same order and the values are bit-identical; and inline, because a call
// per vector costs half as much again as the function itself (8-lane exp: 3.8 ns inline
// against 5.7 ns called, pinned to one core), and a call makes the tape store every value it
// holds in registers first. bear.vm has 29 exp and 8 ln a point.
#pragma once

#include <asmjit/x86.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace fortu::tape_jit_math {

class Writer;

/// A value of the code being written: a vector register it holds (ymm or zmm, as the Writer
/// writes; shared by copies, free again when the last copy goes), a comparison's mask (on
/// AVX-512 a k register), or a constant of the tape's pool (a memory operand).
class Value {
public:
    Value() = default;
    Value(const Value& other);
    Value& operator=(const Value& other);
    ~Value();

    bool in_register() const { return reg_ >= 0; }
    bool is_mask_register() const { return reg_ >= kMaskBase; }
    /// The vector register: ymm or zmm by the Writer's width.
    asmjit::x86::Vec vec() const;
    /// The k register of an AVX-512 comparison.
    asmjit::x86::KReg k() const { return asmjit::x86::k(reg_ - kMaskBase); }
    /// The register, or the constant's memory operand.
    asmjit::Operand operand() const;

private:
    friend class Writer;
    /// reg_ of a k register: kMaskBase + its number.
    static constexpr int kMaskBase = 32;
    int reg_ = -1;
    std::uint32_t constant_bits_ = 0;
};

/// The code the templates write into, for as long as it lives: one at a time per thread (the
/// templates' W is a type, so its functions find the current Writer).
class Writer {
public:
    /// `registers`: the vector registers the written code may change; `pool_entry`: the memory
    /// operand of a pool entry holding `bits` in every lane (made on first use); `wide`:
    /// AVX-512 code on zmm registers (masks in k1..k7, which the code may change too), else
    /// AVX2 on ymm.
    Writer(asmjit::x86::Assembler& assembler, std::vector<int> registers,
           std::function<asmjit::x86::Mem(std::uint32_t bits)> pool_entry, bool wide = false);
    ~Writer();
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    static Writer& current();
    asmjit::x86::Assembler& assembler() { return a_; }
    bool wide() const { return wide_; }
    /// Register `reg` at the Writer's width.
    asmjit::x86::Vec vec(int reg) const;
    /// A register for a comparison's result: a vector register, or on AVX-512 a k register.
    Value allocate_mask();
    /// Jumps to `target` if a lane of the mask `any` is set.
    void jump_if_any(const Value& any, const asmjit::Label& target);

    /// A value loaded from memory into a register of its own.
    Value load(const asmjit::x86::Mem& memory);
    /// A value already in register `reg`, one not given to the Writer: read, never changed,
    /// and not taken for other values when its copies go.
    Value borrow(int reg);
    Value constant(std::uint32_t bits);
    /// A register for a new value.
    Value allocate();
    /// `value` in a register: itself, or a constant loaded.
    Value in_register(const Value& value);
    /// The most of its own registers the written code has held at once.
    int peak() const { return peak_; }

private:
    friend class Value;
    void retain(int reg) { ++uses_[reg]; }
    void release(int reg);

    asmjit::x86::Assembler& a_;
    std::vector<int> free_;
    std::vector<int> free_masks_;   ///< AVX-512: k registers, as Value::kMaskBase + number
    int uses_[Value::kMaskBase + 8] = {};
    bool owned_[Value::kMaskBase + 8] = {};   ///< given to the Writer: free again when a value's copies go
    bool wide_ = false;
    int held_ = 0, peak_ = 0;
    std::function<asmjit::x86::Mem(std::uint32_t)> pool_entry_;
    Writer* previous_;
};

/// vector_math_functions.hpp's W, writing code: F, I and M are all Values.
struct Code {
    using F = Value;
    using I = Value;
    using M = Value;
    static F set(float v);
    static I seti(int v);
    static F add(const F& a, const F& b);
    static F sub(const F& a, const F& b);
    static F mul(const F& a, const F& b);
    static F fma(const F& a, const F& b, const F& c);
    static F fnma(const F& a, const F& b, const F& c);
    static F min(const F& a, const F& b);
    static F max(const F& a, const F& b);
    static F abs(const F& a);
    static F to_float(const I& a);
    static F as_float(const I& a) { return a; }
    static I as_int(const F& a) { return a; }
    static I addi(const I& a, const I& b);
    static I subi(const I& a, const I& b);
    static I andi(const I& a, const I& b);
    static I shl23(const I& a);
    static I sra1(const I& a);
    static I sra23(const I& a);
    static M less(const F& a, const F& b);
    static M greater(const F& a, const F& b);
    static M equal(const F& a, const F& b);
    static M not_less_equal(const F& a, const F& b);
    static M not_greater_equal(const F& a, const F& b);
    static M or_mask(const M& a, const M& b);
    static F select(const M& m, const F& if_true, const F& if_false);
};

}  // namespace fortu::tape_jit_math
