// cli/option_table.hpp — one command's options as a table: names, value, help, and what a
// given value does. Every `fortu` command (run, eval, check, ir, singular, bench, golden,
// repl) declares its options this way; CLI11 splits the command line (`--size 100` and
// `--size=100`, values that look like negative numbers), the table applies the values in
// the order given and writes the command's --help.
//
// Why one table rather than a parser per command: the options, their help and their errors
// cannot drift apart, and every command answers --help and an unknown option the same way.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace fortu {

/// A usage error: printed as `fortu: error: MESSAGE` with exit status 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// An option's value cut at every `separator` ("1,2,3" -> 1 2 3; empty parts kept, so a
/// stray separator is reported by whoever reads the parts).
std::vector<std::string> split_value(const std::string& value, char separator);

class OptionTable {
public:
    /// `command`: "run", "bench"... (for `see fortu COMMAND --help`); `usage`: the text --help
    /// prints before the options.
    OptionTable(std::string command, std::string usage);

    /// An option without a value. `names`: "--stats" or "-o,--output".
    OptionTable& flag(const std::string& names, const std::string& help, std::function<void()> apply);
    /// An option with one value (`--size 100` or `--size=100`); `apply` throws UsageError for a bad one.
    OptionTable& option(const std::string& names, const std::string& value_name, const std::string& help,
                        std::function<void(const std::string& value)> apply);
    /// Where the arguments that are not options go, in order.
    OptionTable& positionals(std::vector<std::string>& into);

    /// Parses `args` (after the command's name) and applies the options in the order given.
    /// Returns false when --help (or -h) was given: nothing is applied, print help().
    /// Throws UsageError: an unknown option (with `see fortu COMMAND --help`), a missing value,
    /// or what an option's `apply` throws.
    bool parse(const std::vector<std::string>& args) const;

    /// The usage text, then options_help().
    std::string help() const;
    /// "options:" and one line per option (help text continuing on indented lines).
    std::string options_help() const;

private:
    struct Row {
        std::string names, value_name, help;
        std::function<void(const std::string&)> apply;   ///< flags: called with ""
    };
    std::string command_, usage_;
    std::vector<Row> rows_;
    std::vector<std::string>* positionals_ = nullptr;
};

}  // namespace fortu
