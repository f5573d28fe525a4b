#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace sph {

Progress::Progress(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled && isatty(fileno(stderr))), start_(std::chrono::steady_clock::now()),
      last_(start_) {}

void Progress::update(double fraction, const std::string& detail) {
    if (!enabled_) return;
    fraction = std::clamp(fraction, 0.0, 1.0);
    const auto now = std::chrono::steady_clock::now();
    if (fraction < 1 && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double left = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
    std::fprintf(stderr, "\r%s %s (%3.0f%%), %.0f s left   ", label_.c_str(), detail.c_str(), 100.0 * fraction, left);
    std::fflush(stderr);
}

void Progress::finish() {
    if (enabled_) std::fprintf(stderr, "\r\033[K");
}

}  // namespace sph
