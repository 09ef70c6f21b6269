// cli/repl/repl_commands.cpp — the `:commands` of `fortu repl` and the evaluation of typed FORTU.
// Outputs follow `fortu eval` / `fortu run -o` exactly (same point_report, fv_plane and
// write_field), so what the REPL shows is what the command line gives.
#include "cli/repl/repl_commands.hpp"

#include "cli/cli_options.hpp"
#include "cli/model_setup.hpp"
#include "cli/point_report.hpp"
#include "cli/run_grid.hpp"

#include "interp/classic_cost.hpp"
#include "interp/ir_print.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/surface_picture.hpp"
#include "runtime/terminal_picture.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <sstream>

namespace fortu {
namespace {

/// The classic engine's budget in the REPL: `fortu run`'s default --budget.
const double kClassicBudget = CliOptions{}.budget;

const char* const kAxisNames[3] = {"x", "y", "z"};

/// The default size of a shaded view, as `fortu run`'s.
constexpr int kViewPixels = 512;

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
           "  :show [PICTURE]        draw the model in the terminal\n"
           "  :render FILE [PICTURE] write the image (" + output_extensions_text() + ") as `fortu run -o`\n"
           "      PICTURE, for a 3D model: --slice z=V|x=V|y=V|K (a plane) or --view top|front|side|iso|AZ,EL\n"
           "      and --up x|y|z (a shaded view of the solid, the default), as `fortu run`\n"
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
    // :render FILE [--slice S] [--view V] [--up A]: the file name is everything before the first option.
    auto path_and_options = [&]() -> std::optional<std::pair<std::string, std::vector<std::string>>> {
        const std::string rest = trim(line.substr(name.size()));
        std::size_t options_at = rest.size();
        for (std::size_t at = 0; (at = rest.find_first_not_of(" \t", at)) != std::string::npos;) {
            const std::size_t end = std::min(rest.find_first_of(" \t", at), rest.size());
            const std::string word = rest.substr(at, end - at);
            if (word == "--slice" || word == "--view" || word == "--up") { options_at = at; break; }
            at = end;
        }
        const std::string path = trim(rest.substr(0, options_at));
        if (path.empty()) { error(fmt::format("{} needs a file name", name)); return std::nullopt; }
        return std::pair{path, split_words(rest.substr(options_at))};
    };
    auto no_arguments = [&]() {
        if (words.empty()) return true;
        error(fmt::format("{} takes no arguments", name));
        return false;
    };
    if (name == ":quit" || name == ":q" || name == ":exit") return false;
    if (name == ":help" || name == ":h" || name == ":?") { io_.out << help_text(); return true; }
    if (name == ":eval") eval(words);
    else if (name == ":show") show(words);
    else if (name == ":render") { if (auto p = path_and_options()) render(p->first, p->second); }
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
            last_.reset();
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
    // The model may have changed: the last evaluation is no longer this model's.
    if (!r.changes.empty()) last_.reset();
    for (const std::string& change : r.changes)
        if (change.rfind("replaced ", 0) == 0) io_.out << change << "\n";
}

std::optional<std::string> Repl::classic_refusal(const Engine& engine, double points) const {
    // fortu run's check and budget; the advice names the REPL's commands instead of options.
    std::optional<std::string> refusal = fortu::classic_refusal(session_.model(), engine, points, kClassicBudget);
    if (refusal) *refusal = refusal->substr(0, refusal->find("\nnote: ")) + "\nnote: use :engine voxel or a smaller :size";
    return refusal;
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

std::optional<SurfaceImage> Repl::shaded_view(const ViewDirection& view, int width, int height) {
    const Model& m = session_.model();
    const Grid cube = session_.grid();
    const std::array<AxisRange, 3> box{AxisRange{cube.x.min, cube.x.max}, AxisRange{cube.y.min, cube.y.max},
                                       AxisRange{cube.z.min, cube.z.max}};
    EvalOptions options;
    options.cancel = io_.interrupt;
    SurfaceImage image = render_shaded_view(m.graph, m.root, box, view, width, height, options);
    if (io_.interrupt && io_.interrupt->load()) return std::nullopt;
    return image;
}

std::optional<Repl::PictureChoice> Repl::picture_choice(const std::string& command,
                                                        const std::vector<std::string>& args) {
    PictureChoice choice;
    for (std::size_t i = 0; i < args.size(); i += 2) {
        const std::string& option = args[i];
        if (option != "--slice" && option != "--view" && option != "--up") {
            error(fmt::format("{}: '{}' is not --slice, --view or --up", command, option));
            return std::nullopt;
        }
        if (i + 1 == args.size()) {
            error(fmt::format("{}: {} needs a value", command, option));
            return std::nullopt;
        }
        const std::string& value = args[i + 1];
        if (option == "--slice") {
            choice.slice = parse_slice_choice(value);   // throws UsageError, reported by handle()
        } else if (option == "--view") {
            const std::optional<ViewDirection> view = parse_view_direction(value);
            if (!view) {
                error(fmt::format("{}: --view: '{}' is not top, front, side, iso or AZ,EL in degrees", command, value));
                return std::nullopt;
            }
            choice.view.azimuth = view->azimuth;
            choice.view.elevation = view->elevation;
            choice.view_given = true;
        } else {
            const std::string axes = "xyz";
            const std::size_t axis = value.size() == 1 ? axes.find(char(std::tolower(static_cast<unsigned char>(value[0]))))
                                                       : std::string::npos;
            if (axis == std::string::npos) {
                error(fmt::format("{}: --up: '{}' is not x, y or z", command, value));
                return std::nullopt;
            }
            choice.view.up = int(axis);
            choice.view_given = true;
        }
    }
    if (choice.slice && choice.view_given) {
        error(fmt::format("{}: a picture is a plane (--slice) or a shaded view (--view, --up), not both", command));
        return std::nullopt;
    }
    if ((choice.slice || choice.view_given) && session_.model().dims() != 3) {
        error(fmt::format("{}: --slice, --view and --up draw 3D models; this one has {} argument(s)", command,
                          session_.model().arguments.size()));
        return std::nullopt;
    }
    return choice;
}

Grid Repl::plane_grid(const SliceChoice& slice, const std::vector<int>& size) {
    CliOptions o;
    o.size = size;
    o.domain = session_.domain();
    o.slice = slice;
    return run_grid(session_.model(), o);   // fortu run's plane: square cells, checked bounds
}

namespace {

/// Where a grid lies: "x [-1, 1], y [-1, 1], z = 0" (an axis of one node is its coordinate).
std::string extent_text(const Grid& g) {
    const Axis* axes[3] = {&g.x, &g.y, &g.z};
    std::string out;
    for (int a = 0; a < g.dims; ++a) {
        out += a ? ", " : "";
        out += axes[a]->nodes == 1 && g.dims == 3 ? fmt::format("{} = {}", kAxisNames[a], axes[a]->min)
                                                  : fmt::format("{} [{}, {}]", kAxisNames[a], axes[a]->min, axes[a]->max);
    }
    return out;
}

/// The largest w × h (w ≤ max_w, h ≤ max_h) with the aspect wide : tall.
std::pair<int, int> fit_aspect(double wide, double tall, int max_w, int max_h) {
    int w = max_w, h = static_cast<int>(std::lround(max_w * tall / wide));
    if (h > max_h) { h = max_h; w = std::clamp(static_cast<int>(std::lround(max_h * wide / tall)), 2, max_w); }
    return {w, std::max(2, h)};
}

std::string view_text(const ViewDirection& v) {
    return fmt::format("azimuth {}, elevation {}, {} up", v.azimuth, v.elevation, kAxisNames[v.up]);
}

}  // namespace

void Repl::show(const std::vector<std::string>& args) {
    if (!need_model()) return;
    const std::optional<PictureChoice> choice = picture_choice(":show", args);
    if (!choice) return;
    auto [columns, lines] = io_.terminal_size ? io_.terminal_size() : std::pair{80, 24};
    columns = std::max(columns, 8);
    lines = std::max(lines, 6);
    // Two pixels per cell, stacked: a cell is about twice as tall as wide, so pixels are
    // square and the picture keeps the domain's aspect. Two lines stay for caption and prompt.
    const int max_w = columns, max_h = 2 * (lines - 2);
    const std::string legend = io_.colour ? "warm inside, blue outside, black contour"
                                          : fmt::format("{} inside, {} outside, {} contour", kAsciiInside,
                                                        kAsciiOutside, kAsciiContour);
    const Model& m = session_.model();
    if (m.dims() == 3 && !choice->slice) {
        const std::optional<SurfaceImage> image = shaded_view(choice->view, max_w, max_h);
        if (!image) return error("interrupted");
        io_.out << terminal_surface_picture(*image, io_.colour);
        io_.out << fmt::format("{}; shaded view, {}; {}\n", extent_text(session_.grid()), view_text(choice->view),
                               io_.colour ? "cut faces cream"
                                          : fmt::format("{} surface, {} cut by the domain", kAsciiSurface, kAsciiCut));
        return;
    }
    Grid grid;
    if (choice->slice) {
        SliceChoice slice = *choice->slice;
        if (slice.index) {   // z slice K of the :size cube, drawn at the terminal's size
            const Grid cube = session_.grid();
            if (*slice.index >= cube.slices())
                return error(fmt::format(":show: --slice {} is outside 0..{}", *slice.index, cube.slices() - 1));
            slice = SliceChoice{2, std::nullopt, cube.z_at(*slice.index)};
        }
        // The plane's picture: across, X (Y for an x plane); up, Y for a z plane, else Z.
        const Grid plane = plane_grid(slice, {});
        const Axis& across = slice.axis == 0 ? plane.y : plane.x;
        const Axis& up = slice.axis == 2 ? plane.y : plane.z;
        const auto [w, h] = fit_aspect(across.max - across.min, up.max - up.min, max_w, max_h);
        grid = plane_grid(slice, {w, h});
    } else {
        const Grid domain = session_.grid();
        const auto [w, h] = fit_aspect(domain.x.max - domain.x.min, domain.y.max - domain.y.min, max_w, max_h);
        grid = session_.grid_with_nodes(w, h);
    }
    const std::optional<Field> field = evaluate(grid);
    if (!field) return;
    io_.out << terminal_picture(plane_picture(*field), 0, io_.colour);
    io_.out << fmt::format("{}; {}\n", extent_text(grid), legend);
}

void Repl::render(const std::string& path, const std::vector<std::string>& args) {
    if (!need_model()) return;
    const OutputFormat* format = output_format_for(path);
    if (!format)
        return error(fmt::format(":render: cannot write '{}': the extension is not one of {}", path,
                                 fmt::join(supported_output_extensions(), ", ")));
    const std::optional<PictureChoice> choice = picture_choice(":render", args);
    if (!choice) return;
    const Model& m = session_.model();
    const bool picture = format->kind == OutputKind::Picture;
    if (choice->view_given && !picture)
        return error(fmt::format(":render: a shaded view is a picture; '{}' is not one", path));
    if (m.dims() == 3 && picture && !choice->slice) {
        // As fortu run: a 3D picture is the shaded view of the solid, :size N (or W H) pixels.
        const std::vector<int>& size = session_.size();
        if (size.size() == 3) return error(":render: a shaded view is a picture; give :size N or :size W H");
        const int w = size.empty() ? kViewPixels : size[0], h = size.size() == 2 ? size[1] : w;
        const std::optional<SurfaceImage> image = shaded_view(choice->view, w, h);
        if (!image) return error("interrupted");
        write_surface_picture(*image, path);
        io_.out << fmt::format("wrote {} ({}x{} shaded view, {})\n", path, w, h, view_text(choice->view));
        return;
    }
    const Grid grid = choice->slice ? plane_grid(*choice->slice, session_.size()) : session_.grid();
    if (grid.points() > kMaxGridPoints) return error(":render: the grid is too large; choose a smaller :size");
    const std::optional<Field> field = evaluate(grid);
    if (!field) return;
    // Pictures of an x or y plane show it with Z up; values files keep the grid's axes.
    write_field(picture ? plane_picture(*field) : *field, path);
    io_.out << fmt::format("wrote {} ({}{})\n", path, grid_text(grid),
                           choice->slice ? fmt::format(", {}", extent_text(grid)) : "");
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
    if (args.size() == 1 && args[0] == "default") {
        session_.set_size({});
        io_.out << fmt::format("size: {}\n", grid_text(session_.grid()));
        return;
    }
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
    io_.out << fmt::format("size: {}\n", grid_text(session_.grid()));
}

void Repl::time() {
    if (!need_model()) return;
    const Grid grid = last_ ? last_->grid : session_.grid();
    if (!last_) io_.out << "last evaluation: none of this model yet (:show and :render evaluate it)\n";
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
    if (!r.changes.empty()) last_.reset();
    io_.out << fmt::format("loaded {} ({} statement{})\n", path, r.changes.size(), r.changes.size() == 1 ? "" : "s");
}

void Repl::save(const std::string& path) {
    const std::string script = session_.script();
    write_file_atomically(path, [&](OutputFile& file) { file.write(script); });
    io_.out << fmt::format("saved {}\n", path);
}

}  // namespace fortu
