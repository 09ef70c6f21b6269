// cli/repl/repl_commands.cpp — the `:commands` of `fortu repl` and the evaluation of typed FORTU.
// Outputs follow `fortu eval` / `fortu run -o` exactly (same point_report, fv_plane and
// write_field), so what the REPL shows is what the command line gives.
#include "cli/repl/repl_commands.hpp"

#include "cli/point_report.hpp"

#include "interp/classic_cost.hpp"
#include "interp/ir_print.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/terminal_picture.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <sstream>

namespace fortu {
namespace {

/// The classic engine's budget in the REPL (`fortu bench`'s default; `fortu run`'s is --budget).
constexpr double kClassicBudget = 2e10;

std::vector<std::string> split_words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

std::string trim(const std::string& s) {
    const std::size_t a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return {};
    const std::size_t b = s.find_last_not_of(" \t\r\n");
    return s.substr(a, b - a + 1);
}

std::optional<double> parse_number(const std::string& text) {
    try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v)) return v;
    } catch (...) {
    }
    return std::nullopt;
}

std::optional<int> parse_count(const std::string& text) {
    const std::optional<double> v = parse_number(text);
    if (!v || *v < 1 || *v > 1e6 || *v != std::floor(*v)) return std::nullopt;
    return static_cast<int>(*v);
}

std::string grid_text(const Grid& g) {
    return g.dims == 3 && g.slices() > 1 ? fmt::format("{}x{}x{}", g.cols(), g.rows(), g.slices())
                                         : fmt::format("{}x{}", g.cols(), g.rows());
}

std::string seconds_text(double s) { return fmt::format("{:.4f} s", s); }

/// The engines :engine offers: those whose values agree bit for bit (points with gradients
/// for :eval, and what :time compares).
bool offered(const EngineCapabilities& can) { return can.exact; }

}  // namespace

Repl::Repl(Session& session, ReplIo io) : session_(session), io_(std::move(io)) {}

std::string Repl::help_text() {
    return "FORTU statements are added to the model as you type them: ARGUMENT X, Y / CONSTANT R = 0.5 /\n"
           "VARIABLE D = R - SQRT(X^2 + Y^2) / RETURN D. Re-defining a name replaces its definition in\n"
           "place, and everything defined from it follows. A bare expression prints its value at the\n"
           "probe point (the last :eval point).\n"
           "  :eval X Y [Z]          value, gradient, M-image normal at a point (and make it the probe)\n"
           "  :show                  draw the model in the terminal\n"
           "  :render FILE           write the image (" + output_extensions_text() + ") as `fortu run -o`\n"
           "  :domain [XMIN XMAX YMIN YMAX [ZMIN ZMAX] | default]   show or set the domain\n"
           "  :size [W [H [D]] | default]                          show or set the grid nodes of :render\n"
           "  :engine [" + engine_names("|", "|", offered) + "]  show or choose the engine\n"
           "  :rsystem [r0|minmax|alpha=A]  show or choose the R-system of & and |\n"
           "  :time                  time the last evaluation with both engines; say what was reused\n"
           "  :ir                    print the model's IR\n"
           "  :load FILE             add a script's statements to the session\n"
           "  :save FILE             write the session as a .fortu script\n"
           "  :reset                 forget everything\n"
           "  :help                  this text\n"
           "  :quit                  leave (also Ctrl-D); Ctrl-C interrupts an evaluation\n";
}

void Repl::error(const std::string& message) {
    io_.out.flush();
    io_.err << "fortu: error: " << message << "\n";
    io_.err.flush();
    had_error_ = true;
}

bool Repl::need_model() {
    if (session_.has_model()) return true;
    error("there is no model yet\nnote: type RETURN and an expression (after ARGUMENT X, Y and your definitions)");
    return false;
}

bool Repl::handle(const std::string& input) {
    if (io_.interrupt) io_.interrupt->store(false);
    const std::string text = trim(input);
    bool go_on = true;
    try {
        if (!text.empty() && text[0] == ':') go_on = command(text);
        else if (!text.empty()) fortu_text(input);
    } catch (const OutputError& e) {
        error(e.what());
    } catch (const std::bad_alloc&) {
        error("out of memory");
    } catch (const std::exception& e) {
        error(e.what());
    }
    io_.out.flush();
    return go_on;
}

