// tests/unit/cli_docs_test.cpp — keeps docs/language.md true: every ```fortu block in it is
// a script that `fortu check` accepts (or rejects with exactly the diagnostics it says), and
// every value it promises (`// eval X Y → V`) is what `fortu eval` prints; and every built-in
// (ops.def's FORTU_BUILTIN lines, lower.cpp's special forms), statement keyword and stdlib
// FUNCTION has an entry there with an example that uses it, and its limits table is limits.def's.
//
// Why: a reference nobody runs drifts from the code; with this test, adding an operation or
// a stdlib function without documenting it, or changing what a documented example gives,
// fails the build's tests. The README and docs/ must also link only to files (and headings)
// that ship.
//
// The expectation comments inside a block:
//   // eval X Y [Z] → V        `fortu eval` prints value V (to 1e-12 relative; nan, inf, -inf exact)
//   // eval X Y [Z] ≈ V        the value rounds to V at the digits V is written with
//   // check L:C: error: MSG   `fortu check` reports exactly this diagnostic (any severity) at
//                             line L, column C of the block; with an error, it exits 1
// The blocks run from a folder holding copies of examples/*.pgm, as if saved in examples/,
// so IMAGE('vyatkin_bumps.pgm') finds the bundled picture; INCLUDE finds the stdlib as any
// script does.
#include "cli_support.hpp"
#include "test_support.hpp"

#include "grammar/diagnostic.hpp"
#include "grammar/parse.hpp"
#include "grammar/source.hpp"
#include "interp/limits.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using fortu::test::quote;
using fortu::test::run_fortu;

namespace {

const std::filesystem::path kSource = FORTU_SOURCE_DIR;
const std::filesystem::path kReference = kSource / "docs" / "language.md";

struct Block {
    int line = 0;        ///< of the opening fence in language.md
    std::string text;
    std::string section; ///< the text from the heading above the block to the next heading
};

struct Heading {
    int line = 0;
    std::string text;    ///< the heading line
    std::string body;    ///< what follows it up to the next heading
};

bool is_heading(const std::string& line) { return !line.empty() && line[0] == '#'; }

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

/// The ```fortu blocks of the reference (fences inside other fences do not occur).
std::vector<Block> fortu_blocks(const std::vector<std::string>& lines) {
    std::vector<Block> blocks;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i] != "```fortu") continue;
        Block b;
        b.line = static_cast<int>(i) + 1;
        for (++i; i < lines.size() && lines[i] != "```"; ++i) b.text += lines[i] + "\n";
        blocks.push_back(std::move(b));
    }
    return blocks;
}

std::vector<Heading> headings(const std::vector<std::string>& lines) {
    std::vector<Heading> out;
    bool in_fence = false;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i].rfind("```", 0) == 0) in_fence = !in_fence;
        if (!in_fence && is_heading(lines[i])) {
            out.push_back({static_cast<int>(i) + 1, lines[i], {}});
        } else if (!out.empty()) {
            out.back().body += lines[i] + "\n";
        }
    }
    return out;
}

bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// `name` occurs in `text` as a whole word (upper case as written in the reference).
bool uses_word(const std::string& text, const std::string& name) {
    for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
        const bool starts = at == 0 || !is_name_char(text[at - 1]);
        const bool ends = at + name.size() >= text.size() || !is_name_char(text[at + name.size()]);
        if (starts && ends) return true;
    }
    return false;
}

/// The heading that documents `name`: one whose text shows it in code (`NAME(`, `NAME` or
/// `NAME followed by more), followed by a ```fortu example using it. "" when there is one,
/// else what is missing.
std::string entry_problem(const std::vector<Heading>& all, const std::string& name) {
    std::string problem = "no heading of docs/language.md shows `" + name + "(...)` or `" + name + "`";
    for (const Heading& h : all) {
        const bool shows = h.text.find("`" + name + "(") != std::string::npos ||
                           h.text.find("`" + name + "`") != std::string::npos ||
                           h.text.find("`" + name + " ") != std::string::npos;
        if (!shows) continue;
        for (const Block& b : fortu_blocks(lines_of(h.body)))
            if (uses_word(b.text, name)) return "";
        problem = "the heading at docs/language.md:" + std::to_string(h.line) + " has no ```fortu example using " + name;
    }
    return problem;
}

std::string trim(std::string s) {
    const auto first = s.find_first_not_of(" \t");
    const auto last = s.find_last_not_of(" \t\r");
    return first == std::string::npos ? "" : s.substr(first, last - first + 1);
}

/// The value `fortu eval` printed (its `value: ` line).
bool printed_value(const std::string& out, double& value) {
    const auto at = out.find("value: ");
    if (at == std::string::npos) return false;
    const std::string text = out.substr(at + 7, out.find('\n', at) - at - 7);
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    return end != text.c_str();
}

/// Half a unit in the last digit `text` is written with (0.4452 → 0.00005).
double rounding_of(const std::string& text) {
    const std::string mantissa = text.substr(0, text.find_first_of("eE"));
    const int exponent = mantissa.size() == text.size() ? 0 : std::atoi(text.c_str() + mantissa.size() + 1);
    const auto dot = mantissa.find('.');
    const int decimals = dot == std::string::npos ? 0 : static_cast<int>(mantissa.size() - dot - 1);
    return 0.5 * std::pow(10.0, exponent - decimals);
}

