// interp/tape_jit_math.cpp — Code's operations as AVX2 or AVX-512 instructions (tape_jit_math.hpp).
#include "interp/tape_jit_math.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <utility>

namespace fortu::tape_jit_math {
namespace {

using namespace asmjit;

thread_local Writer* current_writer = nullptr;

/// The AVX-512F form of a bitwise operation: vandps and vorps on zmm need AVX512DQ, the
/// integer forms (the same bits) only AVX512F.
InstId bitwise(InstId id) {
    if (!Writer::current().wide()) return id;
    switch (id) {
    case x86::Inst::kIdVandps: case x86::Inst::kIdVpand: return x86::Inst::kIdVpandd;
    case x86::Inst::kIdVorps: return x86::Inst::kIdVpord;
    default: return id;
    }
}

/// a op b into a new register. Only the last source of a VEX instruction may be memory: a
/// constant first operand goes second where the operation commutes, else into a register.
Value binary(InstId id, const Value& a, const Value& b, bool commutative) {
    Writer& w = Writer::current();
    const bool swap = commutative && !a.in_register() && b.in_register();
    const Value x = w.in_register(swap ? b : a);
    const Value& y = swap ? a : b;
    Value d = w.allocate();
    w.assembler().emit(bitwise(id), d.vec(), x.vec(), y.operand());
    return d;
}

/// A comparison's mask: a vector of all-ones lanes (AVX2), or a k register (AVX-512).
Value compare(const Value& a, const Value& b, int predicate) {
    Writer& w = Writer::current();
    const Value x = w.in_register(a);
    Value d = w.allocate_mask();
    if (w.wide()) w.assembler().emit(x86::Inst::kIdVcmpps, d.k(), x.vec(), b.operand(), Imm(predicate));
    else w.assembler().emit(x86::Inst::kIdVcmpps, d.vec(), x.vec(), b.operand(), Imm(predicate));
    return d;
}

Value shift(InstId id, const Value& a, int bits) {
    Writer& w = Writer::current();
    const Value x = w.in_register(a);
    Value d = w.allocate();
    w.assembler().emit(id, d.vec(), x.vec(), Imm(bits));
    return d;
}

/// a·b + c (negated: c − a·b) with one rounding. a·b = b·a exactly, so a register factor goes
/// where the instruction needs one: 213 form d = a; d = b·d + c (b a register), else 231
/// form d = c; d = a·b + d (b from memory).
Value fused(bool negated, const Value& a, const Value& b, const Value& c) {
    Writer& w = Writer::current();
    const bool swap = !a.in_register() && b.in_register();
    const Value x = w.in_register(swap ? b : a);
    const Value& y = swap ? a : b;
    Value d = w.allocate();
    if (y.in_register()) {
        w.assembler().vmovaps(d.vec(), x.vec());
        w.assembler().emit(negated ? x86::Inst::kIdVfnmadd213ps : x86::Inst::kIdVfmadd213ps, d.vec(), y.vec(), c.operand());
    } else {
        if (c.in_register()) w.assembler().vmovaps(d.vec(), c.vec());
        else w.assembler().emit(x86::Inst::kIdVmovups, d.vec(), c.operand());
        w.assembler().emit(negated ? x86::Inst::kIdVfnmadd231ps : x86::Inst::kIdVfmadd231ps, d.vec(), x.vec(), y.operand());
    }
    return d;
}

}  // namespace

// ---- Value ----

Value::Value(const Value& other) : reg_(other.reg_), constant_bits_(other.constant_bits_) {
    if (reg_ >= 0) Writer::current().retain(reg_);
}

Value& Value::operator=(const Value& other) {
    if (other.reg_ >= 0) Writer::current().retain(other.reg_);
    if (reg_ >= 0) Writer::current().release(reg_);
    reg_ = other.reg_;
    constant_bits_ = other.constant_bits_;
    return *this;
}

Value::~Value() {
    if (reg_ >= 0) Writer::current().release(reg_);
}

x86::Vec Value::vec() const { return Writer::current().vec(reg_); }

Operand Value::operand() const {
    if (is_mask_register()) return k();
    if (in_register()) return vec();
    return Writer::current().pool_entry_(constant_bits_);
}

// ---- Writer ----

Writer::Writer(x86::Assembler& assembler, std::vector<int> registers,
               std::function<x86::Mem(std::uint32_t)> pool_entry, bool wide)
    : a_(assembler), free_(std::move(registers)), wide_(wide), pool_entry_(std::move(pool_entry)),
      previous_(current_writer) {
    if (wide_)
        for (int k = 7; k >= 1; --k) free_masks_.push_back(Value::kMaskBase + k);   // k0 means "no mask"
    for (int reg : free_) owned_[reg] = true;
    for (int reg : free_masks_) owned_[reg] = true;
    current_writer = this;
}

Writer::~Writer() { current_writer = previous_; }

Writer& Writer::current() {
    if (!current_writer) throw std::logic_error("tape_jit_math: no code is being written");
    return *current_writer;
}

x86::Vec Writer::vec(int reg) const {
    if (wide_) return x86::zmm(reg);
    return x86::ymm(reg);
}

void Writer::release(int reg) {
    if (--uses_[reg] != 0 || !owned_[reg]) return;
    if (reg >= Value::kMaskBase) {
        free_masks_.push_back(reg);
        return;
    }
    free_.push_back(reg);
    --held_;
}

Value Writer::allocate_mask() {
    if (!wide_) return allocate();
    if (free_masks_.empty()) throw std::logic_error("tape_jit_math: out of mask registers");
    Value v;
    v.reg_ = free_masks_.back();
    free_masks_.pop_back();
    retain(v.reg_);
    return v;
}

void Writer::jump_if_any(const Value& any, const Label& target) {
    if (wide_) a_.kortestw(any.k(), any.k());
    else a_.vtestps(any.vec(), any.vec());
    a_.jnz(target);
}

Value Writer::allocate() {
    // The written functions keep a handful of values alive at once; more than the registers
    // given would be a mistake in the caller's choice of registers, not a case to handle.
    if (free_.empty()) throw std::logic_error("tape_jit_math: out of registers");
    Value v;
    v.reg_ = free_.back();
    free_.pop_back();
    retain(v.reg_);
    peak_ = std::max(peak_, ++held_);
    return v;
}

Value Writer::load(const x86::Mem& memory) {
    Value d = allocate();
    a_.vmovups(d.vec(), memory);
    return d;
}

Value Writer::borrow(int reg) {
    if (owned_[reg]) throw std::logic_error("tape_jit_math: a borrowed register is the Writer's own");
    Value v;
    v.reg_ = reg;
    retain(reg);
    return v;
}

Value Writer::constant(std::uint32_t bits) {
    Value v;
    v.constant_bits_ = bits;
    return v;
}

Value Writer::in_register(const Value& value) {
    if (value.in_register()) return value;
    return load(pool_entry_(value.constant_bits_));
}

// ---- Code ----

Value Code::set(float v) { return Writer::current().constant(std::bit_cast<std::uint32_t>(v)); }
Value Code::seti(int v) { return Writer::current().constant(std::bit_cast<std::uint32_t>(v)); }
Value Code::add(const F& a, const F& b) { return binary(x86::Inst::kIdVaddps, a, b, true); }
Value Code::sub(const F& a, const F& b) { return binary(x86::Inst::kIdVsubps, a, b, false); }
Value Code::mul(const F& a, const F& b) { return binary(x86::Inst::kIdVmulps, a, b, true); }
Value Code::fma(const F& a, const F& b, const F& c) { return fused(false, a, b, c); }
Value Code::fnma(const F& a, const F& b, const F& c) { return fused(true, a, b, c); }
// minps/maxps give the second operand when either is NaN: not commutative.
Value Code::min(const F& a, const F& b) { return binary(x86::Inst::kIdVminps, a, b, false); }
Value Code::max(const F& a, const F& b) { return binary(x86::Inst::kIdVmaxps, a, b, false); }
Value Code::abs(const F& a) { return binary(x86::Inst::kIdVandps, a, seti(0x7fffffff), true); }
Value Code::to_float(const I& a) {
    Writer& w = Writer::current();
    Value d = w.allocate();
    w.assembler().emit(x86::Inst::kIdVcvtdq2ps, d.vec(), a.operand());
    return d;
}
Value Code::addi(const I& a, const I& b) { return binary(x86::Inst::kIdVpaddd, a, b, true); }
Value Code::subi(const I& a, const I& b) { return binary(x86::Inst::kIdVpsubd, a, b, false); }
Value Code::andi(const I& a, const I& b) { return binary(x86::Inst::kIdVpand, a, b, true); }
Value Code::shl23(const I& a) { return shift(x86::Inst::kIdVpslld, a, 23); }
Value Code::sra1(const I& a) { return shift(x86::Inst::kIdVpsrad, a, 1); }
Value Code::sra23(const I& a) { return shift(x86::Inst::kIdVpsrad, a, 23); }
// The predicates of _mm256_cmp_ps the AVX2 W uses (vector_math_avx2.cpp).
Value Code::less(const F& a, const F& b) { return compare(a, b, 0x11); }               // LT_OQ
Value Code::greater(const F& a, const F& b) { return compare(a, b, 0x1E); }            // GT_OQ
Value Code::equal(const F& a, const F& b) { return compare(a, b, 0x00); }              // EQ_OQ
Value Code::not_less_equal(const F& a, const F& b) { return compare(a, b, 0x16); }     // NLE_UQ
Value Code::not_greater_equal(const F& a, const F& b) { return compare(a, b, 0x19); }  // NGE_UQ
Value Code::or_mask(const M& a, const M& b) {
    Writer& w = Writer::current();
    if (!w.wide()) return binary(x86::Inst::kIdVorps, a, b, true);
    Value d = w.allocate_mask();
    w.assembler().korw(d.k(), a.k(), b.k());
    return d;
}
Value Code::select(const M& m, const F& if_true, const F& if_false) {
    Writer& w = Writer::current();
    const Value otherwise = w.in_register(if_false);
    Value d = w.allocate();
    if (w.wide()) {
        w.assembler().k(m.k()).emit(x86::Inst::kIdVblendmps, d.vec(), otherwise.vec(), if_true.operand());
        return d;
    }
    const Value mask = w.in_register(m);
    w.assembler().emit(x86::Inst::kIdVblendvps, d.vec(), otherwise.vec(), if_true.operand(), mask.vec());
    return d;
}

}  // namespace fortu::tape_jit_math
