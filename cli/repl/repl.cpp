// cli/repl/repl.cpp — `fortu repl [MODEL.fortu]`: the read-evaluate-print loop. Owns what touches
// the process (SIGINT, the terminal, the history file); what an input does is repl_commands.
// On a terminal: prompts, line editing, colour. Otherwise: plain lines in, plain text out.
#include "cli/commands.hpp"
#include "cli/data_paths.hpp"
#include "cli/option_table.hpp"
#include "interp/lower.hpp"
#include "cli/repl/repl_commands.hpp"
#include "cli/repl/repl_input.hpp"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sys/ioctl.h>
#include <unistd.h>

namespace fortu {
namespace {

/// Set by SIGINT: a signal is process-wide, so its flag is the one truly global state here.
std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) { g_interrupted.store(true); }

constexpr const char* kUsage =
    "usage: fortu repl [MODEL.fortu]\n"
    "  an interactive session: type FORTU statements and :commands (:help lists them)\n";

std::pair<int, int> terminal_size() {
    winsize ws{};
    if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 && ws.ws_row > 0)
        return {ws.ws_col, ws.ws_row};
    return {80, 24};
}

bool colour_wanted() {
    const char* no_colour = std::getenv("NO_COLOR");
    return isatty(STDOUT_FILENO) && !(no_colour && *no_colour);
}

}  // namespace

int run_repl_command(const std::vector<std::string>& args) {
    std::vector<std::string> models;
    OptionTable table("repl", kUsage);
    table.positionals(models);
    if (!table.parse(args)) { std::cout << table.help(); return 0; }
    if (models.size() > 1) {
        const std::string usage = kUsage;
        throw UsageError("'fortu repl' takes one model at most\n" + usage.substr(0, usage.size() - 1));
    }
    const std::string model_path = models.empty() ? "" : models[0];
    const bool interactive = isatty(STDIN_FILENO);
    if (interactive) {
        // Ctrl-C stops an evaluation (EvalOptions::cancel) instead of the process. SA_RESTART
        // keeps a read at the prompt going.
        struct sigaction action{};
        action.sa_handler = on_interrupt;
        sigemptyset(&action.sa_mask);
        action.sa_flags = SA_RESTART;
        sigaction(SIGINT, &action, nullptr);
    }

    Session session(stdlib_dirs());
    Repl repl(session, ReplIo{std::cout, std::cerr, colour_wanted(), terminal_size, &g_interrupted});
    LineReader reader(interactive, interactive ? default_history_path() : std::string());
    if (interactive) {
        const std::vector<std::string> stdlib = stdlib_function_names(stdlib_dirs());
        reader.set_completer([&repl, stdlib](const std::string& line, std::size_t start) {
            return complete_repl_word(line, start, repl.names(), stdlib);
        });
        std::cout << "fortu repl: type FORTU statements or :help; Tab completes; Ctrl-D quits\n";
    }
    if (!model_path.empty()) repl.load(model_path);

    std::string buffer;
    for (;;) {
        std::optional<std::string> line = reader.read(buffer.empty() ? "fortu> " : " ...> ");
        if (!line) {
            if (interactive && g_interrupted.exchange(false)) {   // Ctrl-C at the prompt: drop the line
                buffer.clear();
                std::cout << "\n";
                continue;
            }
            break;
        }
        g_interrupted.store(false);
        buffer += *line;
        buffer += '\n';
        // A :command is one line; FORTU text may open a FOR or FUNCTION block.
        const std::size_t first = buffer.find_first_not_of(" \t");
        if (first != std::string::npos && buffer[first] != ':' && input_incomplete(buffer)) continue;
        const bool go_on = repl.handle(buffer);
        buffer.clear();
        if (!go_on) break;
    }
    if (!buffer.empty()) repl.handle(buffer);   // an unfinished block at end of input: its errors
    if (interactive) std::cout << "\n";
    return !interactive && repl.had_error() ? 1 : 0;
}

}  // namespace fortu
