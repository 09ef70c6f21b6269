// cli/cli_options.cpp — the commands run, eval, check, ir and singular: each one's option
// table (option_table.hpp) built from shared groups (model, grid, engine, pictures, run
// outputs), and the checks across options. Every malformed value is a UsageError naming the
// option and what was expected.
#include "cli/cli_options.hpp"

#include "cli/brick_options.hpp"
#include "cli/fv_options.hpp"
#include "cli/option_table.hpp"
#include "cli/picture_options.hpp"
#include "cli/standard_streams.hpp"

#include "interp/tape_jit.hpp"
#include "interp/vector_math.hpp"
#include "runtime/grid.hpp"
#include "runtime/output.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_path.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <unistd.h>

namespace fortu {
namespace {

double parse_double(const std::string& text, const std::string& what) {
    double v = 0;
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (ec != std::errc() || ptr != end || !std::isfinite(v))
        throw UsageError(fmt::format("{}: '{}' is not a finite number", what, text));
    return v;
}

std::vector<int> parse_size(const std::string& text) {
    std::vector<int> size;
    for (const std::string& part : split_value(text, 'x')) {
        long v = 0;
        auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
        if (ec != std::errc() || ptr != part.data() + part.size() || part.empty() || v < 1 || v > 1'000'000)
            throw UsageError(fmt::format("--size: '{}' is not a size (use N, WxH or WxHxD with "
                                         "whole numbers from 1 to 1000000)", text));
        size.push_back(static_cast<int>(v));
    }
    if (size.size() > 3) throw UsageError(fmt::format("--size: '{}' has more than 3 dimensions", text));
    return size;
}

std::array<std::optional<AxisRange>, 3> parse_domain(const std::string& text) {
    std::array<std::optional<AxisRange>, 3> domain;
    const std::vector<std::string> axes = split_value(text, ',');
    if (axes.size() > 3) throw UsageError(fmt::format("--domain: '{}' has more than 3 ranges", text));
    for (std::size_t i = 0; i < axes.size(); ++i) {
        const std::vector<std::string> ends = split_value(axes[i], ':');
        if (ends.size() != 2)
            throw UsageError(fmt::format("--domain: '{}' is not a range MIN:MAX (use x0:x1,y0:y1[,z0:z1])", axes[i]));
        AxisRange r{parse_double(ends[0], "--domain"), parse_double(ends[1], "--domain")};
        if (!(r.min < r.max))
            throw UsageError(fmt::format("--domain: range '{}' needs MIN < MAX", axes[i]));
        domain[i] = r;
    }
    return domain;
}

int parse_threads(const std::string& s) {
    int threads = 0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), threads);
    if (ec != std::errc() || ptr != s.data() + s.size() || threads < 1 || threads > 1024)
        throw UsageError(fmt::format("--threads: '{}' is not a thread count from 1 to 1024", s));
    return threads;
}

std::string checked_output(const std::string& path) {
    if (is_stdout_path(path)) return path;   // its format comes from --format (standard_streams.hpp)
    if (!output_format_for(path)) {
        std::string extensions;
        for (const std::string& e : supported_output_extensions()) extensions += (extensions.empty() ? "." : ", .") + e;
        throw UsageError(fmt::format("-o: unknown output format '{}' (use {})", path, extensions));
    }
    return path;
}

/// What the options of one parse leave behind besides CliOptions.
struct EngineChoice {
    bool sign_only = false, engine_given = false;
};

void add_model_options(OptionTable& t, CliOptions& o) {
    t.option("-I,--include-dir", "DIR", "a folder INCLUDE searches after the script's own, before\n"
                                       "FORTU_PATH and the stdlib; repeatable, searched in order",
             [&o](const std::string& dir) {
                 if (dir.empty()) throw UsageError("--include-dir needs a folder");
                 o.include_dirs.push_back(dir);
             });
    t.option("--rsystem", "r0|alpha=A|minmax", "the R-system of & and | (wins over RSYSTEM in the script)",
             [&o](const std::string& r) {
                 o.rsystem = parse_rsystem(r);
                 if (!o.rsystem)
                     throw UsageError(fmt::format("--rsystem: '{}' is not r0, minmax or alpha=A with A in (-1, 1]", r));
             });
    t.option("--limit", "NAME=VALUE", "raise (or lower) a compile-time budget; repeatable:\n" + limits_usage(0),
             [&o](const std::string& v) {
                 if (const std::string problem = o.limits.parse(v); !problem.empty())
                     throw UsageError("--limit: " + problem);
             });
}

