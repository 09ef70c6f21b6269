// cli/option_table.cpp — OptionTable on CLI11: CLI11 classifies the arguments, the rows'
// own functions check and apply the values, so messages stay ours.
#include "cli/option_table.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace fortu {

OptionTable::OptionTable(std::string command, std::string usage) : command_(std::move(command)), usage_(std::move(usage)) {}

OptionTable& OptionTable::flag(const std::string& names, const std::string& help, std::function<void()> apply) {
    rows_.push_back({names, "", help, [apply = std::move(apply)](const std::string&) { apply(); }});
    return *this;
}

OptionTable& OptionTable::option(const std::string& names, const std::string& value_name, const std::string& help,
                                 std::function<void(const std::string&)> apply) {
    rows_.push_back({names, value_name, help, std::move(apply)});
    return *this;
}

OptionTable& OptionTable::positionals(std::vector<std::string>& into) {
    positionals_ = &into;
    return *this;
}

bool OptionTable::parse(const std::vector<std::string>& args) const {
    CLI::App app;
    app.set_help_flag();        // --help is ours: a row-less flag answered below
    app.allow_extras();         // unknown options are reported by us, one line, with the hint
    bool help = false;
    app.add_flag("-h,--help", help);
    std::map<const CLI::Option*, const Row*> row_of;
    for (const Row& row : rows_) {
        CLI::Option* option = row.value_name.empty() ? app.add_flag(row.names)
                                                     : app.add_option(row.names)->expected(1);
        option->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
        row_of[option] = &row;
    }
    std::vector<std::string> positional;
    app.add_option("arguments", positional);

    std::vector<std::string> reversed(args.rbegin(), args.rend());   // CLI11 reads from the back
    try {
        app.parse(reversed);
    } catch (const CLI::ArgumentMismatch& e) {
        const std::string what = e.what();   // "--json: 1 required TEXT missing"
        throw UsageError(fmt::format("'fortu {}': {} needs a value", command_, what.substr(0, what.find(':'))));
    } catch (const CLI::ParseError& e) {
        throw UsageError(fmt::format("'fortu {}': {}\nsee fortu {} --help", command_, e.what(), command_));
    }
    if (help) return false;
    for (const std::string& extra : app.remaining())
        if (extra.size() > 1 && extra[0] == '-')
            throw UsageError(fmt::format("unknown option '{}'\nsee fortu {} --help", extra, command_));

    // In the order given, so a later option sees (and may override) an earlier one.
    std::map<const CLI::Option*, std::size_t> used;
    for (const CLI::Option* option : app.parse_order()) {
        auto row = row_of.find(option);
        if (row == row_of.end()) continue;
        const std::size_t k = used[option]++;
        row->second->apply(row->second->value_name.empty() ? std::string() : option->results().at(k));
    }
    if (positionals_) positionals_->insert(positionals_->end(), positional.begin(), positional.end());
    return true;
}

std::vector<std::string> split_value(const std::string& value, char separator) {
    std::vector<std::string> parts;
    for (std::size_t start = 0;;) {
        const std::size_t at = value.find(separator, start);
        parts.push_back(value.substr(start, at - start));
        if (at == std::string::npos) return parts;
        start = at + 1;
    }
}

std::string OptionTable::help() const { return usage_ + "\n" + options_help(); }

std::string OptionTable::options_help() const {
    std::string text = "options:\n";
    for (const Row& row : rows_) {
        std::string names = row.names;
        std::replace(names.begin(), names.end(), ',', ' ');
        const std::string left = row.value_name.empty() ? names : names + " " + row.value_name;
        std::string help = row.help;
        for (std::size_t at = help.find('\n'); at != std::string::npos; at = help.find('\n', at + 1))
            help.insert(at + 1, std::string(30, ' '));
        text += left.size() < 28 ? fmt::format("  {:<28}{}\n", left, help)
                                 : fmt::format("  {}\n{}{}\n", left, std::string(30, ' '), help);
    }
    text += "  -h --help                   this text\n";
    return text;
}

}  // namespace fortu
