// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <stdexcept>
#include <string>

namespace mixload {

// Bad user input. The CLI turns it into exit code 2 and one line naming the key, the value and
// the allowed range, before anything has been written.
class InputError : public std::runtime_error {
public:
    InputError(const std::string& key, const std::string& value, const std::string& allowed);
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

std::string formatNumber(double v);

// Throws InputError unless lo <= v <= hi (inclusive flags choose strictness).
void requireRange(const std::string& key, double v, double lo, double hi, bool loInclusive = true,
                  bool hiInclusive = true);
void requirePositive(const std::string& key, double v);

}  // namespace mixload
