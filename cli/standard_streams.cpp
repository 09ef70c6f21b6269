// cli/standard_streams.cpp — see standard_streams.hpp.
#include "cli/standard_streams.hpp"

#include "runtime/output_error.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/temp_files.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <optional>
#include <signal.h>
#include <unistd.h>

namespace fortu {
namespace {

constexpr const char* kStdinName = "<stdin>";
constexpr const char* kStdoutName = "<stdout>";

/// The live StdoutOutput's file ("" when none): one output goes to standard output per run.
std::string& live_stdout_path() {
    static std::string path;
    return path;
}

std::shared_ptr<SourceFile> read_stdin(std::string& error) {
    std::string text;
    char buffer[1 << 16];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, stdin)) > 0) {
        if (text.size() + n > SourceFile::kMaxBytes) {
            error = fmt::format("cannot read '{}': larger than {} MiB, which no script needs", kStdinName,
                                SourceFile::kMaxBytes >> 20);
            return nullptr;
        }
        text.append(buffer, n);
    }
    if (std::ferror(stdin)) {
        error = fmt::format("cannot read '{}': {}", kStdinName, std::strerror(errno));
        return nullptr;
    }
    return std::make_shared<SourceFile>(kStdinName, std::move(text));
}

/// "png|jpg|tif|..." : each format by its usual extension.
std::string format_names() {
    std::string names;
    for (const OutputFormat& format : output_formats()) {
        if (!names.empty()) names += '|';
        names += format.extension();
    }
    return names;
}

}  // namespace

bool is_stdout_path(const std::string& path) { return path == "-" || path == "/dev/stdout"; }

std::shared_ptr<SourceFile> load_script_argument(const std::string& argument, std::string& error) {
    if (argument != "-") return SourceFile::load(argument, error);
    // Standard input can be read once; `fortu check - -` and a run's second pass share it.
    static std::shared_ptr<SourceFile> text;
    static std::string text_error;
    static bool read = false;
    if (!read) {
        text = read_stdin(text_error);
        read = true;
    }
    error = text_error;
    return text;
}

std::string shown_script_name(const std::string& argument) { return argument == "-" ? kStdinName : argument; }

void check_stdout_output(const CliOptions& o, bool stdout_is_terminal) {
    const bool to_stdout = is_stdout_path(o.output);
    if (!to_stdout) {
        if (!o.format.empty())
            throw UsageError(fmt::format("--format applies to -o - (standard output); '{}' names its format by its "
                                         "extension", o.output.empty() ? std::string("no -o") : o.output));
        return;
    }
    if (o.format.empty())
        throw UsageError(fmt::format("-o {}: give the format with --format ({})", o.output,
                                     format_names()));
    const OutputFormat* format = output_format_for("stdout." + o.format);
    if (!format)
        throw UsageError(fmt::format("--format: unknown output format '{}' (use {})", o.format,
                                     format_names()));
    if (format->extension() == "pvti")
        throw UsageError(fmt::format("-o {}: a .pvti names piece files beside it; give it a path (-o f.pvti)", o.output));
    const bool text = format->text || (format->extension() == "stl" && o.ascii);
    if (!text && stdout_is_terminal)
        throw UsageError(fmt::format("-o {}: {} is binary and standard output is a terminal; redirect it to a file "
                                     "or a pipe (fortu run MODEL -o - --format {} > out.{})",
                                     o.output, format->name, o.format, o.format));
}

StdoutOutput::StdoutOutput(const std::string& extension) {
    std::error_code ec;
    std::filesystem::path base = std::filesystem::temp_directory_path(ec);
    if (ec) base = "/tmp";
    // Named as the writers' temporaries are, so SIGINT/SIGTERM/SIGHUP remove it and a later
    // run writing into the same folder removes it if this process is killed.
    const std::string suffix = "." + extension;
    std::string path = (base / temporary_file_name("stdout" + suffix, "XXXXXX")).string();
    const int fd = ::mkstemps(path.data(), static_cast<int>(suffix.size()));
    if (fd < 0) throw OutputError(kStdoutName, std::string("cannot make a temporary file: ") + std::strerror(errno));
    ::close(fd);
    path_ = path;
    slot_ = remember_temporary(path_);
    live_stdout_path() = path_;
}

StdoutOutput::~StdoutOutput() {
    live_stdout_path().clear();
    ::unlink(path_.c_str());
    if (slot_ >= 0) forget_temporary(slot_);
}

void StdoutOutput::send() const {
    std::FILE* file = std::fopen(path_.c_str(), "rb");
    if (!file) throw OutputError(kStdoutName, std::string("the output was not written: ") + std::strerror(errno));
    std::cout.flush();
    // A reader that stops early (`| head`) closes the pipe: remove the temporary, then end by
    // SIGPIPE as any Unix filter does, without a message.
    struct sigaction ignore {}, previous{};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGPIPE, &ignore, &previous);
    char buffer[1 << 16];
    std::size_t n = 0;
    bool failed = false;
    while (!failed && (n = std::fread(buffer, 1, sizeof buffer, file)) > 0)
        failed = std::fwrite(buffer, 1, n, stdout) != n;
    std::fclose(file);
    if (!failed) failed = std::fflush(stdout) != 0;
    const int error = errno;
    ::sigaction(SIGPIPE, &previous, nullptr);
    if (failed && error == EPIPE) {
        ::unlink(path_.c_str());
        ::raise(SIGPIPE);
    }
    if (failed) throw OutputError(kStdoutName, std::strerror(error));
}

std::string shown_output_path(const std::string& path) {
    return !path.empty() && path == live_stdout_path() ? kStdoutName : path;
}

std::ostream& report_stream(const CliOptions& o) {
    return !o.output.empty() && (is_stdout_path(o.output) || o.output == live_stdout_path()) ? std::cerr : std::cout;
}

}  // namespace fortu