bool Repl::command(const std::string& line) {
    std::vector<std::string> words = split_words(line);
    const std::string name = words[0];
    words.erase(words.begin());
    auto one_path = [&]() -> std::optional<std::string> {
        const std::string rest = trim(line.substr(name.size()));
        if (rest.empty()) { error(fmt::format("{} needs a file name", name)); return std::nullopt; }
        return rest;
    };
    auto no_arguments = [&]() {
        if (words.empty()) return true;
        error(fmt::format("{} takes no arguments", name));
        return false;
    };
    if (name == ":quit" || name == ":q" || name == ":exit") return false;
    if (name == ":help" || name == ":h" || name == ":?") { io_.out << help_text(); return true; }
    if (name == ":eval") eval(words);
    else if (name == ":show") { if (no_arguments()) show(); }
    else if (name == ":render") { if (auto p = one_path()) render({*p}); }
    else if (name == ":domain") domain(words);
    else if (name == ":size") size(words);
    else if (name == ":engine") {
        const Engine* chosen = words.size() == 1 ? find_engine(words[0]) : nullptr;
        if (words.empty()) io_.out << fmt::format("engine: {}\n", engine_->name());
        else if (chosen && offered(chosen->capabilities())) engine_ = chosen;
        else error(fmt::format(":engine: '{}' is not {}", trim(line.substr(name.size())), engine_names(", ", " or ", offered)));
    } else if (name == ":rsystem") {
        if (words.empty()) {
            const RSystem r = session_.rsystem().value_or(RSystem{});
            io_.out << fmt::format("rsystem: {}{}\n", r.name(), session_.rsystem() ? "" : " (unless the script says otherwise)");
        } else if (auto r = parse_rsystem(words[0]); r && words.size() == 1) {
            session_.set_rsystem(*r);
        } else {
            error(fmt::format(":rsystem: '{}' is not r0, minmax, r1 or alpha=A with A in (-1, 1]",
                              trim(line.substr(name.size()))));
        }
    } else if (name == ":time") { if (no_arguments()) time(); }
    else if (name == ":ir") { if (no_arguments() && need_model()) io_.out << print_ir(session_.model(), "<session>"); }
    else if (name == ":load") { if (auto p = one_path()) load(*p); }
    else if (name == ":save") { if (auto p = one_path()) save(*p); }
    else if (name == ":reset") {
        if (no_arguments()) { session_.reset(); last_.reset(); probe_ = {0, 0, 0}; }
    } else error(fmt::format("unknown command '{}'\nnote: :help lists the commands", name));
    return true;
}

void Repl::fortu_text(const std::string& text) {
    SubmitResult r = session_.submit(text, "<input>");
    if (r.kind == SubmitResult::Kind::Error) {
        io_.out.flush();
        io_.err << r.diagnostics;
        io_.err.flush();
        had_error_ = true;
        return;
    }
    if (!r.diagnostics.empty()) { io_.out.flush(); io_.err << r.diagnostics; io_.err.flush(); }
    if (r.kind == SubmitResult::Kind::Expression) {
        const Model& m = *r.model;
        if (engine_->capabilities().expanded_tree_cost && dag_depth(m.graph, m.root) > kClassicMaxDepth)
            return error("the expression is too deep for the classic engine\nnote: use :engine voxel");
        io_.out << fmt::format("{}\n", evaluate_point(m, probe_, *engine_).value);
        return;
    }
    for (const std::string& change : r.changes)
        if (change.rfind("replaced ", 0) == 0) io_.out << change << "\n";
}

std::optional<std::string> Repl::classic_refusal(const Engine& engine, double points) const {
    if (!engine.capabilities().expanded_tree_cost) return std::nullopt;
    const Model& m = session_.model();
    if (dag_depth(m.graph, m.root) > kClassicMaxDepth)
        return "the model is too deep for the classic engine's recursion\nnote: use :engine voxel";
    const double per_point = classic_operations_per_point(m.graph, m.root);
    if (per_point * points <= kClassicBudget) return std::nullopt;
    return fmt::format("the classic engine would need {} operations per point x {} points (budget {:.3g})\n"
                       "note: use :engine voxel or a smaller :size",
                       format_operations(per_point), format_operations(points), kClassicBudget);
}

std::optional<Field> Repl::evaluate(const Grid& grid) {
    if (auto refusal = classic_refusal(*engine_, double(grid.points()))) { error(*refusal); return std::nullopt; }
    EvalOptions options;
    options.cancel = io_.interrupt;
    EvalReport report;
    Field field = session_.evaluate(grid, *engine_, options, report);
    last_ = report;
    if (report.cancelled) {
        error("interrupted");
        return std::nullopt;
    }
    return field;
}

