// tests/unit/cli_support.hpp — running the `fortu` binary from tests.
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace fortu::test {

struct CommandResult {
    int status = -1;
    std::string out;   ///< stdout, or stdout+stderr as the command line redirects
};

/// Runs a shell command line, capturing its standard output.
inline CommandResult run_shell(const std::string& command) {
    CommandResult r;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buffer;
    std::size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.out.append(buffer.data(), n);
    const int raw = pclose(pipe);
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    return r;
}

inline std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// `fortu ARGS` with stderr captured (stdout discarded unless `with_stdout`).
inline CommandResult run_fortu(const std::string& args, const std::string& cwd = ".", bool with_stdout = false) {
    const std::string redirect = with_stdout ? " 2>&1" : " 2>&1 >/dev/null";
    return run_shell("cd " + quote(cwd) + " && " + quote(FORTU_BINARY) + " " + args + redirect);
}

}  // namespace fortu::test