void add_grid_options(OptionTable& t, CliOptions& o) {
    t.option("--size", "N|WxH|WxHxD", "grid nodes per axis (both ends included); N: N along the\n"
                                      "longest axis, square cells; default: RECTBMP, else 256x256\n"
                                      "(2D) or 64x64x64 (3D); a shaded view: its picture size",
             [&o](const std::string& v) { o.size = parse_size(v); });
    t.option("--domain", "x0:x1,y0:y1[,z0:z1]|auto", "the box (wins over the script's ranges); default: the\n"
                                                "script's ARGUMENT ranges or RECTANGLE, else its RANOK header\n"
                                                "comment, else [-1, 1]; auto: found by interval subdivision",
             [&o](const std::string& v) {
                 o.domain_auto = v == "auto";
                 if (!o.domain_auto) o.domain = parse_domain(v);
             });
}

void use_isa_named(const std::string& name) {
    if (name == "avx2") {
        if (!tape_jit_available() && vector_math::best_isa() == vector_math::Isa::none)
            throw UsageError("--isa avx2: this CPU has no AVX2");
        vector_math::use_isa(vector_math::Isa::avx2);
        use_tape_jit_width(JitWidth::avx2);
    } else if (name == "avx512") {
        if (vector_math::best_isa() != vector_math::Isa::avx512 || !tape_jit_avx512_available())
            throw UsageError("--isa avx512: this CPU (or this build) has no AVX-512");
        vector_math::use_isa(vector_math::Isa::avx512);
        use_tape_jit_width(JitWidth::avx512);
    } else {
        throw UsageError(fmt::format("--isa: '{}' is not avx2 or avx512", name));
    }
}

}  // namespace

void add_isa_option(OptionTable& t) {
    t.option("--isa", "avx2|avx512", "the widest vector instructions used (default: AVX-512 where\n"
                                     "the CPU has it, else AVX2; float32 sin, cos and the like\n"
                                     "may differ in the last bit between the two)",
             [](const std::string& v) { use_isa_named(v); });
}

