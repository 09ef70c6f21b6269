// grammar/domain_comment.cpp — a small hand scanner for the header comment's axis entries;
// the re2c lexer drops comments, and the entries are not FORTU syntax (decimal commas).
#include "grammar/domain_comment.hpp"

#include <cctype>
#include <string>
#include <string_view>
#include <vector>

namespace fortu {
namespace {

struct Entry {
    int axis = 0;
    bool is_range = false;
    double a = 0, b = 0;   ///< half-extent in a, or the range [a, b]
};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

void skip_spaces(std::string_view s, std::size_t& i) {
    while (i < s.size() && is_space(s[i])) ++i;
}

/// A number with `.` or `,` as the decimal point ("3,5" = 3.5); the comma counts only when a
/// digit follows it, so "x=8, y=5" is two entries.
std::optional<double> read_number(std::string_view s, std::size_t& i) {
    std::string text;
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) text += s[i++];
    const std::size_t digits_start = i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) text += s[i++];
    if (i + 1 < s.size() && (s[i] == '.' || s[i] == ',') && std::isdigit(static_cast<unsigned char>(s[i + 1]))) {
        text += '.';
        ++i;
        while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) text += s[i++];
    }
    if (i == digits_start) return std::nullopt;
    return std::stod(text);
}

/// The entries of one comment's text, or nullopt when it holds anything else.
std::optional<std::vector<Entry>> read_entries(std::string_view s) {
    std::vector<Entry> entries;
    std::size_t i = 0;
    for (;;) {
        while (i < s.size() && (is_space(s[i]) || s[i] == ',' || s[i] == ';')) ++i;
        if (i == s.size()) break;
        const char letter = static_cast<char>(std::tolower(static_cast<unsigned char>(s[i])));
        if (letter < 'x' || letter > 'z') return std::nullopt;
        Entry e;
        e.axis = letter - 'x';
        ++i;
        skip_spaces(s, i);
        if (i == s.size() || (s[i] != '=' && s[i] != ':')) return std::nullopt;
        ++i;
        skip_spaces(s, i);
        if (i < s.size() && s[i] == '[') {
            ++i;
            skip_spaces(s, i);
            const auto lo = read_number(s, i);
            skip_spaces(s, i);
            if (!lo || i == s.size() || s[i] != ';') return std::nullopt;
            ++i;
            skip_spaces(s, i);
            const auto hi = read_number(s, i);
            skip_spaces(s, i);
            if (!hi || i == s.size() || s[i] != ']') return std::nullopt;
            ++i;
            e.is_range = true;
            e.a = *lo;
            e.b = *hi;
        } else {
            const auto v = read_number(s, i);
            if (!v) return std::nullopt;
            e.a = *v;
        }
        entries.push_back(e);
    }
    if (entries.empty()) return std::nullopt;
    return entries;
}

/// True for a line that starts with the ARGUMENT statement (or its short form ARG).
bool is_argument_line(std::string_view line) {
    std::size_t i = 0;
    skip_spaces(line, i);
    std::string word;
    while (i < line.size() && std::isalpha(static_cast<unsigned char>(line[i])))
        word += static_cast<char>(std::toupper(static_cast<unsigned char>(line[i++])));
    return word == "ARGUMENT" || word == "ARG";
}

}  // namespace

std::optional<DomainComment> read_domain_comment(const SourceFile& source) {
    // Per axis: the first list's entry, then the second list's (the centre).
    std::array<std::optional<Entry>, 3> extent, centre;
    DomainComment found;
    bool any = false;
    for (int n = 1; n <= source.line_count(); ++n) {
        std::string_view line = source.line(n);
        std::size_t i = 0;
        skip_spaces(line, i);
        if (i == line.size()) continue;
        if (line.substr(i, 2) != "//") {
            if (is_argument_line(line)) continue;
            break;   // the first statement: the header is over
        }
        const std::optional<std::vector<Entry>> entries = read_entries(line.substr(i + 2));
        if (!entries) continue;
        if (!any) found.where = {&source, {n, static_cast<int>(i) + 1}, {n, static_cast<int>(line.size()) + 1}};
        any = true;
        for (const Entry& e : *entries) {
            if (!extent[e.axis]) extent[e.axis] = e;
            else if (!centre[e.axis] && !e.is_range && !extent[e.axis]->is_range) centre[e.axis] = e;
        }
    }
    if (!any) return std::nullopt;
    for (int a = 0; a < 3; ++a) {
        if (!extent[a]) continue;
        const Entry& e = *extent[a];
        if (e.is_range) {
            if (!(e.a < e.b)) return std::nullopt;
            found.ranges[a] = std::array<double, 2>{e.a, e.b};
        } else {
            if (!(e.a > 0)) return std::nullopt;
            const double c = centre[a] ? centre[a]->a : 0.0;
            found.ranges[a] = std::array<double, 2>{c - e.a, c + e.a};
        }
    }
    return found;
}

}  // namespace fortu
