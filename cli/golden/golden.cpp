// cli/golden/golden.cpp — `fortu golden DIR|FILE... [--engine both|classic|voxel] [--update]
// [--jobs N]`: collects the tests, runs them (on N threads), and reports one block per test in
// a stable order and a summary ending `N passed, M failed`, the line CI reads.
#include "cli/option_table.hpp"
#include "cli/commands.hpp"
#include "cli/golden/golden_run.hpp"
#include "cli/golden/golden_spec.hpp"
#include "runtime/output_formats.hpp"

#include <fmt/format.h>

#include <atomic>
#include <condition_variable>
#include <iostream>
#include <mutex>
#include <thread>

namespace fortu {
namespace {

/// "both|classic|voxel": what --engine and golden-engine take.
std::string engine_choices() { return golden_engine_choices("|", "|"); }

std::string golden_usage() {
    return fmt::format("usage: fortu golden DIR|FILE... [--engine {}] [--update] [--jobs N]", engine_choices());
}

constexpr const char* kGoldenHelp = R"(
A golden test is a .fortu script with expectations in its comments, and/or reference files
beside it (NAME.expected.{bar}, made and refreshed by --update):
  // expect-value X Y[ Z]: VALUE [+- TOL]    the value at a point (TOL: golden-tolerance)
  // expect-inside X Y[ Z]                   value > 0 (also expect-outside < 0,
                                             expect-boundary = 0)
  // expect-error LINE:COL: MESSAGE          the script's errors, in order
  // expect-singular (X, Y) ... | none       every singular point `fortu singular` finds
  // golden-engine {engines:<25} default both (--engine overrides)
  // golden-size N | WxH | WxHxD ...         default RECTBMP, else 64x64 (2D), 16x16x16 (3D)
  // golden-tolerance T                      values, npy, csv, svg, exr (default 1e-9)
  // golden-pixel-tolerance L                png, in 8-bit levels (default 0)
  // golden-output KIND...                   references --update creates; KIND: {spaced}
A NAME.golden manifest runs scripts kept elsewhere (`scripts ../models/*.fortu`, then
directives without `//`, or `STEM: directive` for one script); references sit beside it.
Output: PASS/FAIL/UPDATE per test, then `T tests: N passed, M failed`; exit 0 iff all pass.
)";

struct GoldenCommand {
    std::vector<std::string> paths;
    GoldenRunOptions run;
    int jobs = 1;
    bool help = false;
    std::string help_text;   ///< with help: the text --help prints
};

GoldenCommand parse_golden_arguments(const std::vector<std::string>& args) {
    GoldenCommand c;
    OptionTable t("golden", golden_usage() + "\n" + fmt::format(fmt::runtime(kGoldenHelp), fmt::arg("engines", engine_choices()),
                                                         fmt::arg("bar", fmt::join(golden_output_kinds(), "|")),
                                                         fmt::arg("spaced", fmt::join(golden_output_kinds(), " "))));
    t.flag("--update", "rewrite, atomically, the references and expectation lines that failed",
           [&c] { c.run.update = true; });
    t.option("--engine", engine_choices(), "the engines every test runs (replaces golden-engine)",
             [&c](const std::string& e) {
                 c.run.engines = parse_golden_engines(e);
                 if (!c.run.engines)
                     throw UsageError(fmt::format("'fortu golden': --engine '{}' is not {}", e, golden_engine_choices(", ", " or ")));
             });
    t.option("-j,--jobs", "N", "tests run at a time (default 1); the output order never changes",
             [&c](const std::string& n) {
                 std::size_t used = 0;
                 int jobs = 0;
                 try { jobs = std::stoi(n, &used); } catch (...) { used = 0; }
                 if (used != n.size() || jobs < 1 || jobs > 256)
                     throw UsageError(fmt::format("'fortu golden': --jobs '{}' is not a number of threads from 1 to 256", n));
                 c.jobs = jobs;
             });
    t.positionals(c.paths);
    if (!t.parse(args)) {
        c.help = true;
        c.help_text = t.help();
    }
    if (c.help) return c;
    if (c.paths.empty()) throw UsageError(fmt::format("'fortu golden': no tests given\n{}", golden_usage()));
    // Tests share the cores: one evaluation thread each when several run at once.
    c.run.eval_threads = c.jobs > 1 ? 1 : 0;
    return c;
}

/// One test's report: `PASS name`, `UPDATE name: files`, or `FAIL name: problem` with further
/// problems and continuation lines indented below it.
std::string report(const std::string& name, const GoldenResult& r) {
    using Status = GoldenResult::Status;
    if (r.status == Status::Pass) return fmt::format("PASS {}\n", name);
    std::string text;
    if (r.status == Status::Updated) {
        text = fmt::format("UPDATE {}: rewrote ", name);
        for (std::size_t i = 0; i < r.messages.size(); ++i) text += (i ? ", " : "") + r.messages[i];
        return text + "\n";
    }
    for (std::size_t i = 0; i < r.messages.size(); ++i) {
        std::string message = r.messages[i];
        for (std::size_t at = message.find('\n'); at != std::string::npos; at = message.find('\n', at + 1))
            message.insert(at + 1, "  ");
        text += i == 0 ? fmt::format("FAIL {}: {}\n", name, message) : fmt::format("  {}\n", message);
    }
    return text;
}

}  // namespace

int run_golden_command(const std::vector<std::string>& args) {
    const GoldenCommand command = parse_golden_arguments(args);
    if (command.help) {
        std::cout << command.help_text;
        return 0;
    }
    std::vector<GoldenTest> tests;
    for (const std::string& path : command.paths)
        for (GoldenTest& t : collect_tests(path)) tests.push_back(std::move(t));

    // Workers take tests in order; the reporter prints each result as soon as all before it
    // are printed, so the output is the same for any --jobs.
    std::vector<std::optional<GoldenResult>> results(tests.size());
    std::mutex mutex;
    std::condition_variable done;
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (std::size_t i; (i = next++) < tests.size();) {
            GoldenResult r = run_golden_test(tests[i], command.run);
            std::lock_guard lock(mutex);
            results[i] = std::move(r);
            done.notify_all();
        }
    };
    std::vector<std::jthread> threads;
    const int workers = std::min<int>(command.jobs, static_cast<int>(tests.size()));
    for (int j = 0; j < workers; ++j) threads.emplace_back(worker);

    int passed = 0, failed = 0;
    for (std::size_t i = 0; i < tests.size(); ++i) {
        std::unique_lock lock(mutex);
        done.wait(lock, [&] { return results[i].has_value(); });
        const GoldenResult r = *results[i];
        lock.unlock();
        (r.status == GoldenResult::Status::Fail ? failed : passed)++;
        std::cout << report(tests[i].name, r) << std::flush;
    }
    threads.clear();
    std::cout << fmt::format("{} test{}: {} passed, {} failed\n", tests.size(), tests.size() == 1 ? "" : "s", passed,
                             failed);
    return failed == 0 ? 0 : 1;
}

}  // namespace fortu