namespace {

void add_engine_options(OptionTable& t, CliOptions& o, EngineChoice& choice, bool grids) {
    const std::string engine_help = fmt::format("the engine (default {}):", default_engine().name()) + engine_summaries();
    t.option("--engine", "NAME", engine_help, [&o, &choice](const std::string& e) {
        o.engine = find_engine(e);
        if (!o.engine) throw UsageError(fmt::format("--engine: unknown engine '{}' (use {})", e, engine_names(", ", " or ")));
        choice.engine_given = true;
    });
    if (grids)
        t.flag("--sign-only", "--engine sign: compute only the sign (1 inside, 0 boundary,\n"
                              "-1 outside, NaN invalid): for sign pictures and contours,\n"
                              "much faster on large models",
               [&choice] { choice.sign_only = true; });
    t.option("--precision", "float64|float32", "the voxel engine's numbers (default float64; float32 is\n"
                                               "about twice as fast, values within 1e-5 relative to the field)",
             [&o](const std::string& p) {
                 if (p == "float64") o.engine_settings.precision = Precision::Float64;
                 else if (p == "float32") o.engine_settings.precision = Precision::Float32;
                 else throw UsageError(fmt::format("--precision: '{}' is not float64 or float32", p));
             });
    t.flag("--no-hoist", "the voxel engine computes X-only and Y-only sub-expressions\n"
                         "at every point instead of once per column/row (to compare)",
           [&o] { o.engine_settings.hoist = false; });
    t.flag("--no-jit", "the voxel engine and the shaded view's leaves run their tapes\n"
                       "through the lane loops instead of machine code compiled for\n"
                       "them (the same values; to compare)",
           [&o] { o.engine_settings.compile = false; });
    add_isa_option(t);
    if (grids) add_fv_options(t, o);
    if (grids)
        t.option("--threads", "N", "worker threads (default: all cores)",
                 [&o](const std::string& v) { o.threads = parse_threads(v); });
    t.option("--budget", "OPS", "the classic engine refuses runs above OPS operations\n"
                                "(default 1e10, about a minute here); --force runs anyway",
             [&o](const std::string& v) {
                 o.budget = parse_double(v, "--budget");
                 if (o.budget <= 0) throw UsageError("--budget must be positive");
             });
    t.flag("--force", "run the classic engine even above the budget, and a run\nabove its memory estimate", [&o] { o.force = true; });
}

void add_picture_options(OptionTable& t, CliOptions& o) {
    t.option("-o,--output", "FILE", output_formats_usage(0) + "\n3D pictures: a shaded view (--view), a plane (--slice), or\n"
                                                             "one file per z slice when FILE contains %d",
             [&o](const std::string& v) { o.output = checked_output(v); });
    t.option("--slice", "z=V|x=V|y=V|K", "one plane of a 3D model, evaluated alone (its size: --size N\n"
                                        "or WxH); K: z slice K of the --size cube. Without it a 3D\n"
                                        "picture is a shaded view of the solid",
             [&o](const std::string& v) { o.slice = parse_slice_choice(v); });
    t.option("--view", "top|front|side|iso|AZ,EL", "the direction of a 3D shaded view (default iso;\n"
                                                   "AZ: degrees about the --up axis from the front, EL: above)",
             [&o](const std::string& v) {
                 const std::optional<ViewDirection> view = parse_view_direction(v);
                 if (!view) throw UsageError(fmt::format("--view: '{}' is not top, front, side, iso or AZ,EL in degrees "
                                                         "(EL from -90 to 90)", v));
                 const int up = o.view.up;
                 o.view = *view;
                 o.view.up = up;
             });
    t.option("--up", "x|y|z", "the axis a shaded view draws upwards (default y, as RANOK's\n"
                              "scripts and the Prospero models stand; z: front from -Y)",
             [&o](const std::string& v) {
                 if (v == "x" || v == "X") o.view.up = 0;
                 else if (v == "y" || v == "Y") o.view.up = 1;
                 else if (v == "z" || v == "Z") o.view.up = 2;
                 else throw UsageError(fmt::format("--up: '{}' is not x, y or z", v));
             });
    add_picture_style_options(t, o.picture);
}

void add_run_outputs(OptionTable& t, CliOptions& o) {
    t.option("--mimages", "FILE", "the M-images: FILE.exr, FILE.vti|.pvti|.hdf (the value and\n"
                                     "n1..n5; bricked runs too, a file of its own beside -o),\n"
                                     "or FILE_%d.png for grey PNGs",
             [&o](const std::string& v) { o.mimages = v; });
    t.option("--contour", "FILE.svg", "the zero contour as SVG", [&o](const std::string& v) { o.contour = v; });
    t.flag("--float32", ".npy as float32 instead of float64", [&o] { o.float32 = true; });
    t.flag("--ascii", ".stl as ASCII instead of binary", [&o] { o.ascii = true; });
    t.option("--band", "W", ".vdb: keep the nodes with |value| <= W cells (default 3)", [&o](const std::string& v) {
        o.vdb_band = parse_double(v, "--band");
        if (!(o.vdb_band > 0)) throw UsageError("--band must be positive");
    });
    t.flag("--stats", "nodes, sharing, classic cost, time per stage, points/s,\ninvalid points, peak memory",
           [&o] { o.stats = true; });
    t.option("--format", "EXT", "the format of -o - (standard output): png, npy, csv, svg...;\n"
                                "a binary format is refused when standard output is a terminal",
             [&o](const std::string& v) { o.format = v; });
    t.flag("-q,--quiet", "no `wrote FILE (WxH)` line per file written", [&o] { o.quiet = true; });
}

struct CommandRow {
    const char* name;
    const char* synopsis;   ///< what follows `fortu NAME`
    const char* summary;    ///< one or two lines for the usage texts
    void (*add)(OptionTable&, CliOptions&, EngineChoice&);
};

/// The commands of this parser (golden, bench and repl have their own, in their folders).
const CommandRow kCommands[] = {
    {"run", "MODEL.fortu [options]", "evaluate on a grid, write images and data\n(MODEL may be a Prospero .vm file everywhere)",
     [](OptionTable& t, CliOptions& o, EngineChoice& c) {
         add_grid_options(t, o);
         add_engine_options(t, o, c, true);
         add_model_options(t, o);
         add_picture_options(t, o);
         add_run_outputs(t, o);
         add_brick_options(t, o);
     }},
    {"eval", "MODEL.fortu X Y [Z] [options]", "value, gradient and M-image normal at a point",
     [](OptionTable& t, CliOptions& o, EngineChoice& c) {
         add_grid_options(t, o);
         add_engine_options(t, o, c, false);
         add_model_options(t, o);
     }},
    {"check", "MODEL.fortu... [options]", "parse and check; diagnostics only (exit status: the worst)",
     [](OptionTable& t, CliOptions& o, EngineChoice&) { add_model_options(t, o); }},
    {"ir", "MODEL.fortu [options]", "print the lowered IR (nodes, sharing, costs),\nor with --stage the tape and its hoisted split",
     [](OptionTable& t, CliOptions& o, EngineChoice&) {
         add_model_options(t, o);
         t.option("--stage", "lower|tape|hoist", "the lowered DAG (default), the voxel engine's tape\n"
                                                 "(slots, immediates), or its column/row/per-point split",
                  [&o](const std::string& s) {
                      const std::optional<IrStage> stage = parse_ir_stage(s);
                      if (!stage) throw UsageError(fmt::format("--stage: '{}' is not lower, tape or hoist", s));
                      o.stage = *stage;
                  });
     }},
    {"singular", "MODEL.fortu [options]", "singular (corner) points: K = 0 and R = 0\n(search grid: --size, default 401x401 / 48^3)",
     [](OptionTable& t, CliOptions& o, EngineChoice&) {
         add_grid_options(t, o);
         add_model_options(t, o);
         add_picture_options(t, o);
     }},
};

const CommandRow* find_command(const std::string& name) {
    for (const CommandRow& c : kCommands)
        if (name == c.name) return &c;
    return nullptr;
}

/// Checks across options, once all are applied.
void check_combinations(CliOptions& o, const EngineChoice& choice) {
    if (o.command == "run") check_stdout_output(o, ::isatty(STDOUT_FILENO) == 1);
    else if (is_stdout_path(o.output))
        throw UsageError(fmt::format("-o {}: 'fortu {}' writes files only (standard output: fortu run)", o.output,
                                     o.command));
    if (o.slice && !o.output.empty() && is_file_series(o.output))
        throw UsageError(fmt::format("-o: '{}' writes every z slice (%d); it does not combine with --slice", o.output));
    if (!o.mimages.empty())
        if (auto problem = mimages_path_problem(o.mimages)) throw UsageError(fmt::format("--mimages: {}", *problem));
    const OutputFormat* contour = o.contour.empty() ? nullptr : output_format_for(o.contour);
    if (!o.contour.empty() && (!contour || contour->kind != OutputKind::Contour))
        throw UsageError(fmt::format("--contour: '{}' must be an .svg file", o.contour));
    const OutputFormat* output =
        o.output.empty() ? nullptr : output_format_for(is_stdout_path(o.output) ? "stdout." + o.format : o.output);
    if (output && output->kind == OutputKind::Mesh && (!o.mimages.empty() || !o.contour.empty()))
        throw UsageError(fmt::format("-o {}: a mesh does not combine with --mimages or --contour (run twice)", o.output));
    if (o.ascii && (!output || output->extension() != "stl")) throw UsageError("--ascii applies to -o FILE.stl only");
    // --sign-only is --engine sign; naming the default engine beside it is harmless, as before.
    if (choice.sign_only && choice.engine_given && o.engine != &default_engine() && !o.engine->capabilities().sign_only)
        throw UsageError(fmt::format("--sign-only runs the interval renderer; it does not combine with --engine {}",
                                     o.engine->name()));
    if (choice.sign_only) o.engine = &engine_named("sign");
    check_fv_options(o);
    if (o.engine->capabilities().sign_only && !o.mimages.empty())
        throw UsageError(fmt::format("{} computes no values; the M-images need them (drop one of the two)",
                                     choice.sign_only ? "--sign-only" : fmt::format("--engine {}", o.engine->name())));
}

void check_positionals(const CliOptions& o) {
    if (o.positional.empty()) throw UsageError(fmt::format("'fortu {}' needs a MODEL file", o.command));
    if (o.command == "eval") {
        if (o.positional.size() < 3 || o.positional.size() > 4) throw UsageError("'fortu eval' needs MODEL X Y [Z]");
    } else if (o.positional.size() > 1 && o.command != "check") {
        throw UsageError(fmt::format("unexpected argument '{}'", o.positional[1]));
    }
}

/// `summary`'s lines, each indented by `indent` spaces and ended by a newline.
std::string summary_lines(std::string_view summary, int indent) {
    std::string out;
    for (std::size_t start = 0; start <= summary.size();) {
        const std::size_t end = std::min(summary.find('\n', start), summary.size());
        out += fmt::format("{:{}}{}\n", "", indent, summary.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

/// The option table of `command` filled to write into `o`.
OptionTable command_table(const CommandRow& command, CliOptions& o, EngineChoice& choice) {
    OptionTable table(command.name, fmt::format("usage: fortu {} {}\n{}", command.name, command.synopsis,
                                                summary_lines(command.summary, 2)));
    command.add(table, o, choice);
    table.positionals(o.positional);
    return table;
}

}  // namespace

std::string usage_text() {
    constexpr int kSummaryColumn = 44;
    auto line = [](const std::string& left, std::string_view summary) {
        const std::string lines = summary_lines(summary, kSummaryColumn);
        return fmt::format("  {:<{}}{}", left, kSummaryColumn - 2, lines.substr(kSummaryColumn));
    };
    std::string text = "fortu — evaluate FORTU R-function models (RANOK scripts) on 2D/3D grids\n\nusage:\n";
    for (const CommandRow& c : kCommands) text += line(fmt::format("fortu {} {}", c.name, c.synopsis), c.summary);
    text += line("fortu golden DIR|FILE... [options]", "run golden tests of scripted models");
    text += line("fortu bench MODEL... [options]", "time the engines; --paper: the papers' experiments;\n"
                                                    "--performance: the performance suite");
    text += line("fortu repl [MODEL.fortu]", "interactive session");
    text += line("fortu help | --help | -h", "this text");
    text += line("fortu --version | -V", "the version");
    text += line("fortu COMMAND --help", "that command's options");
    CliOptions unused;
    EngineChoice choice;
    return text + "\nrun's " + command_table(*find_command("run"), unused, choice).options_help() +
           "\nexit status: 0 success, 1 model error (diagnostics printed), 2 usage error\n";
}

CliOptions parse_command_line(const std::vector<std::string>& args) {
    CliOptions o;
    if (args.empty()) throw UsageError("no command given (try 'fortu --help')");
    o.command = args[0];
    if (o.command == "--help" || o.command == "-h") o.command = "help";
    if (o.command == "--version" || o.command == "-V") o.command = "version";
    if (o.command == "help" || o.command == "version") return o;
    const CommandRow* command = find_command(o.command);
    if (!command) throw UsageError(fmt::format("unknown command '{}' (try 'fortu --help')", o.command));

    EngineChoice choice;
    const OptionTable table = command_table(*command, o, choice);
    if (!table.parse(std::vector<std::string>(args.begin() + 1, args.end()))) {
        o.help = table.help();
        o.command = "help";
        return o;
    }
    check_combinations(o, choice);
    check_positionals(o);
    return o;
}

}  // namespace fortu
