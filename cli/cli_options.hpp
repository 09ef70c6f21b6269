// cli/cli_options.hpp — the command line of run, eval, check, ir and singular: parsing
// `fortu COMMAND [options]` into one struct, with usage errors (exit status 2) reported
// before any work is done. (golden, bench and repl parse their own options, in cli/golden/,
// cli/bench/ and cli/repl/, with the same OptionTable.)
#pragma once

#include "cli/option_table.hpp"
#include "cli/slice_choice.hpp"
#include "interp/engine.hpp"
#include "interp/limits.hpp"
#include "interp/model.hpp"
#include "interp/shaded_view.hpp"
#include "interp/stage_print.hpp"
#include "runtime/output_options.hpp"

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace fortu {


struct CliOptions {
    std::string command;                       ///< run, eval, check, ir, singular, help, version
    std::string help;                          ///< `fortu COMMAND --help`: that command's help (command "help")
    std::vector<std::string> positional;       ///< MODEL, then coordinates for eval
    std::vector<int> size;                     ///< --size: 1 to 3 node counts
    std::array<std::optional<AxisRange>, 3> domain;  ///< --domain
    bool domain_auto = false;                  ///< --domain auto (run_grid.hpp)
    const Engine* engine = &default_engine();  ///< --engine (--sign-only: the sign engine)
    EngineSettings engine_settings;            ///< --precision, --no-hoist
    std::optional<RSystem> rsystem;
    Limits limits;                             ///< --limit NAME=VALUE (interp/limits.def)
    std::string output;                        ///< -o
    std::string mimages;                       ///< --mimages
    std::string contour;                       ///< --contour
    std::optional<SliceChoice> slice;          ///< --slice: one plane of a 3D model (run_grid.hpp)
    ViewDirection view{45, 35.264389682754654}; ///< --view: the shaded view of a 3D picture (default iso)
    PictureStyle picture;                      ///< --scale, --levels, --legend (cli/picture_options.hpp)
    bool stats = false;
    bool force = false;
    double budget = 1e10;                      ///< classic operations per run before refusing (~1 min here)
    int threads = 0;
    bool float32 = false;                      ///< --float32 for .npy output
    bool ascii = false;                        ///< --ascii for .stl output
    double vdb_band = 3.0;                     ///< --band: the .vdb narrow band, in cells
    IrStage stage = IrStage::Lower;            ///< --stage: what `fortu ir` prints
    std::string steps;                         ///< --steps: the folder for each definition's M-images
    const Engine* compare = nullptr;           ///< --compare: the engine the result is measured against
    std::vector<std::string> include_dirs;     ///< -I / --include-dir: searched by INCLUDE before FORTU_PATH
    std::string format;                        ///< --format: the format of `-o -` (standard output)
    bool quiet = false;                        ///< --quiet: no `wrote FILE` lines
    std::size_t memory = 0;                    ///< --memory: a bricked run's bound in bytes (0: none given)
    bool resume = false;                       ///< --resume: a bricked run computes only missing bricks
    int brick = 128;                           ///< --brick: nodes per brick edge
    std::string brick_times;                   ///< --brick-times: a CSV line per brick (docs/scaling.md's simulation)
    std::vector<std::string> sets;             ///< --set NAME=A:B:STEP or NAME=V (a sweep over a CONSTANT)
    std::vector<std::pair<std::string, double>> constants;  ///< one point of a sweep (CompileOptions::constants)
    bool sweep_point = false;                  ///< a run of a sweep: one process, even under mpirun
};

/// `-o -` and `-o /dev/stdout`: the output goes to standard output (stdout_output.hpp).
bool is_stdout_path(const std::string& path);

/// Parses argv (without the program name). Throws UsageError.
CliOptions parse_command_line(const std::vector<std::string>& args);

/// `--isa avx2|avx512` in `t`: narrows (or widens, up to what the CPU has) the vector
/// instructions of the lane loops' transcendentals and of the compiled tapes, at once (a
/// usage error where the CPU lacks them).
void add_isa_option(OptionTable& t);

/// The text of `fortu --help`: the commands, then run's options.
std::string usage_text();

}  // namespace fortu
