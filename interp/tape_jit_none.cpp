// interp/tape_jit_none.cpp — the tape compiler where machine code cannot be linked (shared
// objects: interp/CMakeLists.txt): it compiles nothing, so the lane loops run every tape.
#include "interp/tape_jit.hpp"

namespace fortu {

template <class T>
struct CompiledTape<T>::Compiled {};

bool tape_jit_available() { return false; }
bool tape_jit_avx512_available() { return false; }
JitWidth tape_jit_width() { return JitWidth::avx2; }
void use_tape_jit_width(JitWidth) {}

template <class T>
std::unique_ptr<CompiledTape<T>> CompiledTape<T>::compile(const Tape&, std::span<const uint8_t>) {
    return nullptr;
}

template <class T>
CompiledTape<T>::~CompiledTape() = default;

template <class T>
void CompiledTape<T>::run(const Instruction*, std::size_t, T* const*, int, JitScratch<T>&, bool,
                          const RowValues<T>*) const {}

template <class T>
bool CompiledTape<T>::reads_code_constants() const {
    return true;
}

template <class T>
std::size_t CompiledTape<T>::divisions_by_reciprocal() const {
    return 0;
}

template <class T>
int CompiledTape<T>::chunk_lanes() const {
    return 0;
}

template <class T>
JitWidth CompiledTape<T>::width() const {
    return JitWidth::avx2;
}

template class CompiledTape<float>;
template class CompiledTape<double>;

}  // namespace fortu
