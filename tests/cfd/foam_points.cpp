// SPDX-License-Identifier: GPL-3.0-or-later
#include "foam_points.hpp"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>

namespace mixload::testing {

std::vector<std::array<double, 3>> readFoamPoints(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + file.string());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const bool binary = text.find("format      binary") != std::string::npos ||
                        text.find("format binary") != std::string::npos;
    // The data starts after the header's closing brace: a count, then '('.
    size_t at = text.find('}', text.find("FoamFile"));
    if (at == std::string::npos) throw std::runtime_error("no FoamFile header in " + file.string());
    size_t open = at;
    long n = -1;
    while ((open = text.find('(', open + 1)) != std::string::npos) {
        size_t back = open;
        while (back > 0 && std::isspace(static_cast<unsigned char>(text[back - 1]))) --back;
        size_t start = back;
        while (start > 0 && std::isdigit(static_cast<unsigned char>(text[start - 1]))) --start;
        if (start < back) {
            n = std::stol(text.substr(start, back - start));
            break;
        }
    }
    if (n < 0) throw std::runtime_error("no point count in " + file.string());
    std::vector<std::array<double, 3>> pts(static_cast<size_t>(n));
    if (binary) {
        if (open + 1 + pts.size() * 24 > text.size())
            throw std::runtime_error("truncated " + file.string());
        std::memcpy(pts.data(), text.data() + open + 1, pts.size() * 24);
        return pts;
    }
    std::istringstream is(text.substr(open + 1));
    for (auto& p : pts) {
        char c;
        is >> c >> p[0] >> p[1] >> p[2] >> c;
    }
    if (!is) throw std::runtime_error("short ascii list in " + file.string());
    return pts;
}

}  // namespace mixload::testing
