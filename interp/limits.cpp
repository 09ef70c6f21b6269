// interp/limits.cpp — the table of limits.def and what is generated from it.
#include "interp/limits.hpp"

#include <fmt/format.h>

#include "runtime/resources.hpp"

#include <charconv>
#include <cstdint>

namespace fortu {
namespace {

constexpr LimitInfo kLimits[] = {
#define FORTU_LIMIT(id, name, value, what) {LimitId::id, name, value, what},
#include "interp/limits.def"
};
static_assert(std::size(kLimits) == kLimitCount);

std::string names() {
    std::string out;
    for (const LimitInfo& l : kLimits) out += fmt::format("{}{}", out.empty() ? "" : ", ", l.name);
    return out;
}

}  // namespace

std::span<const LimitInfo> limit_table() { return kLimits; }

const LimitInfo& limit_info(LimitId id) { return kLimits[static_cast<std::size_t>(id)]; }

Limits::Limits() {
    for (const LimitInfo& l : kLimits) set(l.id, l.default_value);
}

std::string Limits::parse(std::string_view text) {
    const auto equals = text.find('=');
    if (equals == std::string_view::npos) return fmt::format("'{}' is not NAME=VALUE (names: {})", text, names());
    const std::string_view name = text.substr(0, equals), value = text.substr(equals + 1);
    for (const LimitInfo& l : kLimits) {
        if (l.name != name) continue;
        long long number = 0;
        const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
        if (error != std::errc{} || end != value.data() + value.size() || number < 1)
            return fmt::format("'{}' is not a whole number from 1 for limit '{}'", value, name);
        set(l.id, number);
        return {};
    }
    return fmt::format("unknown limit '{}' (names: {})", name, names());
}

std::string limit_hint(LimitId id, long long value) {
    const LimitInfo& l = limit_info(id);
    return fmt::format("the limit '{}' is {}; raise it with --limit {}=N", l.name, format_count(static_cast<std::uint64_t>(value)), l.name);
}

std::string limits_usage(int indent) {
    std::string out;
    for (const LimitInfo& l : kLimits) {
        if (!out.empty()) out.append("\n").append(static_cast<std::size_t>(indent), ' ');
        out += fmt::format("{:<14} {:>11}  {}", l.name, l.default_value, l.what);
    }
    return out;
}

}  // namespace fortu
