// runtime/value_compare.hpp — numbers compared under an absolute tolerance, the rule every
// golden comparator shares: NaN matches NaN, infinities match exactly, and a failure names
// the worst place with both values.
#pragma once

#include "runtime/field.hpp"

#include <optional>
#include <span>
#include <string>

namespace fortu {

/// Two values agree: within `tolerance`, or the same non-finite value.
bool values_agree(double expected, double actual, double tolerance);

/// How far apart two values are: 0 when they agree exactly, infinity when only one is finite.
double value_distance(double expected, double actual);

/// Compares reference values (one per node of `field`'s grid, image order) with the field's:
/// "" when every one agrees, else `N of M values differ by more than T; worst at node (col C,
/// row R) = (X, Y): expected E, got A`.
std::string compare_field_values(std::span<const double> expected, const Field& field, double tolerance);

/// The bytes of a file, or nullopt if it cannot be read.
std::optional<std::string> read_file_bytes(const std::string& path);

}  // namespace fortu
