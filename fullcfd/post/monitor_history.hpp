// SPDX-License-Identifier: GPL-3.0-or-later
// A function object writes one history file per (re)start: <monitorDir>/<startTime>/<file>.
#pragma once
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace mixload::post {

// Merges the segments in start-time order; a restart replaces the tail of the earlier history from
// its start time on. parse(line stream, sample&) returns false for lines to skip.
template <class Sample, class Parse>
std::vector<Sample> readSegments(const std::filesystem::path& monitorDir, const std::string& file,
                                 Parse parse) {
    namespace fs = std::filesystem;
    std::map<double, fs::path> segments;
    if (fs::exists(monitorDir))
        for (const auto& e : fs::directory_iterator(monitorDir)) {
            const auto f = e.path() / file;
            if (e.is_directory() && fs::exists(f))
                segments[std::atof(e.path().filename().c_str())] = f;
        }
    std::vector<Sample> out;
    for (const auto& [start, path] : segments) {
        while (!out.empty() && out.back().t > start + 1e-12) out.pop_back();
        std::ifstream is(path);
        std::string line;
        while (std::getline(is, line)) {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream ls(line);
            Sample s{};
            if (parse(ls, s)) out.push_back(s);
        }
    }
    return out;
}

}  // namespace mixload::post
