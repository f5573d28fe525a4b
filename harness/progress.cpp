#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace sph {

Progress::Progress(std::string label, long total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled && isatty(fileno(stderr))),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

void Progress::update(long done, const std::string& detail) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < total_ && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double left = done > 0 ? elapsed * double(total_ - done) / double(done) : 0;
    std::fprintf(stderr, "\r%s %ld/%ld (%3.0f%%) %s, %.0f s left   ", label_.c_str(), done, total_,
                 100.0 * double(done) / double(total_ > 0 ? total_ : 1), detail.c_str(), left);
    std::fflush(stderr);
}

void Progress::finish() {
    if (enabled_) std::fprintf(stderr, "\r\033[K");
}

}  // namespace sph
