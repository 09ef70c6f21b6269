// cli/golden/golden_spec.cpp — see golden_spec.hpp. Directives are parsed strictly: a typo in one
// (`expect-valeu`) fails the test rather than silently testing less.
#include "cli/golden/golden_spec.hpp"

#include "cli/option_table.hpp"
#include "runtime/output_formats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fnmatch.h>
#include <fstream>
#include <set>
#include <sstream>

namespace fortu {
namespace {

namespace fs = std::filesystem;

/// Largest golden grid: golden tests are meant to be small and fast.
constexpr long kMaxGoldenPoints = 1L << 22;

std::string trim(std::string s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return "";
    const auto last = s.find_last_not_of(" \t\r");
    return s.substr(first, last - first + 1);
}

std::vector<std::string> words(const std::string& s) {
    std::istringstream in(s);
    std::vector<std::string> out;
    for (std::string w; in >> w;) out.push_back(w);
    return out;
}

/// A number as a user writes it, including `nan`, `inf`, `-inf`; nullopt if malformed.
std::optional<double> number(const std::string& text) {
    if (text.empty()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size()) return std::nullopt;
    return v;
}

std::optional<int> count(const std::string& text) {
    const auto v = number(text);
    if (!v || *v != std::floor(*v) || *v < 1 || *v > 1 << 16) return std::nullopt;
    return static_cast<int>(*v);
}

std::string parse_size(GoldenTest& t, const std::vector<std::string>& specs) {
    if (specs.empty() || specs.size() > 2) return "golden-size wants N, WxH, WxHxD or one WxH and one WxHxD";
    for (const std::string& spec : specs) {
        std::vector<int> n;
        std::size_t at = 0;
        while (true) {
            const std::size_t x = spec.find('x', at);
            const auto c = count(spec.substr(at, x == std::string::npos ? std::string::npos : x - at));
            if (!c) return fmt::format("golden-size: '{}' is not N, WxH or WxHxD (positive node counts)", spec);
            n.push_back(*c);
            // Checked while reading: the product of many components overflows (found by fuzzing).
            if (n.size() > 3)
                return fmt::format("golden-size: '{}' is not N, WxH or WxHxD (at most 3 node counts)", spec);
            if (x == std::string::npos) break;
            at = x + 1;
        }
        long points = 1;
        for (int v : n) points *= v;
        if (n.size() == 1) points *= long(n[0]) * n[0];
        if (points > kMaxGoldenPoints)
            return fmt::format("golden-size: '{}' is too large for a golden test (at most {} points)", spec,
                               kMaxGoldenPoints);
        if (n.size() == 1) {
            t.size_2d = {n[0], n[0]};
            t.size_3d = {n[0], n[0], n[0]};
        } else if (n.size() == 2) {
            t.size_2d = {n[0], n[1]};
        } else {
            t.size_3d = {n[0], n[1], n[2]};
        }
    }
    return "";
}

/// `X Y[ Z]` before the colon of a point directive.
std::optional<std::vector<double>> coordinates(const std::string& text) {
    std::vector<double> point;
    for (const std::string& w : words(text)) {
        const auto v = number(w);
        if (!v || !std::isfinite(*v)) return std::nullopt;
        point.push_back(*v);
    }
    if (point.empty() || point.size() > 3) return std::nullopt;
    return point;
}

std::string parse_point(GoldenTest& t, const std::string& keyword, const std::string& rest, int line) {
    PointExpectation e;
    e.line = line;
    if (keyword == "expect-value") {
        const auto colon = rest.find(':');
        const auto point = colon == std::string::npos ? std::nullopt : coordinates(rest.substr(0, colon));
        if (!point) return "expect-value wants `X Y[ Z]: VALUE [+- TOLERANCE]`";
        e.point = *point;
        const std::vector<std::string> w = words(rest.substr(colon + 1));
        const auto value = w.empty() ? std::nullopt : number(w[0]);
        if (!value || (w.size() != 1 && w.size() != 3) || (w.size() == 3 && w[1] != "+-"))
            return "expect-value wants `X Y[ Z]: VALUE [+- TOLERANCE]`";
        e.value = *value;
        if (w.size() == 3) {
            const auto tol = number(w[2]);
            if (!tol || !(*tol >= 0) || !std::isfinite(*tol))
                return fmt::format("expect-value: the tolerance '{}' is not a non-negative number", w[2]);
            e.tolerance = *tol;
        }
    } else {
        const auto point = coordinates(rest);
        if (!point) return fmt::format("{} wants the coordinates `X Y[ Z]`", keyword);
        e.point = *point;
        e.kind = keyword == "expect-inside"    ? PointExpectation::Kind::Inside
                 : keyword == "expect-outside" ? PointExpectation::Kind::Outside
                                               : PointExpectation::Kind::Boundary;
    }
    t.points.push_back(std::move(e));
    return "";
}

std::string parse_singular(GoldenTest& t, const std::string& rest, int line) {
    SingularExpectation e;
    e.line = line;
    if (rest == "none") {  // the model has no singular point
        t.singular.push_back(std::move(e));
        return "";
    }
    std::string text = rest;
    std::size_t at = 0;
    while ((at = text.find('(', at)) != std::string::npos) {
        const std::size_t close = text.find(')', at);
        if (close == std::string::npos) break;
        std::string inner = text.substr(at + 1, close - at - 1);
        std::replace(inner.begin(), inner.end(), ',', ' ');
        const auto point = coordinates(inner);
        if (!point || point->size() < 2) return "expect-singular wants points `(X, Y[, Z]) ...` or `none`";
        e.points.push_back({(*point)[0], (*point)[1], point->size() == 3 ? (*point)[2] : 0.0});
        text.erase(at, close - at + 1);
    }
    if (e.points.empty() || !trim(text).empty()) return "expect-singular wants points `(X, Y[, Z]) ...` or `none`";
    t.singular.push_back(std::move(e));
    return "";
}

std::string expand_variables(const std::string& text, std::string& error) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text.compare(i, 2, "${") == 0) {
            const std::size_t close = text.find('}', i);
            if (close == std::string::npos) { error = "an unterminated ${"; return ""; }
            const std::string name = text.substr(i + 2, close - i - 2);
            const char* value = std::getenv(name.c_str());
            if (!value || !*value) { error = fmt::format("the environment variable {} is not set", name); return ""; }
            out += value;
            i = close;
        } else {
            out += text[i];
        }
    }
    return out;
}

