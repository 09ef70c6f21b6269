// cli/fv_options.cpp — --palette, --steps and --compare: parsing and checking (fv_options.hpp).
#include "cli/fv_options.hpp"

#include <filesystem>
#include <fmt/format.h>

namespace fortu {

void add_fv_options(OptionTable& t, CliOptions& o) {
    t.option("--palette", "8|24|float", "how the fv engine stores M-images: P = 256 grey (default),\n"
                                        "P = 2^24 RGB, or unquantised doubles",
             [&o](const std::string& p) {
                 if (p == "8") o.engine_settings.storage = MimageStorage::Grey8;
                 else if (p == "24") o.engine_settings.storage = MimageStorage::Rgb24;
                 else if (p == "float") o.engine_settings.storage = MimageStorage::Float;
                 else throw UsageError(fmt::format("--palette: '{}' is not 8, 24 or float", p));
             });
    t.option("--steps", "DIR", "the fv engine writes each named definition's value picture\n"
                               "and M-images into DIR as it computes them (01_NAME.png,\n"
                               "01_NAME_m1.png...), in order",
             [&o](const std::string& dir) {
                 if (dir.empty()) throw UsageError("--steps: give a folder");
                 if (std::filesystem::exists(dir) && !std::filesystem::is_directory(dir))
                     throw UsageError(fmt::format("--steps: '{}' is a file, not a folder", dir));
                 o.steps = dir;
             });
    t.option("--compare", "ENGINE", "also evaluate with ENGINE and report the result's error\n"
                                    "against it: max and RMS difference, where the sign differs",
             [&o](const std::string& e) {
                 o.compare = find_engine(e);
                 if (!o.compare)
                     throw UsageError(fmt::format("--compare: unknown engine '{}' (use {})", e, engine_names(", ", " or ")));
                 if (o.compare->capabilities().sign_only)
                     throw UsageError(fmt::format("--compare: the {} engine computes no values to compare with (use {})",
                                                  e, engine_names(", ", " or ", [](const EngineCapabilities& c) {
                                                      return !c.sign_only;
                                                  })));
             });
}

void check_fv_options(const CliOptions& o) {
    if (o.engine_settings.storage && !o.engine->capabilities().palette)
        throw UsageError(fmt::format("--palette: the {} engine stores no M-images (use --engine {})", o.engine->name(),
                                     engine_names(", ", " or ", [](const EngineCapabilities& c) { return c.palette; })));
    if (!o.steps.empty() && !o.engine->capabilities().steps)
        throw UsageError(fmt::format("--steps: the {} engine does not hand out its steps (use --engine {})",
                                     o.engine->name(),
                                     engine_names(", ", " or ", [](const EngineCapabilities& c) { return c.steps; })));
    if (o.compare && o.engine->capabilities().sign_only)
        throw UsageError(fmt::format("--compare: the {} engine computes no values to compare", o.engine->name()));
}

}  // namespace fortu
