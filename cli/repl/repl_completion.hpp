// cli/repl/repl_completion.hpp — what Tab completes in `fortu repl`: the :commands, their
// arguments (engines, R-systems, --slice/--view values, file names after :load, :save and
// :render), and in FORTU text the session's names, the keywords, the built-in functions and
// the stdlib's FUNCTIONs.
//
// Why apart from the line editor: deciding what a word can become is plain string work that
// tests can check exactly; repl_input.cpp only hands libedit the answer.
#pragma once

#include <string>
#include <vector>

namespace fortu {

/// The completions of the word that starts at `start` of `line` (the line up to the cursor).
struct Completion {
    bool files = false;               ///< complete a file name (libedit does it)
    std::vector<std::string> words;   ///< else these, in order, each starting with the word
};

/// `names`: the session's definitions, FUNCTIONs and arguments (completed in FORTU text
/// beside the keywords, built-ins and `stdlib_functions`).
Completion complete_repl_word(const std::string& line, std::size_t start, const std::vector<std::string>& names,
                              const std::vector<std::string>& stdlib_functions);

/// The FUNCTION names defined in the .fortu files of `dirs` (the stdlib), sorted, unique.
std::vector<std::string> stdlib_function_names(const std::vector<std::string>& dirs);

/// The REPL's commands, as typed (":render", ...).
std::vector<std::string> repl_command_names();

}  // namespace fortu