std::string stem_of(const fs::path& p) { return p.stem().string(); }

std::vector<GoldenTest> manifest_tests(const fs::path& manifest) {
    GoldenTest defaults;
    defaults.name = manifest.lexically_normal().string();
    defaults.script = manifest.string();
    std::ifstream in(manifest, std::ios::binary);
    if (!in) {
        defaults.problems.push_back("cannot read the manifest");
        return {defaults};
    }
    std::vector<std::string> patterns;
    struct ScriptDirective {
        int line;
        std::string stem, directive;
    };
    std::vector<ScriptDirective> per_script;
    int line_no = 0;
    for (std::string line; std::getline(in, line);) {
        ++line_no;
        line = trim(line);
        if (line.empty() || line[0] == '#') continue;
        if (line.rfind("scripts ", 0) == 0) {
            patterns.push_back(trim(line.substr(8)));
            continue;
        }
        // `STEM: DIRECTIVE` applies to one script only.
        const std::size_t colon = line.find(':');
        if (colon != std::string::npos && line.find_first_of(" \t") > colon) {
            per_script.push_back({line_no, line.substr(0, colon), trim(line.substr(colon + 1))});
            continue;
        }
        if (std::string e = apply_directive(defaults, line, line_no); !e.empty())
            defaults.problems.push_back(fmt::format("line {}: {}", line_no, e));
    }
    if (patterns.empty()) defaults.problems.push_back("no `scripts PATTERN` line");
    if (!defaults.problems.empty()) return {defaults};

    std::vector<GoldenTest> tests;
    for (const std::string& raw : patterns) {
        std::string error;
        const std::string pattern = expand_variables(raw, error);
        fs::path full = fs::path(pattern).is_absolute() ? fs::path(pattern) : manifest.parent_path() / pattern;
        const fs::path dir = full.parent_path();
        const std::string glob = full.filename().string();
        std::error_code ec;
        if (error.empty() && !fs::is_directory(dir, ec)) error = fmt::format("'{}' is not a folder", dir.string());
        if (!error.empty()) {
            GoldenTest broken = defaults;
            broken.problems.push_back(fmt::format("scripts {}: {}", raw, error));
            tests.push_back(broken);
            continue;
        }
        std::vector<fs::path> scripts;
        for (const auto& entry : fs::directory_iterator(dir, ec))
            if (entry.is_regular_file() && fnmatch(glob.c_str(), entry.path().filename().c_str(), 0) == 0)
                scripts.push_back(entry.path());
        std::sort(scripts.begin(), scripts.end());
        if (scripts.empty()) {
            GoldenTest broken = defaults;
            broken.problems.push_back(fmt::format("scripts {}: no file matches", raw));
            tests.push_back(broken);
        }
        for (const ScriptDirective& d : per_script)
            if (std::none_of(scripts.begin(), scripts.end(), [&](const fs::path& p) { return stem_of(p) == d.stem; })) {
                GoldenTest broken = defaults;
                broken.problems.push_back(fmt::format("line {}: no script '{}' matches `scripts {}`", d.line, d.stem, raw));
                if (patterns.size() == 1) tests.push_back(broken);
            }
        for (const fs::path& script : scripts) {
            GoldenTest t = defaults;
            for (const ScriptDirective& d : per_script)
                if (d.stem == stem_of(script))
                    if (std::string e = apply_directive(t, d.directive, d.line); !e.empty())
                        t.problems.push_back(fmt::format("{} line {}: {}", manifest.filename().string(), d.line, e));
            t.name = fmt::format("{}:{}", manifest.lexically_normal().string(), stem_of(script));
            t.script = script.string();
            t.expected_stem = (manifest.parent_path() / stem_of(script)).lexically_normal().string();
            std::string read_error;
            if (!read_script_directives(t, read_error)) t.problems.push_back(read_error);
            tests.push_back(std::move(t));
        }
    }
    return tests;
}

