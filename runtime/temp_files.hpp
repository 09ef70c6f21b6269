// runtime/temp_files.hpp — the temporaries of atomic writes (atomic_file.hpp) must not outlive
// the run: a fixed table of their names that SIGINT/SIGTERM/SIGHUP handlers remove before the
// process dies (async-signal-safe: no allocation, only unlink), and names that carry the
// writer's pid so a later run into the same folder removes those of processes that died by
// SIGKILL or a crash.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace fortu {

/// The temporary's name for destination file name `name` (`out.png`), unique part `unique`:
/// `.out.png.tmp<PID>-<unique>.png` (the real extension last, so OpenImageIO picks the format).
std::string temporary_file_name(std::string_view name, std::string_view unique);

/// The pid in a name made by temporary_file_name(), or nullopt for any other name.
std::optional<long> temporary_file_owner(std::string_view name);

/// Removes in `dir` the temporaries whose owner process no longer exists. Best effort: errors
/// are ignored (the folder may be unreadable; the write reports its own errors).
void remove_stale_temporaries(const std::string& dir);

/// Registers `path` for removal if the process is ended by SIGINT, SIGTERM or SIGHUP (the
/// handlers are installed on first use where the signal's action is still the default).
/// Returns the slot to pass to forget_temporary(), or -1 when the table is full (the name
/// still lets a later run remove it).
int remember_temporary(const std::string& path);
void forget_temporary(int slot);

}  // namespace fortu