void Repl::eval(const std::vector<std::string>& args) {
    if (!need_model()) return;
    const Model& m = session_.model();
    const int dims = static_cast<int>(m.arguments.size());
    const int wanted = std::max(dims, 2);
    if (static_cast<int>(args.size()) != wanted && !(dims == 1 && args.size() == 1))
        return error(fmt::format(":eval: the model has {} argument(s); give {} coordinate(s)", dims, wanted));
    std::array<double, 3> p{0, 0, 0};
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::optional<double> v = parse_number(args[i]);
        if (!v) return error(fmt::format(":eval: '{}' is not a finite coordinate", args[i]));
        p[i] = *v;
    }
    if (auto refusal = classic_refusal(*engine_, 1.0 + m.dims())) return error(*refusal);
    probe_ = p;
    io_.out << point_report(m, p, *engine_, session_.grid());
}

void Repl::show() {
    if (!need_model()) return;
    auto [columns, lines] = io_.terminal_size ? io_.terminal_size() : std::pair{80, 24};
    columns = std::max(columns, 8);
    lines = std::max(lines, 6);
    // Two pixels per cell, stacked: a cell is about twice as tall as wide, so pixels are
    // square and the picture keeps the domain's aspect. Two lines stay for caption and prompt.
    const Grid domain = session_.grid();
    const double wide = domain.x.max - domain.x.min, tall = domain.y.max - domain.y.min;
    const int max_w = columns, max_h = 2 * (lines - 2);
    int w = max_w, h = static_cast<int>(std::lround(max_w * tall / wide));
    if (h > max_h) { h = max_h; w = std::clamp(static_cast<int>(std::lround(max_h * wide / tall)), 2, max_w); }
    h = std::max(2, h);
    const std::optional<Field> field = evaluate(session_.grid_with_nodes(w, h));
    if (!field) return;
    io_.out << terminal_picture(*field, 0, io_.colour);
    const Grid& g = field->grid;
    io_.out << fmt::format("x [{}, {}], y [{}, {}]{}; {}\n", g.x.min, g.x.max, g.y.min, g.y.max,
                           g.dims == 3 ? fmt::format(", z = {}", g.z.min) : "",
                           io_.colour ? "warm inside, blue outside, black contour"
                                      : fmt::format("{} inside, {} outside, {} contour", kAsciiInside,
                                                    kAsciiOutside, kAsciiContour));
}

void Repl::render(const std::vector<std::string>& args) {
    if (!need_model()) return;
    const std::string& path = args[0];
    if (!output_format_for(path))
        return error(fmt::format(":render: cannot write '{}': the extension is not one of {}", path,
                                 fmt::join(supported_output_extensions(), ", ")));
    const Grid grid = session_.grid();
    if (grid.points() > kMaxGridPoints) return error(":render: the grid is too large; choose a smaller :size");
    const std::optional<Field> field = evaluate(grid);
    if (!field) return;
    write_field(*field, path);
    io_.out << fmt::format("wrote {} ({})\n", path, grid_text(grid));
}

void Repl::domain(const std::vector<std::string>& args) {
    if (args.empty()) {
        const Grid g = session_.grid();
        io_.out << fmt::format("domain: x [{}, {}], y [{}, {}]{}\n", g.x.min, g.x.max, g.y.min, g.y.max,
                               g.dims == 3 ? fmt::format(", z [{}, {}]", g.z.min, g.z.max) : "");
        return;
    }
    if (args.size() == 1 && args[0] == "default") { session_.set_domain({}); return; }
    if (args.size() != 4 && args.size() != 6)
        return error(":domain: give XMIN XMAX YMIN YMAX [ZMIN ZMAX], or default");
    std::array<std::optional<AxisRange>, 3> d;
    for (std::size_t a = 0; a < args.size() / 2; ++a) {
        const std::optional<double> lo = parse_number(args[2 * a]), hi = parse_number(args[2 * a + 1]);
        if (!lo || !hi) return error(fmt::format(":domain: '{}' is not a finite number", !lo ? args[2 * a] : args[2 * a + 1]));
        if (!(*lo < *hi)) return error(fmt::format(":domain: {} must be less than {}", *lo, *hi));
        d[a] = AxisRange{*lo, *hi};
    }
    session_.set_domain(d);
}

