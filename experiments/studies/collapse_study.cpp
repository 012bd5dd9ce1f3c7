// SPDX-License-Identifier: GPL-3.0-or-later
#include "studies/collapse_study.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "run/collapse_job.hpp"
#include "run/foam_runner.hpp"
#include "studies/run_pool.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

std::string seriesName(const scene::CollapseScene& s, bool byAspect) {
    std::string n = s.material.name + " " + s.rheology;
    if (s.convention != "standard") n += " (" + s.convention + ")";
    if (byAspect) n += " Li/" + std::to_string(s.cellsPerLength);
    else n += " a=" + std::to_string(s.aspect).substr(0, 4);
    return n;
}

std::string plotStudy(const fs::path& out, const nlohmann::json& rows, bool byAspect) {
    std::map<std::string, std::ostringstream> series;
    for (const auto& r : rows) {
        if (!r.contains("runout_star")) continue;
        series[r["series"].get<std::string>()]
            << (byAspect ? r["aspect"].get<double>() : r["cells_per_length"].get<double>()) << ' '
            << r["runout_star"].get<double>() << ' ' << r["height_star"].get<double>() << '\n';
    }
    std::ostringstream gp;
    gp << "set terminal pngcairo size 1200,480 noenhanced\nset output 'study.png'\n"
       << "set multiplot layout 1,2\nset grid\nset key left top\n"
       << "set xlabel '" << (byAspect ? "aspect ratio a = Hi/Li" : "cells per column length Li/dx")
       << "'\n";
    int k = 0;
    std::string plotL = "set ylabel 'L*f = (Lf - Li)/Li'\nplot ";
    std::string plotH = "set ylabel 'H*f = Hf/Hi'\nset key right top\nset yrange [0:1.05]\nplot ";
    for (auto& [name, data] : series) {
        const std::string file = "series" + std::to_string(k++) + ".dat";
        std::ofstream(out / file) << data.str();
        plotL += "'" + file + "' using 1:2 with linespoints lw 2 title '" + name + "', ";
        plotH += "'" + file + "' using 1:3 with linespoints lw 2 title '" + name + "', ";
    }
    if (byAspect) {
        plotL += "(x < 3 ? 1.2*x : 1.9*x**(2.0/3)) with lines dt 2 lc 'black' title "
                 "'Lajeunesse et al. 2005 (glass beads)', ";
    }
    plotL.resize(plotL.size() - 2);
    plotH.resize(plotH.size() - 2);
    gp << plotL << "\n" << plotH << "\nunset multiplot\n";
    return runGnuplot(out, "study.gp", gp.str());
}

}  // namespace

nlohmann::json runCollapseStudy(const CollapseStudy& study) {
    fs::create_directories(study.out / "runs");
    std::set<double> aspects;
    for (const auto& s : study.scenes) aspects.insert(s.aspect);
    const bool byAspect = aspects.size() > 1;

    nlohmann::json rows = nlohmann::json::array();
    for (const auto& s : study.scenes)
        rows.push_back({{"series", seriesName(s, byAspect)},
                        {"material", s.material.name},
                        {"rheology", s.rheology},
                        {"convention", s.convention},
                        {"aspect", s.aspect},
                        {"cells_per_length", s.cellsPerLength},
                        {"scene_hash", s.hash()}});

    runPool<nlohmann::json>(
        study.scenes.size(), study.jobs, "collapse study", study.progress,
        [&](size_t i) {
            run::CollapseJob job;
            job.scene = study.scenes[i];
            job.out = study.out / "runs" / study.scenes[i].hash();
            try {
                return run::runCollapse(job);
            } catch (const run::RunError& e) {
                return nlohmann::json{{"error", e.what()}};
            }
        },
        [&](size_t i, const nlohmann::json& r) {
            for (const char* k : {"runout_star", "height_star", "stopped_by", "end_time_tstar",
                                  "powder_mass_error", "cells", "time_steps", "solver_wall_seconds",
                                  "error", "run_dir"})
                if (r.contains(k)) rows[i][k] = r[k];
        });

    std::ostringstream csv, md;
    csv << "material,rheology,convention,aspect,cells_per_length,runout_star,height_star,stopped_by,"
           "end_time_tstar,powder_mass_error,cells,solver_wall_seconds\n";
    md << "| material | rheology | a | Li/dx | L*f | H*f | stopped by | t_end/t* | mass err | cells | wall [s] |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : rows) {
        if (!r.contains("runout_star")) {
            md << "| " << r["material"].get<std::string>() << " | " << r["rheology"].get<std::string>()
               << " | " << r["aspect"] << " | " << r["cells_per_length"] << " | failed |||||||\n";
            continue;
        }
        char line[512];
        std::snprintf(line, sizeof line, "%s,%s,%s,%g,%d,%.4f,%.4f,%s,%.2f,%.2e,%ld,%.1f\n",
                      r["material"].get<std::string>().c_str(), r["rheology"].get<std::string>().c_str(),
                      r["convention"].get<std::string>().c_str(), r["aspect"].get<double>(),
                      r["cells_per_length"].get<int>(), r["runout_star"].get<double>(),
                      r["height_star"].get<double>(), r["stopped_by"].get<std::string>().c_str(),
                      r["end_time_tstar"].get<double>(), r["powder_mass_error"].get<double>(),
                      r["cells"].get<long>(), r["solver_wall_seconds"].get<double>());
        csv << line;
        std::snprintf(line, sizeof line, "| %s | %s | %g | %d | %.3f | %.3f | %s | %.1f | %.1e | %ld | %.0f |\n",
                      r["material"].get<std::string>().c_str(), r["rheology"].get<std::string>().c_str(),
                      r["aspect"].get<double>(), r["cells_per_length"].get<int>(),
                      r["runout_star"].get<double>(), r["height_star"].get<double>(),
                      r["stopped_by"].get<std::string>().c_str(), r["end_time_tstar"].get<double>(),
                      r["powder_mass_error"].get<double>(), r["cells"].get<long>(),
                      r["solver_wall_seconds"].get<double>());
        md << line;
    }
    writeFileAtomic(study.out / "table.csv", csv.str());
    writeFileAtomic(study.out / "table.md", md.str());
    const std::string warn = plotStudy(study.out, rows, byAspect);
    nlohmann::json result = {{"rows", rows},
                             {"table_csv", (study.out / "table.csv").string()},
                             {"table_md", (study.out / "table.md").string()},
                             {"plot", warn.empty() ? (study.out / "study.png").string() : ""}};
    writeFileAtomic(study.out / "study.json", result.dump(2));
    return result;
}

}  // namespace mixload::experiments