void check_value(const std::string& where, double got, const std::string& expected_text, bool approximate) {
    INFO(where);
    const double expected = std::strtod(expected_text.c_str(), nullptr);
    if (std::isnan(expected)) {
        CHECK(std::isnan(got));
    } else if (std::isinf(expected)) {
        CHECK(got == expected);
    } else if (approximate) {
        CHECK(std::abs(got - expected) <= rounding_of(expected_text) * (1 + 1e-9));
    } else {
        CHECK(std::abs(got - expected) <= 1e-12 * std::max(1.0, std::abs(expected)));
    }
}

void run_block(const Block& block, const fortu::test::ScratchDir& dir) {
    const std::string where = "docs/language.md:" + std::to_string(block.line);
    const std::string file = "block_" + std::to_string(block.line) + ".fortu";
    dir.write(file, block.text);
    std::vector<std::string> diagnostics;
    bool expects_error = false;
    std::vector<std::string> evals;
    for (const std::string& raw : lines_of(block.text)) {
        const auto comment = raw.find("// ");
        if (comment == std::string::npos) continue;
        const std::string c = raw.substr(comment + 3);
        if (c.rfind("check ", 0) == 0) {
            diagnostics.push_back(file + ":" + trim(c.substr(6)));
            expects_error = expects_error || c.find(": error: ") != std::string::npos;
        } else if (c.rfind("eval ", 0) == 0) {
            evals.push_back(trim(c.substr(5)));
        }
    }
    const fortu::test::CommandResult check = run_fortu("check " + quote(file), dir.path.string());
    {
        INFO(where << ": fortu check printed\n" << check.out);
        CHECK(check.status == (expects_error ? 1 : 0));
        for (const std::string& d : diagnostics) CHECK(check.out.find(d) != std::string::npos);
    }
    for (const std::string& e : evals) {
        const bool approximate = e.find("≈") != std::string::npos;
        const std::string arrow = approximate ? "≈" : "→";
        const auto at = e.find(arrow);
        REQUIRE_MESSAGE(at != std::string::npos, where << ": '// eval " << e << "' needs → or ≈ and a value");
        const std::string point = trim(e.substr(0, at));
        const std::string expected = trim(e.substr(at + arrow.size()));
        const fortu::test::CommandResult r = run_fortu("eval " + quote(file) + " " + point, dir.path.string(), true);
        double got = 0;
        INFO(where << ": fortu eval " << point << " printed\n" << r.out);
        REQUIRE(printed_value(r.out, got));
        check_value(where + ": eval " + point, got, expected, approximate);
    }
}

/// The names ops.def gives FORTU's built-in functions.
std::set<std::string> builtin_spellings() {
    std::set<std::string> names;
#define FORTU_BUILTIN(spelling, name, min_args, max_args) names.insert(spelling);
#include "interp/ir/ops.def"
    return names;
}

/// Every FUNCTION the stdlib's files define, read by the grammar itself.
std::vector<std::string> stdlib_functions() {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(kSource / "stdlib")) {
        if (entry.path().extension() != ".fortu") continue;
        std::string error;
        const auto source = fortu::SourceFile::load(entry.path().string(), error);
        REQUIRE_MESSAGE(source, error);
        fortu::DiagnosticSink sink;
        const fortu::ast::Script script = fortu::parse_script(*source, sink);
        REQUIRE_MESSAGE(!sink.has_errors(), sink.render_all());
        for (const fortu::ast::Statement& s : script.statements)
            if (const auto* f = std::get_if<fortu::ast::FunctionDef>(&s.node)) names.push_back(f->name);
    }
    return names;
}

/// GitHub's anchor for a heading: lower case, ASCII letters, digits, '-' and '_' kept, spaces
/// to '-', everything else dropped.
std::string anchor_of(const std::string& heading) {
    std::string out;
    const std::size_t text = heading.find_first_not_of("# ");
    for (std::size_t i = text == std::string::npos ? heading.size() : text; i < heading.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(heading[i]);
        if (c == ' ') out += '-';
        else if (c < 0x80 && (std::isalnum(c) || c == '-' || c == '_')) out += static_cast<char>(std::tolower(c));
    }
    while (!out.empty() && out.back() == '-') out.pop_back();
    return out;
}

/// The anchors a Markdown file offers: its headings' and its `<a id="...">`s.
std::set<std::string> anchors_in(const std::filesystem::path& file) {
    std::set<std::string> anchors;
    const std::string text = fortu::test::read_file(file);
    for (const Heading& h : headings(lines_of(text))) anchors.insert(anchor_of(h.text));
    const std::regex id("<a id=\"([^\"]+)\">");
    for (auto m = std::sregex_iterator(text.begin(), text.end(), id); m != std::sregex_iterator(); ++m)
        anchors.insert((*m)[1]);
    return anchors;
}

