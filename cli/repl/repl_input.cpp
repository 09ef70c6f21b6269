// cli/repl/repl_input.cpp — line input for `fortu repl` through libedit's readline interface.
// History problems (no HOME, unwritable file) are never errors: the session just has none.
#include "cli/repl/repl_input.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>

#include <editline/readline.h>

namespace fortu {
namespace {

constexpr int kHistoryLines = 1000;

/// libedit calls plain functions: the completer of the one interactive reader, and the
/// words of the completion in progress.
LineReader::Completer* g_completer = nullptr;
std::vector<std::string> g_matches;

char* next_match(const char*, int state) {
    static std::size_t next = 0;
    if (state == 0) next = 0;
    return next < g_matches.size() ? strdup(g_matches[next++].c_str()) : nullptr;
}

char** complete(const char* text, int start, int end) {
    rl_attempted_completion_over = 1;   // no file names unless the completer asks for them
    if (!g_completer || !rl_line_buffer) return nullptr;
    const std::string line(rl_line_buffer, std::size_t(std::max(end, 0)));
    const Completion c = (*g_completer)(line, std::size_t(std::max(start, 0)));
    if (c.files) return rl_completion_matches(text, rl_filename_completion_function);
    g_matches = c.words;
    if (g_matches.empty()) return nullptr;
    return rl_completion_matches(text, next_match);
}

std::string upper_word(const std::string& text, std::size_t& i) {
    std::string word;
    while (i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_'))
        word += static_cast<char>(std::toupper(static_cast<unsigned char>(text[i++])));
    return word;
}

}  // namespace

std::string default_history_path() {
    const char* home = std::getenv("HOME");
    if (!home || !*home) return {};
    return std::string(home) + "/.fortu_history";
}

bool input_incomplete(const std::string& text) {
    int depth = 0;
    std::string previous, before_previous;
    for (std::size_t i = 0; i < text.size();) {
        const char c = text[i];
        if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
            while (i < text.size() && text[i] != '\n') ++i;
        } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
            const std::size_t end = text.find("*/", i + 2);
            i = end == std::string::npos ? text.size() : end + 2;
        } else if (c == '\'' || c == '"') {
            const std::size_t end = text.find(c, i + 1);
            i = end == std::string::npos ? text.size() : end + 1;
        } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
            const std::string word = upper_word(text, i);
            if (word == "END") --depth;
            else if (word == "FOR" && previous != "END") ++depth;
            before_previous = previous;
            previous = word;
        } else {
            // FUNCTION NAME( opens a block; FUNCTION NAME = expr is a one-line variable.
            if (c == '(' && before_previous == "FUNCTION") ++depth;
            if (!std::isspace(static_cast<unsigned char>(c))) before_previous = previous = "";
            ++i;
        }
    }
    return depth > 0;
}

LineReader::LineReader(bool interactive, std::string history_path)
    : interactive_(interactive), history_path_(std::move(history_path)) {
    if (!interactive_) return;
    using_history();
    stifle_history(kHistoryLines);
    if (!history_path_.empty()) read_history(history_path_.c_str());
}

LineReader::~LineReader() {
    if (interactive_) rl_attempted_completion_function = nullptr;
    g_completer = nullptr;
}

void LineReader::set_completer(Completer completer) {
    if (!interactive_) return;
    completer_ = std::move(completer);
    g_completer = &completer_;
    rl_attempted_completion_function = complete;
    // Words end at blanks and FORTU's operators; ':', '/' and '-' stay in (commands, paths, --options).
    static char breaks[] = " \t\n\"'(),=+*^&|!<>;";
    rl_completer_word_break_characters = breaks;
    rl_basic_word_break_characters = breaks;
}

std::optional<std::string> LineReader::read(const std::string& prompt) {
    if (!interactive_) {
        std::string line;
        if (!std::getline(std::cin, line)) return std::nullopt;
        return line;
    }
    char* raw = readline(prompt.c_str());
    if (!raw) return std::nullopt;
    std::string line(raw);
    std::free(raw);
    if (line.find_first_not_of(" \t") != std::string::npos) {
        add_history(line.c_str());
        // Written at once, so a session that is killed keeps its history; failures are ignored.
        if (!history_path_.empty()) write_history(history_path_.c_str());
    }
    return line;
}

}  // namespace fortu
