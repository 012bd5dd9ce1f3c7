// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace mixload {

// Bad user input. The CLI turns it into exit code 2 and one line naming the key, the value and
// the allowed range, before anything has been written.
class InputError : public std::runtime_error {
public:
    InputError(const std::string& key, const std::string& value, const std::string& allowed);
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

std::string formatNumber(double v);
// The number a whole string spells (no leading blanks, no trailing text), or nothing: OpenFOAM time
// directory names, and list entries that may be a number or a name.
std::optional<double> parseNumber(std::string_view s);

// Throws InputError unless lo <= v <= hi (inclusive flags choose strictness).
void requireRange(const std::string& key, double v, double lo, double hi, bool loInclusive = true,
                  bool hiInclusive = true);
void requirePositive(const std::string& key, double v);

// Runs f(); any failure but an InputError becomes an InputError that names file once (readers of
// stored files: a truncated or foreign file is bad input, exit 2).
template <class F>
auto namingFile(const std::filesystem::path& file, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& ex) {
        const std::string what = ex.what();
        throw InputError(what.rfind(file.string(), 0) == 0 ? what : file.string() + ": " + what);
    }
}

}  // namespace mixload
