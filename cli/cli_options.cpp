// cli/cli_options.cpp — command-line parsing; every malformed value is a UsageError
// naming the option and what was expected.
#include "cli/cli_options.hpp"

#include "runtime/grid.hpp"
#include "runtime/output.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>

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

std::vector<std::string> split(const std::string& text, char sep) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        std::size_t at = text.find(sep, start);
        parts.push_back(text.substr(start, at - start));
        if (at == std::string::npos) return parts;
        start = at + 1;
    }
}

std::vector<int> parse_size(const std::string& text) {
    std::vector<int> size;
    for (const std::string& part : split(text, 'x')) {
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
    const std::vector<std::string> axes = split(text, ',');
    if (axes.size() > 3) throw UsageError(fmt::format("--domain: '{}' has more than 3 ranges", text));
    for (std::size_t i = 0; i < axes.size(); ++i) {
        const std::vector<std::string> ends = split(axes[i], ':');
        if (ends.size() != 2)
            throw UsageError(fmt::format("--domain: '{}' is not a range MIN:MAX (use x0:x1,y0:y1[,z0:z1])", axes[i]));
        AxisRange r{parse_double(ends[0], "--domain"), parse_double(ends[1], "--domain")};
        if (!(r.min < r.max))
            throw UsageError(fmt::format("--domain: range '{}' needs MIN < MAX", axes[i]));
        domain[i] = r;
    }
    return domain;
}

/// The --engine lines of the help text, one per engine of the table.
std::string engine_help() {
    std::string text = fmt::format("  --engine NAME               the engine (default {}):\n", default_engine().name());
    for (const Engine* engine : engine_table())
        text += fmt::format("    {:<24}{}\n", engine->name(), engine->summary());
    return text;
}

}  // namespace

std::string usage_text() {
    std::string text = R"(fortu — evaluate FORTU R-function models (RANOK scripts) on 2D/3D grids

usage:
  fortu run   MODEL.fortu [options]      evaluate on a grid, write images and data
                                         (MODEL may be a Prospero .vm file everywhere)
  fortu eval  MODEL.fortu X Y [Z]        value, gradient and M-image normal at a point
  fortu check MODEL.fortu                parse and check; diagnostics only
  fortu ir    MODEL.fortu                print the lowered IR (nodes, sharing, costs)
  fortu singular MODEL.fortu [-o F.png]  singular (corner) points: K = 0 and R = 0
                                         (search grid: --size, default 401x401 / 48^3)
  fortu golden DIR|FILE...               run golden tests of scripted models
  fortu bench MODEL... | --paper         time the engines (the papers' comparison)
  fortu repl [MODEL.fortu]               interactive session
  fortu help | --help                    this text

options:
  --size N | WxH | WxHxD      grid nodes per axis (both ends included); default: RECTBMP,
                              else 256x256 (2D) or 64x64x64 (3D)
  --domain x0:x1,y0:y1[,z0:z1]  the box (wins over the script's ranges); default: the
                              script's ARGUMENT ranges or RECTANGLE, else [-1, 1]
{engines}  --rsystem r0|alpha=A|minmax the R-system of & and | (wins over RSYSTEM in the script)
  -o FILE                     .png .jpg .tif .bmp (picture), .exr (value + n1..n4 channels),
                              .npy, .csv; 3D pictures: a slice, or one file per slice
                              when FILE contains %d
  --slice K                   the z slice of a 3D picture (default: the middle one)
  --mimages FILE              the M-images: FILE.exr, or FILE_%d.png for grey PNGs
  --float32                   .npy as float32 instead of float64
  --precision float64|float32 the voxel engine's numbers (default float64; float32 is
                              about twice as fast, values within 1e-5 relative to the field)
  --no-hoist                  the voxel engine computes X-only and Y-only sub-expressions
                              at every point instead of once per column/row (to compare)
  --sign-only                 --engine sign: compute only the sign (1 inside, 0 boundary,
                              -1 outside, NaN invalid): for sign pictures and contours,
                              much faster on large models
  --stats                     nodes, sharing, classic cost, time per stage, points/s,
                              invalid points, peak memory
  --threads N                 worker threads (default: all cores)
  --budget OPS                the classic engine refuses runs above OPS operations
                              (default 1e10, about a minute here); --force runs anyway
  --force                     run the classic engine even above the budget

exit status: 0 success, 1 model error (diagnostics printed), 2 usage error
)";
    text.replace(text.find("{engines}"), 9, engine_help());
    return text;
}

