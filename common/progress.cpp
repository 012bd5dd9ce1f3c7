// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace mixload {

Progress::Progress(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      lastDraw_() {}

void Progress::update(double fraction, const std::string& detail) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - lastDraw_ < std::chrono::milliseconds(200)) return;
    lastDraw_ = now;
    fraction = std::clamp(fraction, 0.0, 1.0);
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    char eta[32] = "--";
    if (fraction > 0.01) {
        const int s = static_cast<int>(elapsed * (1.0 - fraction) / fraction);
        std::snprintf(eta, sizeof eta, "%dm%02ds", s / 60, s % 60);
    }
    std::fprintf(stderr, "\r%s %5.1f%%  ETA %s  %s\033[K", label_.c_str(), 100.0 * fraction, eta,
                 detail.c_str());
    std::fflush(stderr);
}

void Progress::finish() {
    if (!enabled_) return;
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
}

}  // namespace mixload
