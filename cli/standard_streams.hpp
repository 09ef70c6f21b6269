// cli/standard_streams.hpp — `-` for the script and the output, as Unix tools do:
// `fortu run -` and `fortu check -` read the script from standard input (at most
// SourceFile::kMaxBytes, as files; diagnostics name it `<stdin>`), and `-o -` (or
// `-o /dev/stdout`) with `--format EXT` writes the output to standard output.
//
// Why a temporary file for `-o -`: every writer writes a file atomically beside its target
// (runtime/atomic_file.hpp) and some seek (EXR, TIFF); writing a temporary file and copying the finished file to standard output keeps every writer as it is and never sends
// half a file down a pipe.
#pragma once

#include "cli/cli_options.hpp"
#include "grammar/source.hpp"

#include <iosfwd>
#include <memory>
#include <string>

namespace fortu {

/// The script a command names: a file, or standard input for "-" (read once; a second "-"
/// gets the same text). nullptr and `error` (`cannot read '<stdin>': ...`) on failure.
std::shared_ptr<SourceFile> load_script_argument(const std::string& argument, std::string& error);

/// How a script argument is named in messages: `<stdin>` for "-".
std::string shown_script_name(const std::string& argument);

/// Throws UsageError unless `-o -` and --format agree: --format is given exactly when the
/// output is standard output, names a format fortu writes, and a binary format is not sent to
/// a terminal.
void check_stdout_output(const CliOptions& o, bool stdout_is_terminal);

/// An output sent to standard output: a temporary file (in TMPDIR, named and registered as the
/// writers' temporaries are, runtime/temp_files.hpp) that send() copies to standard output;
/// removed on destruction.
class StdoutOutput {
public:
    /// Throws OutputError when the temporary file cannot be made.
    explicit StdoutOutput(const std::string& extension);
    ~StdoutOutput();
    StdoutOutput(const StdoutOutput&) = delete;
    StdoutOutput& operator=(const StdoutOutput&) = delete;

    /// Where the writer writes.
    const std::string& path() const { return path_; }
    /// Copies the written file to standard output; throws OutputError naming `<stdout>`.
    void send() const;

private:
    std::string path_;
    int slot_ = -1;   ///< remember_temporary()'s
};

/// `<stdout>` for the path of the live StdoutOutput, else `path` (for `wrote` lines).
std::string shown_output_path(const std::string& path);

/// Where a command's report goes: standard error when standard output carries the output.
std::ostream& report_stream(const CliOptions& o);

}  // namespace fortu
