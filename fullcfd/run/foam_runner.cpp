// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/foam_runner.hpp"

#include <chrono>
#include <fstream>
#include <iostream>
#include <cstdlib>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "common/progress.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

std::vector<std::pair<std::string, std::string>> foamEnvironment() {
    return {{"WM_PROJECT_DIR", "/usr/share/openfoam"},
            {"FOAM_ETC", "/usr/share/openfoam/etc"},
            {"FOAM_SIGFPE", "true"},
            {"OMPI_ALLOW_RUN_AS_ROOT", "1"},
            {"OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1"},
            {"OMPI_MCA_rmaps_base_oversubscribe", "1"},
            // Ranks yield the core while waiting: CI shares 2 cores with other work.
            {"OMPI_MCA_mpi_yield_when_idle", "1"},
            // No network fabric on these machines: keep Open MPI on shared memory + loopback.
            {"OMPI_MCA_btl", "self,vader,tcp"},
            {"OMPI_MCA_btl_tcp_if_include", "lo"},
            {"OMPI_MCA_oob_tcp_if_include", "lo"}};
}

namespace {

int run(const fs::path& caseDir, const std::vector<std::string>& argv, const std::string& logName,
        const std::function<void(const std::string&)>& onLine = {},
        std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt, bool stoppable = false) {
    ProcessSpec spec;
    spec.deadline = deadline;
    spec.stopOnRequest = stoppable;  // a solver stops on a signal; a utility finishes what it writes
    spec.argv = argv;
    spec.cwd = caseDir;
    spec.log = caseDir / logName;
    spec.env = foamEnvironment();
    spec.onLine = onLine;
    return runProcess(spec);
}

void check(int rc, const fs::path& caseDir, const std::string& what, const std::string& logName) {
    if (rc == 0) return;
    throw RunError(what + " failed (exit " + std::to_string(rc) + "); last lines of " +
                   (caseDir / logName).string() + ":\n" + tailLines(caseDir / logName, 25));
}

}  // namespace

void runUtility(const fs::path& caseDir, const std::vector<std::string>& argv) {
    const std::string logName = "log." + argv.front();
    check(run(caseDir, argv, logName), caseDir, argv.front(), logName);
}

fs::path latestTimeDir(const fs::path& caseDir) {
    double latest = 0;
    fs::path dir;
    if (!fs::exists(caseDir)) return dir;
    for (const auto& e : fs::directory_iterator(caseDir)) {
        if (!e.is_directory()) continue;
        if (const auto t = parseNumber(e.path().filename().string()); t && *t > latest) latest = *t, dir = e.path();
    }
    return dir;
}

double latestTime(const fs::path& caseDir) {
    const fs::path dir = latestTimeDir(caseDir);
    return dir.empty() ? 0 : *parseNumber(dir.filename().string());
}

std::string interFoamPath() {
    if (const char* env = std::getenv("MIXLOAD_INTERFOAM")) return env;
    return MIXLOAD_INTERFOAM;
}

namespace {
// A field file the solver finished writing ends with OpenFOAM's closing divider.
bool complete(const fs::path& file) {
    if (file.extension() == ".gz") return fs::file_size(file) > 0;
    std::ifstream in(file, std::ios::binary);
    const auto size = static_cast<std::streamoff>(fs::file_size(file));
    if (size < 8) return false;
    in.seekg(std::max<std::streamoff>(0, size - 128));
    const std::string tail((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return tail.find("// ****") != std::string::npos;
}

// Renames a time directory to <time>.partial (then .partial1, ...: a time written again after one
// was set aside can be set aside again), which OpenFOAM ignores.
fs::path setAside(const fs::path& time) {
    fs::path aside = time;
    aside += ".partial";
    for (int k = 1; fs::exists(aside); ++k) aside = time.string() + ".partial" + std::to_string(k);
    fs::rename(time, aside);
    return aside;
}

std::set<std::string> fileNames(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file()) names.insert(e.path().filename().string());
    return names;
}
}  // namespace

std::optional<fs::path> setAsidePartialTime(const fs::path& caseDir) {
    const fs::path latest = latestTimeDir(caseDir);
    if (latest.empty()) return std::nullopt;
    bool partial = false;
    for (const auto& name : fileNames(latest)) partial = partial || !complete(latest / name);
    // Against the time before it (not 0, which holds only the initial fields): a field not written.
    double before = 0;
    fs::path previous;
    for (const auto& e : fs::directory_iterator(caseDir)) {
        const auto t = e.is_directory() ? parseNumber(e.path().filename().string()) : std::nullopt;
        if (t && *t > before && e.path() != latest) before = *t, previous = e.path();
    }
    if (!previous.empty()) {
        const auto had = fileNames(previous), has = fileNames(latest);
        for (const auto& name : had) partial = partial || !has.count(name);
    }
    if (!partial) return std::nullopt;
    return setAside(latest);
}

namespace {
std::vector<fs::path> processorDirs(const fs::path& caseDir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(caseDir))
        if (e.is_directory() && e.path().filename().string().rfind("processor", 0) == 0) out.push_back(e.path());
    return out;
}

// A time as OpenFOAM names it at a precision (general format, as Time::timeName).
std::string timeName(double t, int precision) {
    std::ostringstream os;
    os.precision(precision);
    os << t;
    return os.str();
}
}  // namespace

