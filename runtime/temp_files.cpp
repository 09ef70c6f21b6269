// runtime/temp_files.cpp — see temp_files.hpp. The signal handler may only use
// async-signal-safe calls, so the table is fixed-size char arrays guarded by atomics.
#include "runtime/temp_files.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <csignal>
#include <cstring>
#include <filesystem>

#include <unistd.h>

namespace fortu {
namespace {

constexpr std::string_view kMarker = ".tmp";
constexpr std::size_t kUniqueLength = 6;

struct Slot {
    std::atomic<bool> used{false};
    std::atomic<bool> armed{false};   ///< `path` complete and to be removed on a signal
    char path[4096]{};
};
std::array<Slot, 32> slots;

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_temporaries_and_die(int signal) {
    const int saved = errno;
    for (Slot& slot : slots)
        if (slot.armed.load(std::memory_order_acquire)) ::unlink(slot.path);
    errno = saved;
    // Die of the same signal, so the parent sees what happened.
    std::signal(signal, SIG_DFL);
    ::raise(signal);
}

void install_handlers_once() {
    static std::atomic<bool> installed{false};
    if (installed.exchange(true)) return;
    for (int signal : kSignals) {
        struct sigaction current {};
        if (::sigaction(signal, nullptr, &current) != 0) continue;
        // A handler someone else installed (the REPL's SIGINT) or an ignored signal stays.
        if (current.sa_handler != SIG_DFL || (current.sa_flags & SA_SIGINFO)) continue;
        struct sigaction action {};
        action.sa_handler = remove_temporaries_and_die;
        sigemptyset(&action.sa_mask);
        for (int other : kSignals) sigaddset(&action.sa_mask, other);
        ::sigaction(signal, &action, nullptr);
    }
}

bool process_exists(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH); }

}  // namespace

std::string temporary_file_name(std::string_view name, std::string_view unique) {
    const std::string_view::size_type dot = name.rfind('.');
    const std::string_view extension = dot == std::string_view::npos || dot == 0 ? std::string_view{} : name.substr(dot);
    std::string out = ".";
    out.append(name).append(kMarker).append(std::to_string(::getpid())).append("-").append(unique).append(extension);
    return out;
}

std::optional<long> temporary_file_owner(std::string_view name) {
    if (!name.starts_with('.')) return std::nullopt;
    // Search from the right: the destination's own name may contain ".tmp".
    for (auto at = name.rfind(kMarker); at != std::string_view::npos && at > 0; at = name.rfind(kMarker, at - 1)) {
        const char* first = name.data() + at + kMarker.size();
        const char* last = name.data() + name.size();
        long pid = 0;
        const auto [end, error] = std::from_chars(first, last, pid);
        if (error != std::errc{} || end == first || end == last || *end != '-') continue;
        const std::string_view rest(end + 1, static_cast<std::size_t>(last - end - 1));
        if (rest.size() < kUniqueLength) continue;
        const std::string_view unique = rest.substr(0, kUniqueLength);
        const std::string_view extension = rest.substr(kUniqueLength);
        if (!std::all_of(unique.begin(), unique.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)); }))
            continue;
        if (!extension.empty() && !extension.starts_with('.')) continue;
        return pid;
    }
    return std::nullopt;
}

void remove_stale_temporaries(const std::string& dir) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::directory_iterator it(dir.empty() ? fs::path(".") : fs::path(dir), ec);
    if (ec) return;
    const long self = ::getpid();
    for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) return;
        const std::string name = it->path().filename().string();
        const auto owner = temporary_file_owner(name);
        if (!owner || *owner == self || process_exists(*owner)) continue;
        std::error_code ignored;
        if (it->is_regular_file(ignored)) fs::remove(it->path(), ignored);
    }
}

int remember_temporary(const std::string& path) {
    install_handlers_once();
    if (path.size() >= sizeof(Slot::path)) return -1;
    for (std::size_t i = 0; i < slots.size(); ++i) {
        bool expected = false;
        if (!slots[i].used.compare_exchange_strong(expected, true)) continue;
        std::memcpy(slots[i].path, path.c_str(), path.size() + 1);
        slots[i].armed.store(true, std::memory_order_release);
        return static_cast<int>(i);
    }
    return -1;
}

void forget_temporary(int slot) {
    if (slot < 0 || slot >= static_cast<int>(slots.size())) return;
    slots[static_cast<std::size_t>(slot)].armed.store(false, std::memory_order_release);
    slots[static_cast<std::size_t>(slot)].used.store(false, std::memory_order_release);
}

}  // namespace fortu
