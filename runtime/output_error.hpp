// runtime/output_error.hpp — the one exception every writer throws: "cannot write 'PATH':
// REASON". The destination is never left half-written when it is thrown (atomic_file.hpp).
#pragma once

#include <stdexcept>
#include <string>

namespace fortu {

/// A failure to write an output file; what() is `cannot write 'PATH': REASON`.
class OutputError : public std::runtime_error {
public:
    OutputError(const std::string& path, const std::string& reason)
        : std::runtime_error("cannot write '" + path + "': " + reason), path_(path), reason_(reason) {}

    /// The destination the user asked for (never the temporary).
    const std::string& path() const { return path_; }
    /// The reason alone, without the path.
    const std::string& reason() const { return reason_; }

private:
    std::string path_;
    std::string reason_;
};

}  // namespace fortu
