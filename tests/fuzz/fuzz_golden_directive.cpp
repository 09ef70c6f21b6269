// tests/fuzz/fuzz_golden_directive.cpp — libFuzzer target: any line as a golden-test
// directive (`golden-size 64x64`, `expect-value 0.25 0.5: 0.734 +- 1e-9`, ...).
#include "cli/golden/golden_spec.hpp"

#include <cstdint>
#include <string>

using namespace fortu;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    GoldenTest test;
    std::string text(reinterpret_cast<const char*>(data), size);
    std::size_t start = 0;
    int line = 1;
    // Several directives in a row, as a script's comments give them.
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        (void)apply_directive(test, text.substr(start, end - start), line++);
        start = end + 1;
    }
    return 0;
}