/// The relative links `[text](target)` of a Markdown file outside code blocks that name no
/// file or heading of the repository.
std::vector<std::string> broken_links(const std::filesystem::path& file) {
    std::string prose;
    bool in_fence = false;
    for (const std::string& line : lines_of(fortu::test::read_file(file))) {
        if (line.rfind("```", 0) == 0) in_fence = !in_fence;
        else if (!in_fence) prose += line + "\n";
    }
    std::vector<std::string> broken;
    const std::regex link("\\]\\(([^)\\s]+)\\)");
    for (auto m = std::sregex_iterator(prose.begin(), prose.end(), link); m != std::sregex_iterator(); ++m) {
        const std::string target = (*m)[1];
        if (std::regex_search(target, std::regex("^[a-z]+:"))) continue;   // https:, mailto:
        const std::string path = target.substr(0, target.find('#'));
        const std::string anchor = target.find('#') == std::string::npos ? "" : target.substr(target.find('#') + 1);
        const std::filesystem::path named = path.empty() ? file : file.parent_path() / path;
        if (!std::filesystem::exists(named)) broken.push_back(target + " (no such file)");
        else if (!anchor.empty() && named.extension() == ".md" && !anchors_in(named).count(anchor))
            broken.push_back(target + " (no such heading)");
    }
    return broken;
}

}  // namespace

TEST_CASE("docs: the README and docs/ link only to files and headings that ship") {
    for (const char* name : {"README.md", "docs/language.md", "docs/fv-method.md", "docs/design.md",
                             "docs/meshing.md", "examples/README.md", "bench/README.md"}) {
        INFO(name);
        std::string broken;
        for (const std::string& link : broken_links(kSource / name)) broken += link + "; ";
        CHECK(broken == "");
    }
    CHECK(anchor_of("### `a & b` (R-conjunction) and `a | b` (R-disjunction)") == "a--b-r-conjunction-and-a--b-r-disjunction");
    CHECK(anchor_of("## §1 The FV model: M-images") == "1-the-fv-model-m-images");
}

TEST_CASE("docs: every ```fortu example in docs/language.md runs and gives the value it says") {
    const std::string text = fortu::test::read_file(kReference);
    REQUIRE_MESSAGE(!text.empty(), "cannot read " << kReference);
    const std::vector<Block> blocks = fortu_blocks(lines_of(text));
    CHECK(blocks.size() >= 90);
    fortu::test::ScratchDir dir;
    for (const auto& entry : std::filesystem::directory_iterator(kSource / "examples"))
        if (entry.path().extension() == ".pgm")
            std::filesystem::copy_file(entry.path(), dir.path / entry.path().filename());
    std::size_t with_values = 0;
    for (const Block& block : blocks) {
        with_values += block.text.find("// eval ") != std::string::npos;
        run_block(block, dir);
    }
    CHECK(2 * with_values >= blocks.size());   // most examples promise a value, not only that they parse
}

TEST_CASE("docs: every built-in, statement and stdlib function has an entry with an example") {
    const std::vector<Heading> all = headings(lines_of(fortu::test::read_file(kReference)));
    REQUIRE(!all.empty());
    const std::set<std::string> builtins = builtin_spellings();
    std::vector<std::string> names(builtins.begin(), builtins.end());
    // lower.cpp's special forms: names it resolves itself, not operations of ops.def.
    for (const char* special : {"PI", "IMAGE", "IMAGE_WIDTH", "IMAGE_HEIGHT"}) names.push_back(special);
    // The statements (lexer.re's keywords, with their abbreviations).
    for (const char* keyword : {"ARGUMENT", "CONSTANT", "VARIABLE", "FUNCTION", "RETURN", "RECTANGLE", "RECTBMP",
                                "RSYSTEM", "FOR", "INCLUDE"})
        names.push_back(keyword);
    // The limits' table is the generated one (interp/limits.def), as in --help.
    CHECK(fortu::test::read_file(kReference).find("```\n" + fortu::limits_usage(0) + "\n```\n") != std::string::npos);
    const std::vector<std::string> library = stdlib_functions();
    CHECK(library.size() >= 50);
    names.insert(names.end(), library.begin(), library.end());
    for (const std::string& name : names) {
        INFO(name);
        CHECK(entry_problem(all, name) == "");
    }
}

TEST_CASE("docs: the entry check finds a missing entry or example") {
    // The two rules above must be able to fail.
    const std::vector<Heading> all = headings(lines_of("# `SQRT(x)`\n```fortu\nRETURN SQRT(X)\n```\n# `ABS(x)`\ntext\n"));
    CHECK(entry_problem(all, "SQRT") == "");
    CHECK(entry_problem(all, "ABS") == "the heading at docs/language.md:5 has no ```fortu example using ABS");
    CHECK(entry_problem(all, "EXP") == "no heading of docs/language.md shows `EXP(...)` or `EXP`");
    CHECK_FALSE(uses_word("RETURN HEIGHTMAP_H(X)", "HAT"));
    CHECK(rounding_of("0.4452") == doctest::Approx(0.00005));
    CHECK(rounding_of("2") == 0.5);
    CHECK(rounding_of("1.5e-3") == doctest::Approx(0.00005));
}
