// SPDX-License-Identifier: GPL-3.0-or-later
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "app/commands.hpp"
#include "common/input_error.hpp"
#include "post/bed_profile.hpp"
#include "post/snapshots.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::app {

namespace {
struct SnapshotsCmd {
    std::string runDir, output, fields = "alpha,U,p", file;
    std::vector<std::string> files;
    int every = 1;
    std::optional<double> time;
    bool float64 = false, json = false, noVerify = false;
};

std::vector<std::string> splitList(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) out.push_back(item);
    return out;
}

std::string mb(double bytes) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(2) << bytes / 1e6 << " MB";
    return os.str();
}
}  // namespace

void addSnapshots(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("snapshots", "Export a run's fields to HDF5 (+ XDMF for ParaView) and inspect such files");
    cmd->require_subcommand(1);
    auto o = std::make_shared<SnapshotsCmd>();

    auto* ex = cmd->add_subcommand("export", "Write RUN_DIR's written times to FILE.h5 and FILE.xmf");
    ex->add_option("RUN_DIR", o->runDir, "Run directory (mixload collapse|mixer --out)")->required();
    ex->add_option("-o,--output", o->output, "Output .h5 (default RUN_DIR/snapshots.h5)");
    ex->add_option("--every", o->every, "Keep every K-th written time (the last is always kept)")->capture_default_str();
    ex->add_option("--fields", o->fields, "Comma-separated fields (alpha = alpha.powder)")->capture_default_str();
    ex->add_flag("--float64", o->float64, "Store fields in float64 (default float32: see README)");
    ex->add_flag("--json", o->json, "Print the summary as JSON");
    ex->callback([&action, o] {
        action = [o] {
            post::SnapshotExport e;
            e.runDir = o->runDir;
            e.output = o->output;
            e.every = o->every;
            e.fields = splitList(o->fields);
            e.float64 = o->float64;
            const auto r = post::exportSnapshots(e);
            if (o->json) std::cout << r.dump(2) << '\n';
            else
                std::cout << "snapshots " << r["file"].get<std::string>() << ": " << r["times"] << " times x "
                          << r["cells"] << " cells, fields " << r["fields"].dump() << " ("
                          << r["field_precision"].get<std::string>() << "), " << mb(r["bytes"].get<double>())
                          << "\n  ParaView: " << r["xdmf"].get<std::string>() << '\n';
            return 0;
        };
    });

    auto* in = cmd->add_subcommand("info", "Print a snapshot file's provenance, params and sizes; verify its checksums");
    in->add_option("FILE", o->file, "Snapshot file (.h5)")->required();
    in->add_flag("--no-verify", o->noVerify, "Skip reading every dataset (checksums)");
    in->add_flag("--json", o->json, "Print JSON");
    in->callback([&action, o] {
        action = [o] {
            const auto r = store::SnapshotFile(o->file).info(!o->noVerify);
            if (o->json) {
                std::cout << r.dump(2) << '\n';
                return 0;
            }
            const auto& p = r["provenance"];
            std::cout << r["file"].get<std::string>() << " (" << mb(r["bytes"].get<double>()) << ")\n"
                      << "  scene " << p.value("scene_kind", "") << ", hash " << p.value("scene_hash", "")
                      << "\n  written by mixload " << p.value("mixload_version", "") << " ("
                      << p.value("git_commit", "") << "), OpenFOAM " << p.value("openfoam_version", "")
                      << ", " << p.value("created_utc", "") << "\n  " << r["cells"] << " cells, "
                      << r["times"]["count"] << " times from " << r["times"]["first"] << " to "
                      << r["times"]["last"] << " s, fields " << p.value("field_precision", "") << "\n";
            for (const auto& d : r["datasets"])
                std::cout << "  " << std::left << std::setw(24) << d["path"].get<std::string>() << " "
                          << std::setw(18) << d["shape"].dump() << " " << std::setw(8)
                          << d["type"].get<std::string>() << " " << mb(d["stored_bytes"].get<double>())
                          << " stored of " << mb(d["raw_bytes"].get<double>()) << '\n';
            std::cout << "  params:";
            for (const auto& [k, v] : r["params"].items()) std::cout << ' ' << k << '=' << v.dump();
            std::cout << '\n' << (r["verified"].get<bool>() ? "  checksums verified\n" : "");
            return 0;
        };
    });

    auto* pr = cmd->add_subcommand("profile", "Where a mixer's powder sits along the shaft: mass, dense mass and the dense top per axial layer");
    pr->add_option("FILE", o->files, "Snapshot files (.h5) of mixer runs, e.g. MRF and SM at one point")->required();
    pr->add_option("--time", o->time, "Written time [s] (the nearest in each file; default each file's last)");
    pr->add_option("--plot", o->output, "Directory for profile.dat and profile.png (the files' profiles on one pair of axes)");
    pr->add_flag("--json", o->json, "Print JSON");
    pr->callback([&action, o] {
        action = [o] {
            std::vector<std::pair<std::string, post::BedProfile>> profiles;
            for (const auto& file : o->files) {
                const store::SnapshotFile f(file);
                size_t t = f.times().size() - 1;
                if (o->time) {
                    requireRange("time", *o->time, f.times().front(), f.times().back());
                    for (size_t k = 0; k < f.times().size(); ++k)
                        if (std::abs(f.times()[k] - *o->time) < std::abs(f.times()[t] - *o->time)) t = k;
                }
                profiles.emplace_back(std::filesystem::path(file).stem().string(), post::bedProfile(f, t));
            }
            std::string warning;
            std::optional<std::filesystem::path> png;
            if (!o->output.empty()) png = post::plotBedProfiles(profiles, o->output, warning);
            if (!warning.empty()) std::cerr << "mixload: warning: " << warning << '\n';
            if (o->json) {
                nlohmann::json j{{"profiles", nlohmann::json::array()}};
                for (size_t k = 0; k < profiles.size(); ++k) {
                    auto p = profiles[k].second.toJson();
                    p["file"] = o->files[k];
                    j["profiles"].push_back(p);
                }
                if (png) j["plot"] = png->string();
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            for (size_t k = 0; k < profiles.size(); ++k) {
                const auto& p = profiles[k].second;
                std::cout << o->files[k] << " at t = " << p.time << " s: M = " << p.loadingKg << " kg ("
                          << p.layers.size() << " axial layers; dense: cells more than half powder)\n"
                          << "  x [m]    mass [kg]  dense [kg]  dense top z [m]\n";
                for (const auto& l : p.layers) {
                    std::cout << "  " << std::fixed << std::setprecision(4) << std::setw(6) << l.x << "  "
                              << std::setprecision(5) << std::setw(9) << l.massKg << "  " << std::setw(9) << l.denseKg << "  ";
                    if (std::isfinite(l.topZ)) std::cout << std::setprecision(4) << std::setw(8) << l.topZ;
                    else std::cout << "       -";
                    std::cout << std::defaultfloat << '\n';
                }
            }
            if (png) std::cout << "plot " << png->string() << '\n';
            return 0;
        };
    });
}

}  // namespace mixload::app
