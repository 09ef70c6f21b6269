// interp/tape_jit_none.cpp — the tape compiler where machine code cannot be linked (shared
// objects: interp/CMakeLists.txt): it compiles nothing, so the lane loops run every tape.
#include "interp/tape_jit.hpp"

namespace fortu {

template <class T>
struct CompiledTape<T>::Compiled {};

bool tape_jit_available() { return false; }

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
bool CompiledTape<T>::reads_code_constants(int) const {
    return true;
}

template class CompiledTape<float>;
template class CompiledTape<double>;

}  // namespace fortu