GoldenTest script_test(const fs::path& script) {
    GoldenTest t;
    t.name = script.lexically_normal().string();
    t.script = script.string();
    t.expected_stem = (script.parent_path() / stem_of(script)).lexically_normal().string();
    std::string error;
    if (!read_script_directives(t, error)) t.problems.push_back(error);
    return t;
}

}  // namespace

std::vector<const Engine*> golden_both_engines() {
    std::vector<const Engine*> engines{&default_engine()};
    for (const Engine& engine : exact_engines())
        if (&engine != &default_engine()) engines.push_back(&engine);
    return engines;
}

std::optional<std::vector<const Engine*>> parse_golden_engines(const std::string& name) {
    if (name == "both") return golden_both_engines();
    const Engine* engine = find_engine(name);
    if (!engine || !engine->capabilities().exact) return std::nullopt;
    return std::vector{engine};
}

std::string golden_engine_choices(std::string_view separator, std::string_view last_separator) {
    return "both" + std::string(separator) +
           engine_names(separator, last_separator, [](const EngineCapabilities& can) { return can.exact; });
}

std::string apply_directive(GoldenTest& t, const std::string& directive, int line) {
    const std::string text = trim(directive);
    const std::size_t space = text.find_first_of(" \t");
    const std::string keyword = text.substr(0, space);
    const std::string rest = space == std::string::npos ? "" : trim(text.substr(space));
    const std::vector<std::string> args = words(rest);
    if (keyword == "golden-engine") {
        if (args.size() != 1) return "golden-engine wants one of " + golden_engine_choices(", ", ", ");
        if (auto engines = parse_golden_engines(args[0])) t.engines = *engines;
        else return fmt::format("golden-engine: '{}' is not {}", args[0], golden_engine_choices(", ", " or "));
        t.engines_given = true;
        return "";
    }
    if (keyword == "golden-size") return parse_size(t, args);
    if (keyword == "golden-tolerance") {
        const auto v = args.size() == 1 ? number(args[0]) : std::nullopt;
        if (!v || !(*v >= 0) || !std::isfinite(*v)) return "golden-tolerance wants one non-negative number";
        t.tolerance = *v;
        return "";
    }
    if (keyword == "golden-pixel-tolerance") {
        const auto v = args.size() == 1 ? number(args[0]) : std::nullopt;
        if (!v || *v != std::floor(*v) || *v < 0 || *v > 255)
            return "golden-pixel-tolerance wants a whole number of 8-bit levels, 0..255";
        t.pixel_tolerance = static_cast<int>(*v);
        return "";
    }
    if (keyword == "golden-output") {
        const std::string kinds = fmt::format("{}", fmt::join(golden_output_kinds(), ", "));
        if (args.empty()) return fmt::format("golden-output wants one or more of {}", kinds);
        for (const std::string& kind : args) {
            if (!golden_output_format(kind)) return fmt::format("golden-output: '{}' is not one of {}", kind, kinds);
            if (std::find(t.outputs.begin(), t.outputs.end(), kind) == t.outputs.end()) t.outputs.push_back(kind);
        }
        return "";
    }
    if (keyword == "expect-value" || keyword == "expect-inside" || keyword == "expect-outside" ||
        keyword == "expect-boundary")
        return parse_point(t, keyword, rest, line);
    if (keyword == "expect-error") {
        if (rest.empty()) return "expect-error wants `LINE:COLUMN: message`";
        t.errors.push_back({line, rest});
        return "";
    }
    if (keyword == "expect-singular") return parse_singular(t, rest, line);
    return fmt::format("unknown directive '{}'", keyword);
}