int fitTimePrecision(const fs::path& caseDir, bool decomposed) {
    const fs::path dict = caseDir / "system" / "controlDict";
    if (!fs::exists(dict)) return 0;
    std::ifstream in(dict);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    static const std::regex entry(R"((^|\n)(\s*timePrecision\s+)(\d+)(\s*;))");
    std::smatch m;
    if (!std::regex_search(text, m, entry)) return 0;
    const int has = std::stoi(m[3].str());
    // The latest time the solver starts from: the case's, or each rank's.
    std::vector<std::string> names;
    const std::vector<fs::path> dirs = decomposed ? processorDirs(caseDir) : std::vector<fs::path>{caseDir};
    for (const auto& d : dirs)
        if (const auto latest = latestTimeDir(d); !latest.empty()) names.push_back(latest.filename().string());
    const auto names_at = [&](int p) {
        for (const auto& n : names)
            if (timeName(*parseNumber(n), p) != n) return false;
        return true;
    };
    if (names_at(has)) return has;
    // Too few digits, or too many (a precision raised for a time since set aside prints digits
    // the name does not have): the least precision that names them all as written.
    for (int p = 1; p <= 18; ++p)
        if (names_at(p)) {
            writeFileAtomic(dict, m.prefix().str() + m[1].str() + m[2].str() + std::to_string(p) + m[4].str() +
                                      m.suffix().str());
            return p;
        }
    return has;  // names OpenFOAM did not write: left to the solver to report
}

void gatherParallelTimes(const fs::path& caseDir, int np) {
    const auto procs = processorDirs(caseDir);
    if (procs.empty()) return;
    // The case's own latest time may be half reconstructed (a driver killed in reconstructPar):
    // aside, it is reconstructed again from the ranks below.
    setAsidePartialTime(caseDir);
    // A rank killed while writing, or ranks killed between writes: the restart time is the latest
    // one every rank wrote whole, and later ones go aside on every rank.
    double common = 1e300;
    for (const auto& p : procs) {
        setAsidePartialTime(p);
        common = std::min(common, latestTime(p));
    }
    std::vector<fs::path> later;  // collected first: renaming while iterating may skip entries
    for (const auto& p : procs)
        for (const auto& e : fs::directory_iterator(p)) {
            const auto t = e.is_directory() ? parseNumber(e.path().filename().string()) : std::nullopt;
            if (t && *t > common) later.push_back(e.path());
        }
    for (const auto& t : later) setAside(t);
    if (common > latestTime(caseDir)) runUtility(caseDir, {"reconstructPar", "-newTimes"});
    // Decomposed for another number of ranks: decomposed again from the latest time.
    if (static_cast<int>(procs.size()) != np)
        for (const auto& p : procs) fs::remove_all(p);
}

double runSolver(const SolverRun& r) {
    const auto start = std::chrono::steady_clock::now();
    // A parallel slice stopped or killed may have left its newest times in processor*/ only.
    gatherParallelTimes(r.caseDir, r.np);
    // A solver killed while writing leaves a time it cannot restart from: resume before it.
    if (r.np <= 1) setAsidePartialTime(r.caseDir);
    Progress bar(r.label, r.progress);
    auto onLine = [&](const std::string& line) {
        if (line.rfind("Time = ", 0) == 0) {
            const double t = std::atof(line.c_str() + 7);
            bar.update(t / r.endTime, "t = " + line.substr(7) + " s");
        }
    };
    // Logs keep the solver's plain name (log.interFoam) wherever its binary lives.
    const std::string name = fs::path(r.solver).filename().string() == "mixloadInterFoam"
                                 ? "interFoam"
                                 : fs::path(r.solver).filename().string();
    const std::string logName = "log." + name;
    if (r.np <= 1) {
        fitTimePrecision(r.caseDir, false);
        check(run(r.caseDir, {r.solver}, logName, onLine, r.deadline, true), r.caseDir, name, logName);
    } else {
        // The latest time only: a resumed or warm-continued case starts from it.
        if (!fs::exists(r.caseDir / "processor0")) runUtility(r.caseDir, {"decomposePar", "-force", "-latestTime"});
        fitTimePrecision(r.caseDir, true);
        try {
            check(run(r.caseDir, {"mpirun", "-np", std::to_string(r.np), r.solver, "-parallel"}, logName, onLine,
                      r.deadline, true),
                  r.caseDir, "mpirun " + name, logName);
        } catch (const DeadlineReached&) {
            // The case itself holds what the slice ran (kept progress, a serial resume read it there).
            try {
                gatherParallelTimes(r.caseDir, r.np);
            } catch (const std::exception& e) {
                std::cerr << "mixload: warning: the stopped slice's times stay in " << r.caseDir.string()
                          << "/processor*, the next slice gathers them: " << e.what() << '\n';
            }
            throw;
        }
        runUtility(r.caseDir, {"reconstructPar", "-newTimes"});
    }
    bar.finish();
    return secondsSince(start);
}

}  // namespace mixload::run
