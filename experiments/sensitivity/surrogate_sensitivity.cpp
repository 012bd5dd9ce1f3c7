// SPDX-License-Identifier: GPL-3.0-or-later
#include "sensitivity/surrogate_sensitivity.hpp"

#include <iomanip>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "sensitivity/sobol_indices.hpp"

namespace mixload::experiments {

namespace {

// Where each box parameter goes in the surrogate's point; delta_mu is added to mu_s.
int slotOf(const std::string& name) {
    if (name == "mu_s") return 0;
    if (name == "delta_mu") return 1;
    if (name == "i0") return 2;
    if (name == "d") return 3;
    if (name == "rho") return 4;
    if (name == "feed_kg_h") return 5;
    if (name == "rpm") return 6;
    throw InputError("ranges parameter", name, "mu_s|delta_mu|i0|d|rho|feed_kg_h|rpm");
}

}  // namespace

nlohmann::json surrogateSensitivity(const surrogates::Surrogate& model, const ParameterSpace& box,
                                    const surrogates::Point& fixed, int n, int bootstrap,
                                    const std::filesystem::path& outDir) {
    if (box.scene != "mixer") throw InputError("ranges", box.scene, "a mixer ranges file");
    std::vector<int> slots;
    for (const auto& p : box.params) slots.push_back(slotOf(p.name));
    const double deltaMu0 = fixed[1] - fixed[0];
    auto ws = model.makeWorkspace();
    long outside = 0, calls = 0;
    const auto f = [&](const std::vector<double>& u) {
        const auto x = box.toPhysical(u);
        surrogates::Point p = fixed;
        double deltaMu = deltaMu0;
        for (size_t j = 0; j < slots.size(); ++j) {
            if (slots[j] == 1) deltaMu = x[j];
            else p[static_cast<size_t>(slots[j])] = x[j];
        }
        p[surrogates::kMuD] = p[surrogates::kMuS] + deltaMu;
        const auto pred = model.predict(p, ws);
        ++calls;
        outside += !pred.inBox;
        return pred.m;
    };
    const auto s = sobolIndices(static_cast<int>(box.params.size()), f, n, bootstrap);

    nlohmann::json rows = nlohmann::json::array();
    std::ostringstream md, csv, dat;
    md << "| input | range | first-order S | 90% interval | total S_T | 90% interval |\n|---|---|---|---|---|---|\n";
    csv << "input,min,max,unit,scale,first,first_lo,first_hi,total,total_lo,total_hi\n";
    md << std::fixed << std::setprecision(3);
    for (size_t i = 0; i < box.params.size(); ++i) {
        const auto& p = box.params[i];
        const auto& ix = s.inputs[i];
        rows.push_back({{"input", p.name},
                        {"min", p.min},
                        {"max", p.max},
                        {"unit", p.unit},
                        {"log", p.log},
                        {"first", ix.first},
                        {"first_ci90", {ix.firstLo, ix.firstHi}},
                        {"total", ix.total},
                        {"total_ci90", {ix.totalLo, ix.totalHi}}});
        md << "| " << p.name << " | " << formatNumber(p.min) << " – " << formatNumber(p.max) << ' ' << p.unit << (p.log ? " (log)" : "")
           << " | " << ix.first << " | " << ix.firstLo << " – " << ix.firstHi << " | " << ix.total << " | " << ix.totalLo << " – "
           << ix.totalHi << " |\n";
        csv << p.name << ',' << p.min << ',' << p.max << ',' << p.unit << ',' << (p.log ? "log" : "linear") << ',' << ix.first << ','
            << ix.firstLo << ',' << ix.firstHi << ',' << ix.total << ',' << ix.totalLo << ',' << ix.totalHi << '\n';
        dat << i << ' ' << p.name << ' ' << ix.first << ' ' << ix.firstLo << ' ' << ix.firstHi << ' ' << ix.total << ' ' << ix.totalLo
            << ' ' << ix.totalHi << '\n';
    }
    std::filesystem::create_directories(outDir);
    writeFileAtomic(outDir / "sensitivity.md", md.str());
    writeFileAtomic(outDir / "sensitivity.csv", csv.str());
    writeFileAtomic(outDir / "sensitivity.dat", dat.str());
    const std::string script =
        "set title 'Sobol indices of M (" + model.sourceLabel() + ")' noenhanced\n"
        "set style data histogram\nset style histogram errorbars gap 2 lw 1\nset style fill solid 0.6 border -1\n"
        "set yrange [0:1.05]\nset ylabel 'share of the variance of M'\nset xtics noenhanced\nset key top right\n"
        "plot 'sensitivity.dat' using 3:4:5:xtic(2) title 'first-order S', '' using 6:7:8 title 'total S_T'\n";
    std::string warning;
    const auto png = renderPng(outDir, "sensitivity", "pngcairo size 900,500", script, warning);
    nlohmann::json fixedJson = nlohmann::json::object();
    for (size_t k = 0; k < surrogates::kInputs; ++k) fixedJson[surrogates::kInputSpecs[k].name] = fixed[k];
    return {{"indices", rows},
            {"mean_kg", s.mean},
            {"variance_kg2", s.variance},
            {"n", s.n},
            {"evaluations", s.evaluations},
            {"bootstrap", s.bootstrap},
            {"held_at", fixedJson},
            {"outside_training_box", static_cast<double>(outside) / static_cast<double>(std::max(calls, 1L))},
            {"model_source", model.sourceLabel()},
            {"table", (outDir / "sensitivity.md").string()},
            {"plot", png ? nlohmann::json(png->string()) : nlohmann::json()},
            {"plot_warning", warning}};
}

}  // namespace mixload::experiments
