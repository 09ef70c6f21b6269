// runtime/oiio_util.hpp — small helpers shared by the OpenImageIO writers (picture, EXR):
// error text that names the user's file rather than the temporary.
#pragma once

#include <string>

namespace fortu {

/// `message` (an OpenImageIO error) with every mention of `temp_path` replaced by `path`, and
/// a generic text if it is empty.
std::string oiio_reason(std::string message, const std::string& temp_path, const std::string& path);

}  // namespace fortu
