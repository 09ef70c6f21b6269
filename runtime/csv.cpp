// runtime/csv.cpp — CSV text, formatted with fmt into a buffer flushed in blocks.
#include "runtime/csv.hpp"

#include "runtime/atomic_file.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <string_view>

namespace fortu {
namespace {

constexpr std::size_t kFlushAt = 1 << 20;   // bytes

void append_number(fmt::memory_buffer& out, double v) {
    if (std::isfinite(v)) {
        // printf's %.17g, as std::to_chars defines it, without fmt's format-string path
        // (a 1024² grid's CSV: 3 M numbers).
        char text[32];
        const std::to_chars_result r = std::to_chars(text, text + sizeof text, v, std::chars_format::general, 17);
        out.append(text, r.ptr);
        return;
    }
    const std::string_view text = std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
    out.append(text.data(), text.data() + text.size());
}

}  // namespace

void write_csv(const Field& field, const OutputTarget& target, const OutputOptions&) {
    const std::string& path = target.path;
    const Grid& g = field.grid;
    write_file_atomically(path, [&](OutputFile& file) {
        fmt::memory_buffer out;
        const std::string_view header = g.dims == 3 ? "x,y,z,value\n" : "x,y,value\n";
        out.append(header.data(), header.data() + header.size());
        for (int s = 0; s < g.slices(); ++s)
            for (int r = 0; r < g.rows(); ++r)
                for (int c = 0; c < g.cols(); ++c) {
                    append_number(out, g.x_at(c));
                    out.push_back(',');
                    append_number(out, g.y_at(r));
                    out.push_back(',');
                    if (g.dims == 3) {
                        append_number(out, g.z_at(s));
                        out.push_back(',');
                    }
                    append_number(out, field.values[g.index(c, r, s)]);
                    out.push_back('\n');
                    if (out.size() >= kFlushAt) {
                        file.write(out.data(), out.size());
                        out.clear();
                    }
                }
        file.write(out.data(), out.size());
    });
}

}  // namespace fortu
