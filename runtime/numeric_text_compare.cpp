// runtime/numeric_text_compare.cpp — see numeric_text_compare.hpp.
#include "runtime/numeric_text_compare.hpp"

#include "runtime/resources.hpp"
#include "runtime/value_compare.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <vector>

namespace fortu {
namespace {

/// A text cut into the numbers in it and the text between them.
struct Tokens {
    std::vector<std::string> text;   ///< text[i] precedes numbers[i]; one more text than numbers
    std::vector<double> numbers;
    std::vector<int> lines;          ///< the line of each number
};

Tokens tokenize(const std::string& s) {
    Tokens t;
    t.text.emplace_back();
    int line = 1;
    for (std::size_t i = 0; i < s.size();) {
        const char c = s[i];
        const bool sign = (c == '-' || c == '+' || c == '.') && i + 1 < s.size() &&
                          (std::isdigit(static_cast<unsigned char>(s[i + 1])) ||
                           (s[i + 1] == '.' && i + 2 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 2]))));
        const bool starts = std::isdigit(static_cast<unsigned char>(c)) || sign;
        const bool after_word = i > 0 && (std::isalpha(static_cast<unsigned char>(s[i - 1])) || s[i - 1] == '_');
        if (starts && !after_word) {
            char* end = nullptr;
            const double v = std::strtod(s.c_str() + i, &end);
            const std::size_t used = static_cast<std::size_t>(end - (s.c_str() + i));
            if (used > 0) {
                t.numbers.push_back(v);
                t.lines.push_back(line);
                t.text.emplace_back();
                i += used;
                continue;
            }
        }
        if (c == '\n') ++line;
        t.text.back() += c;
        ++i;
    }
    return t;
}

std::string line_of(const std::string& s, int line) {
    std::size_t at = 0;
    for (int l = 1; l < line && at != std::string::npos; ++l) {
        at = s.find('\n', at);
        if (at != std::string::npos) ++at;
    }
    if (at == std::string::npos) return "";
    const std::size_t end = s.find('\n', at);
    std::string text = s.substr(at, end == std::string::npos ? std::string::npos : end - at);
    if (text.size() > 120) text = text.substr(0, 117) + "...";
    return text;
}

}  // namespace

OutputComparison compare_numeric_text(const ComparedOutput& compared) {
    const std::string& expected_path = compared.expected_path;
    const std::string& actual_path = compared.actual_path;
    const double tolerance = compared.tolerance;
    const auto expected = read_file_bytes(expected_path);
    if (!expected) return {fmt::format("cannot read '{}'", expected_path)};
    const auto actual = read_file_bytes(actual_path);
    if (!actual) return {fmt::format("cannot read the new output '{}'", actual_path)};
    const Tokens a = tokenize(*expected), b = tokenize(*actual);
    // The text between numbers first: a different structure makes number matching meaningless.
    const std::size_t n = std::min(a.text.size(), b.text.size());
    std::size_t i = 0;
    while (i < n && a.text[i] == b.text[i]) ++i;
    if (i < n || a.text.size() != b.text.size()) {
        const int line = i == 0 ? 1 : i - 1 < a.lines.size() ? a.lines[i - 1] : b.lines[i - 1];
        return {fmt::format("the text differs on line {}:\n  expected: {}\n  actual:   {}", line,
                            line_of(*expected, line), line_of(*actual, line))};
    }
    std::size_t failing = 0, worst = 0;
    double worst_distance = -1;
    for (std::size_t i = 0; i < a.numbers.size(); ++i) {
        if (values_agree(a.numbers[i], b.numbers[i], tolerance)) continue;
        ++failing;
        const double d = value_distance(a.numbers[i], b.numbers[i]);
        if (d > worst_distance) { worst_distance = d; worst = i; }
    }
    if (failing == 0) return {};
    const int line = a.lines[worst];
    return {fmt::format("{} of {} numbers differ by more than {}; worst on line {}: expected {}, got {}\n"
                        "  expected: {}\n  actual:   {}",
                        format_count(failing), format_count(a.numbers.size()), tolerance, line, a.numbers[worst],
                        b.numbers[worst], line_of(*expected, line), line_of(*actual, b.lines[worst]))};
}

}  // namespace fortu