CliOptions parse_command_line(const std::vector<std::string>& args) {
    CliOptions o;
    if (args.empty()) throw UsageError("no command given (try 'fortu --help')");
    o.command = args[0];
    bool sign_only = false, engine_given = false;
    if (o.command == "--help" || o.command == "-h") o.command = "help";
    if (o.command == "--version") o.command = "version";
    static const char* kCommands[] = {"run", "eval", "check", "ir", "singular", "help", "version"};
    bool known = false;
    for (const char* c : kCommands) known = known || o.command == c;
    if (!known) throw UsageError(fmt::format("unknown command '{}' (try 'fortu --help')", o.command));

    for (std::size_t i = 1; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&](const char* name) -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(fmt::format("{} needs a value", name));
            return args[++i];
        };
        if (a == "--help" || a == "-h") { o.command = "help"; return o; }
        else if (a == "--size") o.size = parse_size(value("--size"));
        else if (a == "--domain") o.domain = parse_domain(value("--domain"));
        else if (a == "--engine") {
            const std::string& e = value("--engine");
            o.engine = find_engine(e);
            if (!o.engine) throw UsageError(fmt::format("--engine: unknown engine '{}' (use {})", e, engine_names(", ", " or ")));
            engine_given = true;
        } else if (a == "--rsystem") {
            const std::string& r = value("--rsystem");
            o.rsystem = parse_rsystem(r);
            if (!o.rsystem)
                throw UsageError(fmt::format("--rsystem: '{}' is not r0, minmax or alpha=A with A in (-1, 1]", r));
        } else if (a == "-o" || a == "--output") {
            o.output = value("-o");
            if (!output_format_for(o.output)) {
                std::string extensions;
                for (const std::string& e : supported_output_extensions())
                    extensions += (extensions.empty() ? "." : ", .") + e;
                throw UsageError(fmt::format("-o: unknown output format '{}' (use {})", o.output, extensions));
            }
        } else if (a == "--mimages") o.mimages = value("--mimages");
        else if (a == "--contour") o.contour = value("--contour");
        else if (a == "--slice") {
            const std::string& s = value("--slice");
            int v = 0;
            auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
            if (ec != std::errc() || ptr != s.data() + s.size() || v < 0)
                throw UsageError(fmt::format("--slice: '{}' is not a slice number", s));
            o.slice = v;
        } else if (a == "--stats") o.stats = true;
        else if (a == "--force") o.force = true;
        else if (a == "--float32") o.float32 = true;
        else if (a == "--sign-only") sign_only = true;
        else if (a == "--no-hoist") o.engine_settings.hoist = false;
        else if (a == "--precision") {
            const std::string& p = value("--precision");
            if (p == "float64") o.engine_settings.precision = Precision::Float64;
            else if (p == "float32") o.engine_settings.precision = Precision::Float32;
            else throw UsageError(fmt::format("--precision: '{}' is not float64 or float32", p));
        }
        else if (a == "--budget") {
            o.budget = parse_double(value("--budget"), "--budget");
            if (o.budget <= 0) throw UsageError("--budget must be positive");
        } else if (a == "--threads") {
            const std::string& s = value("--threads");
            auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), o.threads);
            if (ec != std::errc() || ptr != s.data() + s.size() || o.threads < 1 || o.threads > 1024)
                throw UsageError(fmt::format("--threads: '{}' is not a thread count from 1 to 1024", s));
        } else if (a.size() > 1 && a[0] == '-' && !(std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.')) {
            throw UsageError(fmt::format("unknown option '{}' (try 'fortu --help')", a));
        } else {
            o.positional.push_back(a);
        }
    }
    if (!o.mimages.empty())
        if (auto problem = mimages_path_problem(o.mimages))
            throw UsageError(fmt::format("--mimages: {}", *problem));
    if (!o.contour.empty() && output_format_for(o.contour) != OutputFormat::Svg)
        throw UsageError(fmt::format("--contour: '{}' must be an .svg file", o.contour));

    // --sign-only is --engine sign; naming the default engine beside it is harmless, as before.
    if (sign_only && engine_given && o.engine != &default_engine() && !o.engine->capabilities().sign_only)
        throw UsageError(fmt::format("--sign-only runs the interval renderer; it does not combine with --engine {}",
                                     o.engine->name()));
    if (sign_only) o.engine = &engine_named("sign");
    if (o.engine->capabilities().sign_only && !o.mimages.empty())
        throw UsageError(fmt::format("{} computes no values; the M-images need them (drop one of the two)",
                                     sign_only ? "--sign-only" : fmt::format("--engine {}", o.engine->name())));

    const bool needs_model = o.command != "help" && o.command != "version";
    if (needs_model && o.positional.empty()) throw UsageError(fmt::format("'fortu {}' needs a MODEL file", o.command));
    if (o.command == "eval") {
        if (o.positional.size() < 3 || o.positional.size() > 4)
            throw UsageError("'fortu eval' needs MODEL X Y [Z]");
    } else if (needs_model && o.positional.size() > 1) {
        throw UsageError(fmt::format("unexpected argument '{}'", o.positional[1]));
    }
    return o;
}

}  // namespace fortu
