// cli/golden/golden_run.hpp — running one golden test: compile the script, check its inline
// expectations and reference files on each engine, and with --update rewrite what failed.
#pragma once

#include "cli/golden/golden_spec.hpp"

#include <optional>
#include <string>
#include <vector>

namespace fortu {

struct GoldenRunOptions {
    std::optional<std::vector<const Engine*>> engines;   ///< --engine: replaces every test's own
    bool update = false;                              ///< --update
    int eval_threads = 0;                             ///< per grid evaluation (0: all cores)
};

struct GoldenResult {
    enum class Status { Pass, Fail, Updated };
    Status status = Status::Pass;
    /// Fail: what differed, one entry per problem (entries may span lines). Updated: the
    /// files rewritten.
    std::vector<std::string> messages;
};

/// Classic-engine operations a golden test may spend on one grid before it is refused
/// (the classic engine is exponential in nesting; a test must not run for hours).
inline constexpr double kGoldenClassicBudget = 2e8;

/// Runs one test. Never throws: every failure, including unreadable or corrupt reference
/// files, is a Fail with a message.
GoldenResult run_golden_test(const GoldenTest& test, const GoldenRunOptions& options);

}  // namespace fortu
