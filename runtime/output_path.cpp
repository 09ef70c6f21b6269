// runtime/output_path.cpp — extensions, and the number conversion of a series parsed by hand:
// a user's path is never passed to printf as a format string.
#include "runtime/output_path.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cstddef>

namespace fortu {
namespace {

struct Conversion {
    std::size_t length = 0;   ///< characters from '%' to 'd' inclusive; 0 = not a conversion
    bool zero_pad = false;
    int width = 0;
};

Conversion conversion_at(std::string_view path, std::size_t at) {
    Conversion c;
    std::size_t i = at + 1;
    if (i < path.size() && path[i] == '0') {
        c.zero_pad = true;
        ++i;
    }
    const std::size_t digits_from = i;
    while (i < path.size() && std::isdigit(static_cast<unsigned char>(path[i])) && i - digits_from < 2) {
        c.width = c.width * 10 + (path[i] - '0');
        ++i;
    }
    if (i < path.size() && path[i] == 'd') c.length = i + 1 - at;
    return c;
}

}  // namespace

std::string path_extension(std::string_view path) {
    const auto dot = path.find_last_of("./");
    if (dot == std::string_view::npos || path[dot] != '.') return {};
    std::string ext(path.substr(dot + 1));
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool is_file_series(std::string_view path) {
    for (std::size_t i = 0; i < path.size(); ++i)
        if (path[i] == '%' && conversion_at(path, i).length > 0) return true;
    return false;
}

std::string file_series_name(std::string_view path, int number) {
    std::string out;
    for (std::size_t i = 0; i < path.size(); ++i) {
        const Conversion c = path[i] == '%' ? conversion_at(path, i) : Conversion{};
        if (c.length == 0) {
            out += path[i];
            continue;
        }
        if (c.width == 0) out += fmt::format("{}", number);
        else if (c.zero_pad) out += fmt::format("{:0{}d}", number, c.width);
        else out += fmt::format("{:{}d}", number, c.width);
        i += c.length - 1;
    }
    return out;
}

}  // namespace fortu
