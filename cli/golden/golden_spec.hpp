// cli/golden/golden_spec.hpp — what a golden test expects, read from the directives in its script's
// comments (`// expect-value 0.25 0.5: 0.734 +- 1e-9`) or in a manifest (`NAME.golden`), and
// which tests a list of paths names. The syntax is documented in the README ("Golden tests").
#pragma once

#include "interp/engine.hpp"

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fortu {

/// One `// expect-...` directive about the model's value at a point.
struct PointExpectation {
    enum class Kind { Value, Inside, Outside, Boundary };
    Kind kind = Kind::Value;
    int line = 0;                       ///< 1-based line of the directive in the script
    std::vector<double> point;          ///< one coordinate per model argument
    double value = 0.0;                 ///< Kind::Value
    std::optional<double> tolerance;    ///< `+- T`; else the test's tolerance
};

/// `// expect-error L:C: message` — one error diagnostic of the compile, in order.
struct ErrorExpectation {
    int line = 0;          ///< the directive's line
    std::string text;      ///< `L:C: message` as written
};

/// `// expect-singular (x, y) ...` or `// expect-singular none`: together, the lines list every
/// singular point `fortu singular` finds.
struct SingularExpectation {
    int line = 0;
    std::vector<std::array<double, 3>> points;
};

/// `golden-engine both`: the engines whose values must agree (EngineCapabilities::exact),
/// the default engine first (its output is what --update writes).
std::vector<const Engine*> golden_both_engines();
/// What golden-engine and `fortu golden --engine` take: "both" or an exact engine's name.
std::optional<std::vector<const Engine*>> parse_golden_engines(const std::string& name);
/// Those names, `separator` between them and `last_separator` before the last:
/// "both, classic or voxel", "both|classic|voxel".
std::string golden_engine_choices(std::string_view separator, std::string_view last_separator);

/// One golden test: a script plus what it must produce.
struct GoldenTest {
    std::string name;          ///< as printed: the script path, or MANIFEST:STEM
    std::string script;        ///< the .fortu file run
    std::string expected_stem; ///< NAME.expected.EXT and NAME.diff.EXT live at this stem + ".expected.EXT"
    std::vector<std::string> problems;  ///< malformed directives: the test fails with these

    std::vector<const Engine*> engines = golden_both_engines();
    bool engines_given = false;
    std::optional<std::array<int, 2>> size_2d;   ///< `golden-size WxH`
    std::optional<std::array<int, 3>> size_3d;   ///< `golden-size WxHxD`
    double tolerance = 1e-9;                     ///< values, npy, csv, svg, exr
    int pixel_tolerance = 0;                     ///< 8-bit levels, png
    std::vector<std::string> outputs;            ///< `golden-output` kinds (created by --update)

    std::vector<PointExpectation> points;
    std::vector<ErrorExpectation> errors;
    std::vector<SingularExpectation> singular;
};

/// Applies one directive (the text after `//`, e.g. `golden-size 64x64`) to `test`;
/// returns an error text for a malformed or unknown one, "" when it applied.
std::string apply_directive(GoldenTest& test, const std::string& directive, int line);

/// Reads the inline directives of `test.script` into `test` (problems go to test.problems).
/// Returns false and sets `error` if the script cannot be read.
bool read_script_directives(GoldenTest& test, std::string& error);

/// The tests a command-line path names: a .fortu script, a .golden manifest, or a folder
/// searched recursively for both (sorted by path). Throws UsageError for a path that does not
/// exist or a folder without tests. A manifest that cannot be used becomes one test whose
/// problems say why.
std::vector<GoldenTest> collect_tests(const std::string& path);

}  // namespace fortu
