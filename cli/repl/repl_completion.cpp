// cli/repl/repl_completion.cpp — Tab completion's answers (see repl_completion.hpp).
#include "cli/repl/repl_completion.hpp"

#include "interp/engine.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace fortu {
namespace {

/// What a command's arguments are, for completion.
enum class Arguments { None, File, FileAndPicture, Picture, Engine, RSystem };

struct CommandRow {
    const char* name;
    Arguments arguments;
};

/// Every :command (the long spellings; :help lists them).
constexpr CommandRow kCommands[] = {
    {":eval", Arguments::None},    {":show", Arguments::Picture},     {":render", Arguments::FileAndPicture},
    {":domain", Arguments::None},  {":size", Arguments::None},        {":engine", Arguments::Engine},
    {":rsystem", Arguments::RSystem}, {":time", Arguments::None},     {":ir", Arguments::None},
    {":load", Arguments::File},    {":save", Arguments::File},        {":reset", Arguments::None},
    {":help", Arguments::None},    {":quit", Arguments::None},
};

/// The statement keywords of the lexer (grammar/lexer.re), long spellings.
constexpr const char* kKeywords[] = {"ARGUMENT", "CONSTANT", "VARIABLE", "FUNCTION", "RETURN", "RECTANGLE",
                                     "RECTBMP",  "RSYSTEM",  "FOR",      "END",      "INCLUDE"};

/// The built-in functions' spellings (ops.def's FORTU_BUILTIN lines).
constexpr const char* kBuiltins[] = {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr)
#define FORTU_BUILTIN(spelling, name, min_args, max_args) spelling,
#include "interp/ir/ops.def"
#undef FORTU_BUILTIN
#undef FORTU_OP
};

/// The options of :show and :render, and the values they take.
constexpr const char* kPictureOptions[] = {"--slice", "--view", "--up"};
constexpr const char* kViews[] = {"top", "front", "side", "iso"};
constexpr const char* kAxes[] = {"x", "y", "z"};
constexpr const char* kRSystems[] = {"r0", "minmax", "r1", "alpha="};

bool starts_with_ignoring_case(const std::string& word, const std::string& prefix) {
    if (prefix.size() > word.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i)
        if (std::toupper(static_cast<unsigned char>(word[i])) != std::toupper(static_cast<unsigned char>(prefix[i])))
            return false;
    return true;
}

template <typename Range>
void add_matches(std::vector<std::string>& out, const Range& candidates, const std::string& prefix) {
    for (const auto& c : candidates) {
        const std::string word(c);
        if (starts_with_ignoring_case(word, prefix) && std::find(out.begin(), out.end(), word) == out.end())
            out.push_back(word);
    }
}

std::vector<std::string> words_of(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

}  // namespace

std::vector<std::string> repl_command_names() {
    std::vector<std::string> names;
    for (const CommandRow& c : kCommands) names.emplace_back(c.name);
    return names;
}

std::vector<std::string> stdlib_function_names(const std::vector<std::string>& dirs) {
    static const std::regex function("^\\s*FUNCTION\\s+([A-Za-z_][A-Za-z0-9_]*)\\s*\\(", std::regex::icase);
    std::set<std::string> names;
    for (const std::string& dir : dirs) {
        std::error_code ec;
        for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
            if (entry.path().extension() != ".fortu") continue;
            std::ifstream in(entry.path());
            std::smatch m;
            for (std::string line; std::getline(in, line);)
                if (std::regex_search(line, m, function)) names.insert(m[1]);
        }
    }
    return {names.begin(), names.end()};
}

Completion complete_repl_word(const std::string& line, std::size_t start, const std::vector<std::string>& names,
                              const std::vector<std::string>& stdlib_functions) {
    Completion out;
    start = std::min(start, line.size());
    const std::string word = line.substr(start);
    const std::vector<std::string> before = words_of(line.substr(0, start));
    if (before.empty() && word.starts_with(":")) {
        add_matches(out.words, repl_command_names(), word);
        return out;
    }
    if (before.empty() || !before[0].starts_with(":")) {   // FORTU text
        add_matches(out.words, names, word);
        add_matches(out.words, kKeywords, word);
        add_matches(out.words, kBuiltins, word);
        add_matches(out.words, stdlib_functions, word);
        return out;
    }
    const auto row = std::find_if(std::begin(kCommands), std::end(kCommands),
                                  [&](const CommandRow& c) { return before[0] == c.name; });
    if (row == std::end(kCommands)) return out;
    const std::string& previous = before.back();
    switch (row->arguments) {
        case Arguments::None: return out;
        case Arguments::File: out.files = true; return out;
        case Arguments::Engine:
            if (before.size() == 1) {
                std::vector<std::string> engines;   // those :engine offers
                for (const Engine& e : exact_engines()) engines.emplace_back(e.name());
                add_matches(out.words, engines, word);
            }
            return out;
        case Arguments::RSystem:
            if (before.size() == 1) add_matches(out.words, kRSystems, word);
            return out;
        case Arguments::FileAndPicture:
            if (before.size() == 1 && !word.starts_with("-")) { out.files = true; return out; }
            [[fallthrough]];
        case Arguments::Picture:
            if (previous == "--view") add_matches(out.words, kViews, word);
            else if (previous == "--up") add_matches(out.words, kAxes, word);
            else if (previous == "--slice") add_matches(out.words, std::vector<std::string>{"x=", "y=", "z="}, word);
            else add_matches(out.words, kPictureOptions, word);
            return out;
    }
    return out;
}

}  // namespace fortu
