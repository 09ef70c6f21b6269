// cli/golden/golden_run.cpp — see golden_run.hpp. The model is evaluated once per engine; each
// reference file is compared with that engine's output, so "both" also checks that the two
// engines agree. New outputs are written to a private temporary folder and only copied beside
// the test (NAME.actual.EXT, NAME.diff.EXT) when they differ.
#include "cli/golden/golden_run.hpp"

#include "cli/data_paths.hpp"
#include "grammar/diagnostic.hpp"
#include "interp/classic_cost.hpp"
#include "interp/ir_print.hpp"
#include "interp/lower.hpp"
#include "interp/mesher.hpp"
#include "interp/singular.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/output.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_error.hpp"
#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <span>

namespace fortu {
namespace {

namespace fs = std::filesystem;
using Status = GoldenResult::Status;

/// A private temporary folder, removed with the object.
class TempDir {
public:
    TempDir() {
        std::string pattern = (fs::temp_directory_path() / "fortu-golden-XXXXXX").string();
        if (mkdtemp(pattern.data())) path_ = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        if (!path_.empty()) fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

/// The grid of a golden run: the script's domain, the test's size (default: RECTBMP, else
/// 64x64 in 2D and 16x16x16 in 3D — small, so a suite stays fast).
Grid golden_grid(const Model& model, const GoldenTest& test) {
    std::array<int, 3> n{64, 64, 1};
    if (model.raster) n = {(*model.raster)[0], (*model.raster)[1], 1};
    if (model.dims() == 3) n = test.size_3d.value_or(std::array<int, 3>{16, 16, 16});
    else if (test.size_2d) n = {(*test.size_2d)[0], (*test.size_2d)[1], 1};
    return model_grid(model, n);
}

std::string coordinates_text(const std::vector<double>& p) {
    std::string s;
    for (double v : p) s += fmt::format("{}{}", s.empty() ? "" : " ", v);
    return s;
}

std::string error_text(const Diagnostic& d, const std::string& script) {
    if (!d.range.file) return d.message;
    const std::string where = fmt::format("{}:{}", d.range.begin.line, d.range.begin.column);
    if (d.range.file->path() == script) return fmt::format("{}: {}", where, d.message);
    return fmt::format("{}:{}: {}", fs::path(d.range.file->path()).filename().string(), where, d.message);
}

std::optional<std::string> read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The script's lines (each keeping a trailing '\r'), for rewriting directives in place.
std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t end = text.find('\n', at);
        if (end == std::string::npos) {
            if (at < text.size()) lines.push_back(text.substr(at));
            break;
        }
        lines.push_back(text.substr(at, end - at));
        at = end + 1;
    }
    return lines;
}

/// Rewrites script lines (1-based line → new text, nullopt = delete) atomically.
std::string rewrite_script(const std::string& path, const std::map<int, std::optional<std::string>>& edits) {
    const auto text = read_text(path);
    if (!text) return fmt::format("cannot read '{}'", path);
    std::vector<std::string> lines = split_lines(*text);
    std::string out;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const auto edit = edits.find(static_cast<int>(i + 1));
        std::string line = lines[i];
        if (edit != edits.end()) {
            if (!edit->second) continue;
            const bool cr = !line.empty() && line.back() == '\r';
            line = *edit->second + (cr ? "\r" : "");
        }
        out += line;
        if (i + 1 < lines.size() || (!text->empty() && text->back() == '\n')) out += '\n';
    }
    try {
        write_file_atomically(path, [&](OutputFile& f) { f.write(out); });
    } catch (const OutputError& e) {
        return e.what();
    }
    return "";
}

/// The directive line with its keyword (and, for expect-value, its value) replaced.
std::string edited_directive(const std::string& line, const std::string& keyword, const std::string& new_keyword,
                             std::optional<double> new_value) {
    std::string s = line;
    if (!s.empty() && s.back() == '\r') s.pop_back();
    const std::size_t at = s.find(keyword);
    if (at == std::string::npos) return s;
    s.replace(at, keyword.size(), new_keyword);
    if (new_value) {
        const std::size_t colon = s.find(':', at);
        const std::size_t begin = s.find_first_not_of(" \t", colon + 1);
        const std::size_t end = begin == std::string::npos ? begin : s.find_first_of(" \t", begin);
        if (begin != std::string::npos) s.replace(begin, end == std::string::npos ? std::string::npos : end - begin,
                                                  fmt::format("{}", *new_value));
    }
    return s;
}

const char* keyword_of(PointExpectation::Kind kind) {
    switch (kind) {
        case PointExpectation::Kind::Value: return "expect-value";
        case PointExpectation::Kind::Inside: return "expect-inside";
        case PointExpectation::Kind::Outside: return "expect-outside";
        case PointExpectation::Kind::Boundary: return "expect-boundary";
    }
    return "";
}

PointExpectation::Kind kind_of_value(double v) {
    return v > 0 ? PointExpectation::Kind::Inside : v < 0 ? PointExpectation::Kind::Outside
                                                          : PointExpectation::Kind::Boundary;
}

/// The run of one test, its messages gathered as it goes.
class TestRun {
public:
    TestRun(const GoldenTest& test, const GoldenRunOptions& options) : test_(test), options_(options) {}

