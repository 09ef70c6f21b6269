// runtime/image_compare_oiio.cpp — the OpenImageIO side of image_compare.hpp, built into the
// image module (libfortu_image.so, see image_io.hpp). NaN pixels (invalid points in an EXR)
// defeat ImageBufAlgo::compare's arithmetic, so parts holding them are judged by a scan.
#include "runtime/image_compare.hpp"


#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <cmath>

namespace fortu {
namespace {

namespace OIIO = OIIO_NAMESPACE;

/// OpenImageIO's message on one line (a report line per problem).
std::string one_line(std::string message) {
    for (std::size_t at; (at = message.find('\n')) != std::string::npos;) message.replace(at, 1, "; ");
    return message;
}

int subimage_count(const std::string& path, std::string& error) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        error = fmt::format("cannot read '{}': {}", path, one_line(OIIO::geterror()));
        return 0;
    }
    int n = 0;
    while (in->seek_subimage(n, 0)) ++n;
    in->close();
    return n;
}

/// Reads one subimage as float pixels; "" or an error text.
std::string read(OIIO::ImageBuf& buf, const std::string& path, int subimage) {
    buf.reset(path, subimage, 0);
    if (!buf.read(subimage, 0, /*force=*/true, OIIO::TypeDesc::FLOAT) || buf.has_error())
        return fmt::format("cannot read '{}': {}", path, one_line(buf.geterror()));
    return "";
}

std::string shape(const OIIO::ImageBuf& b) {
    return fmt::format("{}x{} with {} channel{}", b.spec().width, b.spec().height, b.nchannels(),
                       b.nchannels() == 1 ? "" : "s");
}

}  // namespace

ImageComparison oiio_compare_images(const std::string& expected_path, const std::string& actual_path,
                                    double tolerance) {
    ImageComparison result;
    const int expected_parts = subimage_count(expected_path, result.error);
    if (!result.error.empty()) return result;
    const int actual_parts = subimage_count(actual_path, result.error);
    if (!result.error.empty()) return result;
    if (expected_parts != actual_parts) {
        result.error = fmt::format("the reference has {} subimage(s), the new image {}", expected_parts, actual_parts);
        return result;
    }
    double worst = -1.0;
    for (int part = 0; part < expected_parts; ++part) {
        OIIO::ImageBuf a, b;
        if (std::string e = read(a, expected_path, part); !e.empty()) { result.error = e; return result; }
        if (std::string e = read(b, actual_path, part); !e.empty()) { result.error = e; return result; }
        if (a.spec().width != b.spec().width || a.spec().height != b.spec().height ||
            a.nchannels() != b.nchannels()) {
            result.error = fmt::format("the reference is {}, the new image {}", shape(a), shape(b));
            return result;
        }
        const int w = a.spec().width, h = a.spec().height, nc = a.nchannels();
        result.pixels += static_cast<unsigned long long>(w) * h;
        // Pixel by pixel: exact NaN/inf handling, and the worst pixel over all subimages.
        std::vector<float> pa(static_cast<std::size_t>(w) * h * nc), pb(pa.size());
        a.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, pa.data());
        b.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, pb.data());
        // ImageBufAlgo::compare judges finite data; NaN (an EXR's invalid points) defeats its
        // arithmetic, so a part holding a non-finite value is judged by the scan below alone.
        bool finite = true;
        for (std::size_t i = 0; i < pa.size() && finite; ++i) finite = std::isfinite(pa[i]) && std::isfinite(pb[i]);
        unsigned long long failing = 0;
        double part_worst = -1.0;
        std::size_t worst_p = 0;
        if (finite) {
            const OIIO::ImageBufAlgo::CompareResults cr =
                OIIO::ImageBufAlgo::compare(a, b, static_cast<float>(tolerance), static_cast<float>(tolerance));
            // (OpenImageIO 2.4 also sets cr.error when pixels fail; both images were read above,
            // so the counts are what matter.)
            failing = cr.nfail;
            part_worst = cr.maxerror;
            worst_p = static_cast<std::size_t>(cr.maxy - a.spec().y) * w + (cr.maxx - a.spec().x);
        } else {
            for (std::size_t p = 0; p < static_cast<std::size_t>(w) * h; ++p) {
                double pixel_error = 0.0;
                for (int c = 0; c < nc; ++c) {
                    const float x = pa[p * nc + c], y = pb[p * nc + c];
                    const bool same_invalid = (std::isnan(x) && std::isnan(y)) || x == y;
                    const double d = std::isfinite(x) && std::isfinite(y) ? std::fabs(double(x) - double(y))
                                     : same_invalid                       ? 0.0
                                                                          : INFINITY;
                    pixel_error = std::max(pixel_error, d);
                }
                if (pixel_error > tolerance) ++failing;
                if (pixel_error > part_worst) { part_worst = pixel_error; worst_p = p; }
            }
        }
        result.failing += failing;
        if (part_worst > worst && worst_p < static_cast<std::size_t>(w) * h) {
            worst = part_worst;
            result.max_error = part_worst;
            result.worst_x = static_cast<int>(worst_p % w);
            result.worst_y = static_cast<int>(worst_p / w);
            result.worst_subimage = part;
            result.expected.assign(pa.begin() + worst_p * nc, pa.begin() + (worst_p + 1) * nc);
            result.actual.assign(pb.begin() + worst_p * nc, pb.begin() + (worst_p + 1) * nc);
            result.channels = a.spec().channelnames;
        }
    }
    return result;
}

std::string oiio_write_difference(const std::string& expected_path, const std::string& actual_path,
                                  int subimage, const std::string& file) {
    OIIO::ImageBuf a, b;
    if (std::string e = read(a, expected_path, subimage); !e.empty()) return e;
    if (std::string e = read(b, actual_path, subimage); !e.empty()) return e;
    OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(a, b);
    if (diff.has_error()) return fmt::format("cannot compute the difference: {}", diff.geterror());
    const bool picture = a.spec().format.size() == 1;  // 8-bit: stretch so the differences show
    if (picture) {
        const auto stats = OIIO::ImageBufAlgo::computePixelStats(diff);
        float largest = 0.0f;
        for (float m : stats.max) largest = std::max(largest, m);
        if (largest > 0) diff = OIIO::ImageBufAlgo::mul(diff, 1.0f / largest);
    }
    if (!diff.write(file, picture ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT)) {
        std::string reason = diff.geterror();
        return reason.empty() ? std::string("OpenImageIO reported an unknown error") : reason;
    }
    return "";
}

}  // namespace fortu
