// runtime/image_compare.cpp — see image_compare.hpp: the calls go through the image module,
// and the diff image is written atomically like every other output.
#include "runtime/image_compare.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/image_io.hpp"
#include "runtime/oiio_util.hpp"
#include "runtime/output_error.hpp"

namespace fortu {

ImageComparison compare_images(const std::string& expected_path, const std::string& actual_path,
                               double tolerance) {
    ImageComparison failed;
    const ImageModule* module = image_module(failed.error);
    if (!module) return failed;
    return module->compare(expected_path, actual_path, tolerance);
}

std::string write_diff_image(const std::string& expected_path, const std::string& actual_path,
                             int subimage, const std::string& diff_path) {
    std::string error;
    const ImageModule* module = image_module(error);
    if (!module) return error;
    try {
        write_atomically(diff_path, [&](const std::string& temp) {
            const std::string reason = module->write_difference(expected_path, actual_path, subimage, temp);
            if (!reason.empty()) throw OutputError(diff_path, oiio_reason(reason, temp, diff_path));
        });
    } catch (const OutputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace fortu
