// runtime/progress.cpp — the drawing thread: `label [#####.....]  45%  1,234/2,700  3.20 s`,
// redrawn in place with a carriage return, cleared with ESC[K at the end.
#include "runtime/progress.hpp"

#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <algorithm>

#include <sys/ioctl.h>
#include <unistd.h>

namespace fortu {
namespace {

constexpr auto kRedraw = std::chrono::milliseconds(100);

thread_local bool quiet_thread = false;

int terminal_width(std::FILE* out) {
    winsize size{};
    if (ioctl(fileno(out), TIOCGWINSZ, &size) == 0 && size.ws_col >= 20) return size.ws_col;
    return 80;
}

}  // namespace

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), out_(stderr), delay_(1.0),
      started_(std::chrono::steady_clock::now()) {
    start(!quiet_thread && isatty(fileno(stderr)) != 0);
}

Progress::Quiet::Quiet() : was_(quiet_thread) { quiet_thread = true; }
Progress::Quiet::~Quiet() { quiet_thread = was_; }

Progress::Progress(std::string label, std::size_t total, std::FILE* out, double delay_seconds)
    : label_(std::move(label)), total_(total), out_(out), delay_(delay_seconds),
      started_(std::chrono::steady_clock::now()) {
    start(out != nullptr);
}

void Progress::start(bool draw) {
    if (draw) drawer_ = std::thread([this] { run(); });
}

void Progress::finish() {
    if (!drawer_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    drawer_.join();
    if (drawn_) {
        std::fputs("\r\033[K", out_);
        std::fflush(out_);
    }
}

void Progress::run() {
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, kRedraw, [this] { return stop_; })) {
        if (std::chrono::steady_clock::now() - started_ < delay_) continue;
        draw();
    }
}

void Progress::draw() {
    const std::size_t done = std::min(this->done(), total_);
    const double fraction = total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 0.0;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    std::string tail = fmt::format(" {:3.0f}%  {}/{}  {}", 100.0 * fraction, format_count(done),
                                   format_count(total_), format_duration(elapsed));
    if (fraction > 0.0 && fraction < 1.0) tail += "  eta " + format_duration(elapsed * (1.0 / fraction - 1.0));
    const int width = terminal_width(out_);
    const int bar = std::clamp(width - 4 - static_cast<int>(label_.size() + tail.size()), 0, 50);
    const int filled = static_cast<int>(fraction * bar);
    std::string line = "\r" + label_;
    if (bar >= 10) line += " [" + std::string(filled, '#') + std::string(bar - filled, '.') + "]";
    line += tail + "\033[K";
    std::fputs(line.c_str(), out_);
    std::fflush(out_);
    drawn_ = true;
}

}  // namespace fortu