    GoldenResult run();

private:
    void fail(std::string message) { failures_.push_back(std::move(message)); }
    bool check_errors(const DiagnosticSink& sink);
    bool classic_allowed(const Model& model, double points);
    void check_points(const Model& model, const std::vector<const Engine*>& engines);
    void check_point(const PointExpectation& e, double v, const std::string& label);
    void check_files(const Model& model, const Grid& grid, const std::vector<const Engine*>& engines);
    void check_singular(const Model& model);
    void check_file(const Field& field, const std::string& kind, const std::string& label, bool first_engine);
    std::string expected_path(const std::string& kind) const { return test_.expected_stem + ".expected." + kind; }
    std::string beside(const std::string& what, const std::string& kind) const {
        return test_.expected_stem + "." + what + "." + kind;
    }
    /// Where a failure's picture of the difference goes (the row's diff_name: NAME.diff.png,
    /// NAME.values-diff.png for .npy values, ...); "" for formats that draw none.
    std::string diff_path(const OutputFormat& format) const {
        return format.diff_name.empty() ? "" : test_.expected_stem + "." + std::string(format.diff_name);
    }
    void updated(std::string what) { updates_.push_back(std::move(what)); }

    const GoldenTest& test_;
    std::optional<Mesh> mesh_;   ///< the model's mesh, for mesh outputs (made once per test)
    const GoldenRunOptions& options_;
    TempDir temp_;
    std::vector<std::string> failures_;     ///< problems left failing
    std::vector<std::string> updates_;      ///< what --update rewrote
    std::vector<std::string> kinds_;        ///< reference files of the test
    std::map<int, std::optional<std::string>> script_edits_;
    std::vector<std::string> script_lines_;
};

bool TestRun::check_errors(const DiagnosticSink& sink) {
    std::vector<std::string> actual;
    for (const Diagnostic& d : sink.diagnostics())
        if (d.severity == Severity::Error) actual.push_back(error_text(d, test_.script));
    std::vector<std::string> expected;
    for (const ErrorExpectation& e : test_.errors) expected.push_back(e.text);
    if (actual == expected) return true;
    if (options_.update && !actual.empty()) {
        // The first expect-error line takes the actual errors, the other ones go.
        const std::string& first = script_lines_[test_.errors[0].line - 1];
        const std::string prefix = first.substr(0, first.find("expect-error")) + "expect-error ";
        std::string joined;
        for (const std::string& a : actual) {
            if (!joined.empty()) joined += '\n';
            joined += prefix;
            joined += a;
        }
        script_edits_[test_.errors[0].line] = joined;
        for (std::size_t i = 1; i < test_.errors.size(); ++i) script_edits_[test_.errors[i].line] = std::nullopt;
        updated("the script's expect-error lines");
        return false;
    }
    std::string message = "the errors differ\n  expected:";
    for (const std::string& e : expected) message += "\n    " + e;
    message += "\n  actual:";
    if (actual.empty()) message += "\n    (none: the script compiles)";
    for (const std::string& a : actual) message += "\n    " + a;
    fail(message);
    return false;
}

bool TestRun::classic_allowed(const Model& model, double points) {
    const int depth = dag_depth(model.graph, model.root);
    const double per_point = classic_operations_per_point(model.graph, model.root);
    if (depth <= kClassicMaxDepth && per_point * points <= kGoldenClassicBudget) return true;
    fail(fmt::format("the classic engine would need {} operations per point x {} points, more than a golden "
                     "test may spend ({}); declare `// golden-engine voxel` or a smaller golden-size",
                     format_operations(per_point), format_operations(points), fmt::format("{:.3g}", kGoldenClassicBudget)));
    return false;
}

/// The engines' values agree (NaN with NaN): then one check speaks for all of them.
bool same_values(std::span<const double> a, std::span<const double> b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
    return true;
}

std::string engines_label(const std::vector<const Engine*>& engines) {
    return engines.size() > 1 ? "both engines" : std::string(engines[0]->name());
}

void TestRun::check_points(const Model& model, const std::vector<const Engine*>& engines) {
    for (const PointExpectation& e : test_.points) {
        if (e.point.size() != model.arguments.size()) {
            fail(fmt::format("line {}: {} gives {} coordinate(s); the model has {} argument(s)", e.line,
                             keyword_of(e.kind), e.point.size(), model.arguments.size()));
            continue;
        }
        std::array<double, 3> p{0, 0, 0};
        for (std::size_t i = 0; i < e.point.size(); ++i) p[i] = e.point[i];
        std::vector<double> values;
        for (const Engine* engine : engines) values.push_back(evaluate_point(model, p, *engine).value);
        bool agree = true;
        for (double v : values) agree = agree && same_values(std::span(&v, 1), std::span(values.data(), 1));
        if (agree) {
            check_point(e, values[0], engines_label(engines));
        } else {
            for (std::size_t i = 0; i < engines.size(); ++i) check_point(e, values[i], std::string(engines[i]->name()));
        }
    }
}

void TestRun::check_point(const PointExpectation& e, double v, const std::string& label) {
    bool ok;
    std::string wanted;
    if (e.kind == PointExpectation::Kind::Value) {
        const double tol = e.tolerance.value_or(test_.tolerance);
        ok = std::isnan(e.value) ? std::isnan(v)
             : std::isinf(e.value) ? v == e.value
                                   : std::isfinite(v) && std::fabs(v - e.value) <= tol;
        wanted = fmt::format("{} +- {}", e.value, tol);
    } else {
        ok = std::isfinite(v) && kind_of_value(v) == e.kind;
        wanted = e.kind == PointExpectation::Kind::Inside ? "inside (> 0)"
                 : e.kind == PointExpectation::Kind::Outside ? "outside (< 0)" : "on the boundary (= 0)";
    }
    if (ok) return;
    if (options_.update && std::isfinite(v)) {
        if (script_edits_.count(e.line)) return;  // already rewritten from the first engine
        const bool value = e.kind == PointExpectation::Kind::Value;
        script_edits_[e.line] =
            edited_directive(script_lines_[e.line - 1], keyword_of(e.kind),
                             value ? "expect-value" : keyword_of(kind_of_value(v)),
                             value ? std::optional<double>(v) : std::nullopt);
        updated(fmt::format("the script's line {}", e.line));
        return;
    }
    fail(fmt::format("line {}: {} {} ({}): expected {}, got {}", e.line, keyword_of(e.kind),
                     coordinates_text(e.point), label, wanted, v));
}

void TestRun::check_file(const Field& field, const std::string& kind, const std::string& label, bool first_engine) {
    const std::string expected = expected_path(kind);
    const std::string actual = (fs::path(temp_.path()) / fmt::format("{}.{}", first_engine ? 1 : 2, kind)).string();
    OutputOptions out;
    const bool exists = fs::exists(expected);
    auto write_actual = [&](const std::string& path) -> std::string {
        try {
            const OutputTarget target = resolve_output(path);
            if (target.format->kind == OutputKind::Mesh) write_mesh(*mesh_, target, out);
            else write_field(field, target, out);
        } catch (const OutputError& e) {
            return e.what();
        }
        return "";
    };
    if (temp_.path().empty()) return fail("cannot make a temporary folder for the new outputs");
    if (std::string e = write_actual(actual); !e.empty()) return fail(e);

    const OutputFormat& format = *golden_output_format(kind);
    const ComparedOutput compared{format, expected, actual, field, test_.tolerance, test_.pixel_tolerance};
    OutputComparison comparison;
    if (!exists && !options_.update) {
        if (first_engine) fail(fmt::format("{} is missing (run with --update to create it)", expected));
        return;
    }
    if (!exists) comparison.difference = "missing";
    else comparison = format.compare(compared);
    const std::string& difference = comparison.difference;
    std::error_code ec;
    if (difference.empty()) {
        // A pass clears what an earlier failure left beside the test.
        if (first_engine) {
            fs::remove(beside("actual", kind), ec);
            if (!diff_path(format).empty()) fs::remove(diff_path(format), ec);
        }
        return;
    }
    if (options_.update) {
        if (!first_engine) return;  // the reference comes from the first engine; a second run checks the rest
        if (std::string e = write_actual(expected); !e.empty()) return fail(e);
        fs::remove(beside("actual", kind), ec);
        if (!diff_path(format).empty()) fs::remove(diff_path(format), ec);
        return updated(fs::path(expected).filename().string());
    }
    std::string message = fmt::format("{} ({}): {}", fs::path(expected).filename().string(), label, difference);
    if (std::string e = write_actual(beside("actual", kind)); e.empty())
        message += fmt::format("\n  new output: {}", beside("actual", kind));
    if (exists && comparison.diff_subimage >= 0 && format.write_diff) {
        const std::string diff = diff_path(format);
        if (std::string e = format.write_diff(compared, comparison, diff); e.empty())
            message += fmt::format("\n  diff image: {}", diff);
        else
            message += fmt::format("\n  no diff image: {}", e);
    }
    fail(message);
}

/// The points as `(x, y[, z])`, space-separated.
std::string points_text(const std::vector<std::array<double, 3>>& points, int dims) {
    std::string s;
    for (const auto& p : points) {
        if (!s.empty()) s += ' ';
        s += dims == 3 ? fmt::format("({}, {}, {})", p[0], p[1], p[2]) : fmt::format("({}, {})", p[0], p[1]);
    }
    return s.empty() ? "none" : s;
}

void TestRun::check_singular(const Model& model) {
    // The search grid of `fortu singular` (401x401, 48x48x48 over the script's domain), so its
    // output can be pasted into the test. Points match within 1e-6 (or golden-tolerance if
    // larger) in 2D, where they are refined to ~1e-12; within one search step in 3D, where
    // each is one point on an edge curve.
    const Grid grid = model_grid(model, model.dims() == 3 ? std::array<int, 3>{48, 48, 48}
                                                          : std::array<int, 3>{401, 401, 1});
    std::vector<std::array<double, 3>> found;
    for (const SingularPoint& p : find_singular_points(model, grid)) found.push_back(p.point);
    std::vector<std::array<double, 3>> expected;
    for (const SingularExpectation& s : test_.singular) expected.insert(expected.end(), s.points.begin(), s.points.end());

    const double step = std::max({grid.x.step(), grid.y.step(), grid.z.step()});
    const double tol = grid.dims == 3 ? step : std::max(1e-6, test_.tolerance);
    auto near = [&](const std::array<double, 3>& a, const std::array<double, 3>& b) {
        for (int k = 0; k < grid.dims; ++k)
            if (std::fabs(a[k] - b[k]) > tol) return false;
        return true;
    };
    std::vector<std::array<double, 3>> missing, extra;
    for (const auto& e : expected)
        if (std::none_of(found.begin(), found.end(), [&](const auto& f) { return near(e, f); })) missing.push_back(e);
    for (const auto& f : found)
        if (std::none_of(expected.begin(), expected.end(), [&](const auto& e) { return near(e, f); })) extra.push_back(f);
    if (missing.empty() && extra.empty()) return;
    if (options_.update) {
        const std::string& first = script_lines_[test_.singular[0].line - 1];
        script_edits_[test_.singular[0].line] =
            first.substr(0, first.find("expect-singular")) + "expect-singular " + points_text(found, grid.dims);
        for (std::size_t i = 1; i < test_.singular.size(); ++i) script_edits_[test_.singular[i].line] = std::nullopt;
        return updated("the script's expect-singular lines");
    }
    std::string message = fmt::format("line {}: the singular points differ (matched within {})", test_.singular[0].line, tol);
    if (!missing.empty()) message += "\n  expected, not found: " + points_text(missing, grid.dims);
    if (!extra.empty()) message += "\n  found, not expected: " + points_text(extra, grid.dims);
    message += "\n  found: " + points_text(found, grid.dims);
    fail(message);
}

void TestRun::check_files(const Model& model, const Grid& grid, const std::vector<const Engine*>& engines) {
    if (kinds_.empty()) return;
    std::vector<const Engine*> ran;
    std::vector<Field> fields;
    EvalOptions eval;
    eval.threads = options_.eval_threads;
    for (const Engine* engine : engines) {
        if (engine->capabilities().expanded_tree_cost && !classic_allowed(model, double(grid.points()))) continue;
        ran.push_back(engine);
        fields.push_back(evaluate_grid(model, grid, *engine, eval));
    }
    if (fields.empty()) return;
    if (fields.size() == 2 && same_values(fields[0].values, fields[1].values)) fields.pop_back();
    for (const std::string& kind : kinds_)
        if (golden_output_format(kind)->kind == OutputKind::Mesh && !mesh_) {
            if (grid.dims != 3) return fail(fmt::format("golden-output {}: a mesh needs a 3D model", kind));
            mesh_ = extract_mesh(model.graph, model.root, grid, eval);
        }
    for (std::size_t i = 0; i < fields.size(); ++i)
        for (const std::string& kind : kinds_)
            if (i == 0 || golden_output_format(kind)->kind != OutputKind::Mesh)  // one mesh, whatever the engine
                check_file(fields[i], kind, fields.size() == 1 ? engines_label(ran) : std::string(ran[i]->name()), i == 0);
}

GoldenResult TestRun::run() {
    GoldenResult result;
    if (!test_.problems.empty()) {
        result.status = Status::Fail;
        result.messages = test_.problems;
        return result;
    }
    const auto text = read_text(test_.script);
    if (!text) return {Status::Fail, {fmt::format("cannot read '{}'", test_.script)}};
    script_lines_ = split_lines(*text);

    const std::vector<std::string> kinds = golden_output_kinds();
    for (const std::string& kind : kinds)
        if (fs::exists(expected_path(kind)) ||
            std::find(test_.outputs.begin(), test_.outputs.end(), kind) != test_.outputs.end())
            kinds_.push_back(kind);
    if (test_.errors.empty() && test_.points.empty() && test_.singular.empty() && kinds_.empty())
        return {Status::Fail, {fmt::format("no expectations: add `// expect-...` lines, or NAME.expected.{{{}}} "
                                           "files or `// golden-output` for --update to create",
                                           fmt::join(kinds, ","))}};
    if (!test_.errors.empty() && (!test_.points.empty() || !test_.singular.empty() || !kinds_.empty()))
        return {Status::Fail, {"expect-error cannot be combined with other expectations (a model with errors "
                               "produces nothing)"}};

    std::string load_error;
    auto source = SourceFile::load(test_.script, load_error);
    if (!source) return {Status::Fail, {load_error}};
    DiagnosticSink sink;
    CompileOptions compile_options;
    compile_options.include_dirs = stdlib_dirs();
    std::optional<Model> model;
    try {
        model = compile(source, compile_options, sink);
    } catch (const std::exception& e) {
        return {Status::Fail, {fmt::format("compiling failed: {}", e.what())}};
    }

    if (!test_.errors.empty() || !model) {
        if (test_.errors.empty()) {
            std::string rendered = "the script does not compile:";
            for (const Diagnostic& d : sink.diagnostics())
                if (d.severity == Severity::Error) rendered += "\n  " + error_text(d, test_.script);
            fail(rendered);
        } else {
            check_errors(sink);
        }
    } else {
        const std::vector<const Engine*> engines = options_.engines.value_or(test_.engines);
        const Grid grid = golden_grid(*model, test_);
        try {
            std::vector<const Engine*> point_engines;
            const double points = double(test_.points.size()) * (1 + model->dims());
            for (const Engine* engine : engines)
                if (!engine->capabilities().expanded_tree_cost || test_.points.empty() || classic_allowed(*model, points))
                    point_engines.push_back(engine);
            if (!test_.points.empty() && !point_engines.empty()) check_points(*model, point_engines);
            check_files(*model, grid, engines);
            if (!test_.singular.empty()) check_singular(*model);
        } catch (const std::exception& e) {
            fail(fmt::format("evaluation failed: {}", e.what()));
        }
    }

    if (!script_edits_.empty()) {
        if (std::string e = rewrite_script(test_.script, script_edits_); !e.empty()) fail(e);
    }
    if (!failures_.empty()) return {Status::Fail, failures_};
    if (!updates_.empty()) return {Status::Updated, updates_};
    return {Status::Pass, {}};
}

}  // namespace

GoldenResult run_golden_test(const GoldenTest& test, const GoldenRunOptions& options) {
    try {
        TestRun run(test, options);
        return run.run();
    } catch (const std::bad_alloc&) {
        return {Status::Fail, {"out of memory"}};
    } catch (const std::exception& e) {
        return {Status::Fail, {e.what()}};
    }
}

}  // namespace fortu
