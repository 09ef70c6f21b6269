// tests/fuzz/fuzz_repl.cpp — libFuzzer target: any text typed into `fortu repl`, line by
// line, through the same buffering as the interactive loop (a :command is one line, FORTU
// text may span a FOR or FUNCTION block). Why: a REPL must survive every input; a crash
// loses the user's unsaved session.
//
// The session runs in a private temporary folder, and input that would reach outside it
// (a path with '/' or "..") or ask for a grid larger than 64 per axis is skipped: the
// fuzzer searches for crashes, not for ways to fill the disk or wait on large grids.
#include "cli/repl/repl_commands.hpp"
#include "cli/repl/repl_input.hpp"
#include "interp/session.hpp"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <unistd.h>

using namespace fortu;

namespace {

bool stays_small_and_inside(const std::string& text) {
    if (text.find('/') != std::string::npos || text.find("..") != std::string::npos) return false;
    // Every number in the input is at most 64: grids, sizes and loop counts stay cheap.
    std::size_t digits = 0;
    for (char c : text) {
        digits = (c >= '0' && c <= '9') ? digits + 1 : 0;
        if (digits > 2) return false;
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    char folder[] = "/tmp/fortu_fuzz_repl_XXXXXX";
    if (mkdtemp(folder) == nullptr || chdir(folder) != 0) std::abort();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    if (size > 4096 || !stays_small_and_inside(text)) return -1;
    Session session({FORTU_FUZZ_STDLIB_DIR});
    std::ostringstream out, err;
    Repl repl(session, ReplIo{out, err, false, [] { return std::pair<int, int>{40, 20}; }, nullptr});
    std::string buffer;
    std::size_t start = 0;
    while (start < text.size()) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        buffer += text.substr(start, end - start);
        buffer += '\n';
        start = end + 1;
        const std::size_t first = buffer.find_first_not_of(" \t");
        if (first != std::string::npos && buffer[first] != ':' && input_incomplete(buffer)) continue;
        const bool go_on = repl.handle(buffer);
        buffer.clear();
        if (!go_on) return 0;
    }
    if (!buffer.empty()) repl.handle(buffer);
    return 0;
}
