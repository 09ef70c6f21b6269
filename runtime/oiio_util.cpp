// runtime/oiio_util.cpp — see oiio_util.hpp.
#include "runtime/oiio_util.hpp"

namespace fortu {

std::string oiio_reason(std::string message, const std::string& temp_path, const std::string& path) {
    if (message.empty()) return "OpenImageIO reported an unknown error";
    for (std::size_t at = message.find(temp_path); !temp_path.empty() && at != std::string::npos;
         at = message.find(temp_path, at + path.size()))
        message.replace(at, temp_path.size(), path);
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
    return message;
}

}  // namespace fortu
