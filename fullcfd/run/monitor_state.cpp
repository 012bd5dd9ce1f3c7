// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/monitor_state.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "cases/mixer3d.hpp"
#include "common/atomic_file.hpp"
#include "post/foam_files.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

namespace {

fs::path propertiesIn(const fs::path& timeDir) { return timeDir / "uniform" / "functionObjects" / "functionObjectProperties"; }

std::vector<double> thinned(const std::vector<double>& v, std::size_t stride) {
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); i += stride) out.push_back(v[i]);
    if (!v.empty() && (v.size() - 1) % stride != 0) out.push_back(v.back());
    return out;
}

}  // namespace

nlohmann::json keptMonitorState(const fs::path& timeDir, std::size_t maxSamples) {
    const fs::path file = propertiesIn(timeDir);
    if (!fs::exists(file)) return nullptr;
    const auto s = post::readFunctionObjectState(file, cases::kLoadingMonitor);
    const auto get = [&](const char* key) -> const std::vector<double>& {
        const auto it = s.find(key);
        if (it == s.end()) throw std::runtime_error(file.string() + ": the loading monitor keeps no " + key);
        return it->second;
    };
    const auto &t = get("sampleTimes"), &m = get("sampleLoadings"), &c = get("sampleOutflows");
    if (m.size() != t.size() || c.size() != t.size() || get("fed").size() != 1 || get("out").size() != 1)
        throw std::runtime_error(file.string() + ": the loading monitor's samples differ in length");
    const std::size_t step = std::max<std::size_t>(1, (t.size() + maxSamples - 1) / std::max<std::size_t>(1, maxSamples));
    return {{"time_s", std::stod(timeDir.filename().string())},
            {"fed_kg", get("fed")[0]},
            {"out_kg", get("out")[0]},
            {"t", thinned(t, step)},
            {"loading_kg", thinned(m, step)},
            {"out_cumulative_kg", thinned(c, step)}};
}

double seedMonitorState(const fs::path& caseDir, const nlohmann::json& kept) {
    const auto t = kept.at("t").get<std::vector<double>>();
    const auto m = kept.at("loading_kg").get<std::vector<double>>();
    const auto c = kept.at("out_cumulative_kg").get<std::vector<double>>();
    if (t.empty() || m.size() != t.size() || c.size() != t.size())
        throw std::runtime_error("a kept loading-monitor state with samples of different lengths");
    const double t0 = kept.at("time_s").get<double>(), out0 = kept.at("out_kg").get<double>();
    std::ostringstream os;
    os.precision(17);
    const auto list = [&](const char* key, const std::vector<double>& v, double shift) {
        os << "    " << key << ' ' << v.size() << " (";
        for (double x : v) os << ' ' << x - shift;
        os << " );\n";
    };
    os << "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n"
       << "    location \"0/uniform/functionObjects\";\n    object functionObjectProperties;\n}\n\n"
       << cases::kLoadingMonitor << "\n{\n    fed 0;\n    out 0;\n";
    list("sampleTimes", t, t0);
    list("sampleLoadings", m, 0.0);
    list("sampleOutflows", c, out0);
    os << "}\n";
    const fs::path file = propertiesIn(caseDir / "0");
    fs::create_directories(file.parent_path());
    writeFileAtomic(file, os.str());
    return t0 - t.front();
}

}  // namespace mixload::run
