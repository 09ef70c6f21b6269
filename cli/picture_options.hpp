// cli/picture_options.hpp — the picture options `--scale`, `--levels`, `--legend` (rows of the
// run and singular option tables) and the legend's words for a plane of a 3D model.
#pragma once

#include "cli/option_table.hpp"
#include "runtime/field.hpp"
#include "runtime/output_options.hpp"

#include <string>

namespace fortu {

/// Adds the three rows to `table`; their values go into `style`.
void add_picture_style_options(OptionTable& table, PictureStyle& style);

/// `auto`, `symmetric` or `A:B` (A < 0 < B). Throws UsageError naming --scale.
ScaleChoice parse_scale_choice(const std::string& text);

/// `N` (a whole number 1..100: N levels per side) or `v1,v2,...` (at most 100 values; one
/// value is written with a point, `2.0`). Sets style.level_count or style.levels. Throws UsageError.
void parse_levels(const std::string& text, PictureStyle& style);

/// `style` with the legend's axis names and plane for the picture of `field` as `fortu run`
/// evaluated it: an x plane (one column of a 3D grid) is drawn as y across, z up (`x = V`),
/// a y plane as x across, z up (`y = V`); anything else keeps `style`.
PictureStyle plane_picture_style(const Field& field, PictureStyle style);

}  // namespace fortu
