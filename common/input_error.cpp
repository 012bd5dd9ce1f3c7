// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/input_error.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

namespace mixload {

InputError::InputError(const std::string& key, const std::string& value, const std::string& allowed)
    : std::runtime_error("invalid " + key + " = " + value + ": allowed " + allowed) {}

std::optional<double> parseNumber(std::string_view s) {
    double v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return v;
}

std::string formatNumber(double v) {
    std::ostringstream os;
    os.precision(10);
    os << v;
    return os.str();
}

void requireRange(const std::string& key, double v, double lo, double hi, bool loInclusive,
                  bool hiInclusive) {
    const bool okLo = loInclusive ? v >= lo : v > lo;
    const bool okHi = hiInclusive ? v <= hi : v < hi;
    if (std::isfinite(v) && okLo && okHi) return;
    std::string range;
    if (std::isinf(hi)) {
        range = std::string(loInclusive ? ">= " : "> ") + formatNumber(lo);
    } else {
        range = std::string(loInclusive ? "[" : "(") + formatNumber(lo) + ", " + formatNumber(hi) +
                (hiInclusive ? "]" : ")");
    }
    throw InputError(key, formatNumber(v), range);
}

void requirePositive(const std::string& key, double v) {
    requireRange(key, v, 0.0, std::numeric_limits<double>::infinity(), false, true);
}

}  // namespace mixload