void Repl::size(const std::vector<std::string>& args) {
    if (args.empty()) {
        io_.out << fmt::format("size: {}\n", grid_text(session_.grid()));
        return;
    }
    if (args.size() == 1 && args[0] == "default") { session_.set_size({}); return; }
    std::vector<std::string> parts;
    if (args.size() == 1) {
        std::string rest = args[0];
        for (std::size_t x; (x = rest.find('x')) != std::string::npos; rest = rest.substr(x + 1)) parts.push_back(rest.substr(0, x));
        parts.push_back(rest);
    } else {
        parts = args;
    }
    if (parts.size() > 3) return error(":size: give W [H [D]], WxH or WxHxD, or default");
    std::vector<int> nodes;
    for (const std::string& p : parts) {
        const std::optional<int> n = parse_count(p);
        if (!n || *n < 2) return error(fmt::format(":size: '{}' is not a node count from 2 to 1000000", p));
        nodes.push_back(*n);
    }
    const std::vector<int> before = session_.size();
    session_.set_size(nodes);
    if (session_.grid().points() > kMaxGridPoints) {
        session_.set_size(before);
        return error(fmt::format(":size: {} is more points than the {} fortu allocates", fmt::join(parts, "x"),
                                 format_operations(double(kMaxGridPoints))));
    }
}

void Repl::time() {
    if (!need_model()) return;
    const Grid grid = last_ ? last_->grid : session_.grid();
    if (last_) {
        const EvalReport& r = *last_;
        std::string what;
        if (r.reused)
            what = "reused: the values of this model on this grid were kept, nothing was evaluated";
        else if (r.cancelled)
            what = "it was interrupted";
        else if (!engine_named(r.engine).capabilities().known_and_kept)
            what = fmt::format("computed all {} operations in {} (the {} engine saves nothing)",
                               r.operations, seconds_text(r.seconds), r.engine);
        else {
            what = fmt::format("computed {} of {} operations in {}", r.computed_operations, r.operations,
                               seconds_text(r.seconds));
            if (!r.reused_definitions.empty())
                what += fmt::format("; reused the kept values of {} ({})",
                                    r.reused_definitions.size() == 1 ? "1 definition"
                                        : fmt::format("{} definitions", r.reused_definitions.size()),
                                    fmt::join(r.reused_definitions, ", "));
            if (r.kept_definitions > 0)
                what += fmt::format("; kept the values of {} definition{} for next time", r.kept_definitions,
                                    r.kept_definitions == 1 ? "" : "s");
        }
        io_.out << fmt::format("last evaluation: {} engine, {} points; {}\n", r.engine,
                               grid_text(r.grid), what);
    }
    const Model& m = session_.model();
    io_.out << "the whole model, nothing reused:\n";
    for (const Engine& engine : exact_engines()) {
        if (const std::optional<std::string> refusal = classic_refusal(engine, double(grid.points()))) {
            io_.out << fmt::format("{}: not run ({})\n", engine.name(), refusal->substr(0, refusal->find('\n')));
            continue;
        }
        EvalOptions options;
        options.cancel = io_.interrupt;
        const auto start = std::chrono::steady_clock::now();
        evaluate_grid(m, grid, engine, options);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (io_.interrupt && io_.interrupt->load()) return error("interrupted");
        io_.out << fmt::format("{:8} {} points in {} ({} points/s)\n", std::string(engine.name()) + ":",
                               grid_text(grid), seconds_text(s),
                               format_operations(s > 0 ? double(grid.points()) / s : 0.0));
    }
}

void Repl::load(const std::string& path) {
    std::string problem;
    auto source = SourceFile::load(path, problem);
    if (!source) return error(problem);
    SubmitResult r = session_.submit(source->text(), path);
    if (!r.diagnostics.empty()) { io_.out.flush(); io_.err << r.diagnostics; io_.err.flush(); }
    if (r.kind == SubmitResult::Kind::Error) { had_error_ = true; return; }
    if (r.kind == SubmitResult::Kind::Expression)
        return error(fmt::format("'{}' is an expression, not a script", path));
    io_.out << fmt::format("loaded {} ({} statement{})\n", path, r.changes.size(), r.changes.size() == 1 ? "" : "s");
}

void Repl::save(const std::string& path) {
    const std::string script = session_.script();
    write_file_atomically(path, [&](OutputFile& file) { file.write(script); });
    io_.out << fmt::format("saved {}\n", path);
}

}  // namespace fortu
