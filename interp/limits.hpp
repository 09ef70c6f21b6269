// interp/limits.hpp — compile-time budgets: a script may run FOR loops and inline functions,
// so its text says little about the work and memory it asks for (three nested loops of
// 1,000, an array doubled 40 times, a picture claiming 30000² pixels). Every budget is a row
// of limits.def; exceeding one is a located diagnostic, and `--limit name=value` raises it.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace fortu {

enum class LimitId {
#define FORTU_LIMIT(id, name, value, what) id,
#include "interp/limits.def"
};

inline constexpr std::size_t kLimitCount = 0
#define FORTU_LIMIT(id, name, value, what) +1
#include "interp/limits.def"
    ;

struct LimitInfo {
    LimitId id;
    std::string_view name;
    long long default_value;
    std::string_view what;
};

/// Every row of limits.def, in order.
std::span<const LimitInfo> limit_table();

/// The values in force: the defaults unless set.
class Limits {
public:
    Limits();
    long long operator[](LimitId id) const { return values_[static_cast<std::size_t>(id)]; }
    void set(LimitId id, long long value) { values_[static_cast<std::size_t>(id)] = value; }
    /// `NAME=VALUE` from the command line; "" or why it is refused.
    std::string parse(std::string_view text);

private:
    std::array<long long, kLimitCount> values_{};
};

/// The row for `id`.
const LimitInfo& limit_info(LimitId id);

/// The end of a diagnostic for an exceeded budget: "(the limit 'work' is 20,000,000; raise it
/// with --limit work=N)".
std::string limit_hint(LimitId id, long long value);

/// The README/--help table: one line per limit, `name  default  what`.
std::string limits_usage(int indent);

}  // namespace fortu
