// cli/python/picture.cpp — write_field to a temporary PNG, read back as bytes.
#include "cli/python/picture.hpp"

#include "runtime/output.hpp"
#include "runtime/output_error.hpp"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace py = pybind11;

namespace fortu::python {

py::bytes png_bytes(const Field& field) {
    static std::atomic<unsigned> counter{0};
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
        ("fortu-repr-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + ".png");
    std::string bytes, error;
    {
        py::gil_scoped_release release;
        try {
            write_field(field, path.string());
        } catch (const OutputError& e) {
            error = e.what();
        }
        std::ifstream in(path, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        bytes = text.str();
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
    }
    if (!error.empty()) throw std::runtime_error(error);
    return py::bytes(bytes);
}

}  // namespace fortu::python
