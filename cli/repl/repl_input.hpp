// cli/repl/repl_input.hpp — reading `fortu repl` input: libedit line editing with a persistent
// history on a terminal, plain lines otherwise (so scripted sessions are deterministic), and
// the rule for when a multi-line block (FUNCTION ... END, FOR ... END FOR) is complete.
#pragma once

#include "cli/repl/repl_completion.hpp"

#include <functional>
#include <optional>
#include <string>

namespace fortu {

/// `$HOME/.fortu_history`, or "" (no history) when HOME is unset or empty.
std::string default_history_path();

/// True while `text` opens more FOR / FUNCTION NAME( blocks than it closes with END, so the
/// REPL should read another line before submitting it. Comments are skipped.
bool input_incomplete(const std::string& text);

/// The source of input lines: libedit on a terminal, std::cin otherwise.
class LineReader {
public:
    /// interactive: libedit with `history_path` loaded and appended to ("" for none); else
    /// std::cin, no prompt.
    LineReader(bool interactive, std::string history_path);
    LineReader(const LineReader&) = delete;
    LineReader& operator=(const LineReader&) = delete;

    /// The next line without its newline, or nullopt at end of input (or, interactively, when
    /// line editing was interrupted: the caller tells the two apart by its SIGINT flag).
    std::optional<std::string> read(const std::string& prompt);
    bool interactive() const { return interactive_; }

    /// What Tab completes: given the line up to the cursor and where the word being completed
    /// starts. One reader at a time owns libedit's completion (it is process-wide).
    using Completer = std::function<Completion(const std::string& line, std::size_t word_start)>;
    void set_completer(Completer completer);
    ~LineReader();

private:
    bool interactive_;
    std::string history_path_;
    Completer completer_;
};

}  // namespace fortu