bool read_script_directives(GoldenTest& t, std::string& error) {
    std::ifstream in(t.script, std::ios::binary);
    if (!in) {
        error = fmt::format("cannot read '{}'", t.script);
        return false;
    }
    int line_no = 0;
    for (std::string line; std::getline(in, line);) {
        ++line_no;
        const std::string text = trim(line);
        if (text.rfind("//", 0) != 0) continue;
        const std::string body = trim(text.substr(2));
        if (body.rfind("expect-", 0) != 0 && body.rfind("golden-", 0) != 0) continue;
        if (std::string e = apply_directive(t, body, line_no); !e.empty())
            t.problems.push_back(fmt::format("line {}: {}", line_no, e));
    }
    return true;
}

std::vector<GoldenTest> collect_tests(const std::string& path) {
    std::error_code ec;
    const fs::path p(path);
    if (!fs::exists(p, ec)) throw UsageError(fmt::format("'fortu golden': '{}': no such file or folder", path));
    if (!fs::is_directory(p, ec)) {
        if (p.extension() == ".fortu") return {script_test(p)};
        if (p.extension() == ".golden") return manifest_tests(p);
        throw UsageError(fmt::format("'fortu golden': '{}' is neither a .fortu script nor a .golden manifest", path));
    }
    std::vector<fs::path> scripts, manifests;
    for (auto it = fs::recursive_directory_iterator(p, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        if (!it->is_regular_file()) continue;
        if (it->path().extension() == ".fortu") scripts.push_back(it->path());
        if (it->path().extension() == ".golden") manifests.push_back(it->path());
    }
    if (ec) throw UsageError(fmt::format("'fortu golden': cannot list '{}': {}", path, ec.message()));
    std::sort(scripts.begin(), scripts.end());
    std::sort(manifests.begin(), manifests.end());
    std::vector<GoldenTest> tests;
    std::set<fs::path> covered;  // scripts a manifest in the folder already runs
    for (const fs::path& m : manifests)
        for (GoldenTest& t : manifest_tests(m)) {
            covered.insert(fs::weakly_canonical(t.script, ec));
            tests.push_back(std::move(t));
        }
    for (const fs::path& s : scripts)
        if (!covered.count(fs::weakly_canonical(s, ec))) tests.push_back(script_test(s));
    if (tests.empty()) throw UsageError(fmt::format("'fortu golden': no .fortu scripts or .golden manifests in '{}'", path));
    return tests;
}

}  // namespace fortu
