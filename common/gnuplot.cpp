// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/gnuplot.hpp"

#include "common/atomic_file.hpp"
#include "common/process.hpp"

namespace mixload {
std::string runGnuplot(const std::filesystem::path& dir, const std::string& scriptName,
                       const std::string& script) {
    writeFileAtomic(dir / scriptName, script);
    ProcessSpec spec;
    spec.argv = {"gnuplot", scriptName};
    spec.cwd = dir;
    spec.log = dir / "gnuplot.log";
    spec.stopOnRequest = false;
    const int rc = runProcess(spec);
    if (rc != 0) return "gnuplot exited with " + std::to_string(rc) + " (see " + spec.log.string() + ")";
    return "";
}

std::optional<std::filesystem::path> renderPng(const std::filesystem::path& dir, const std::string& name, const std::string& terminal,
                                               const std::string& body, std::string& warning) {
    const auto tmp = dir / (name + ".png.tmp"), png = dir / (name + ".png");
    warning = runGnuplot(dir, name + ".gp", "set terminal " + terminal + "\nset output '" + tmp.filename().string() + "'\n" + body);
    if (!warning.empty() || !std::filesystem::exists(tmp)) return std::nullopt;
    std::filesystem::rename(tmp, png);
    return png;
}
}  // namespace mixload
