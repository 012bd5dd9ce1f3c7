// SPDX-License-Identifier: GPL-3.0-or-later
// Where the powder sits along a mixer, from a snapshot: the mass in each axial layer of cells, the
// part of it in cells more than half powder, and the height of the dense powder's top. Two runs
// that hold different loadings (MRF and the sliding mesh, two feeds) differ in how; this says
// whether a deeper bed, a heap at the feed end or a dam at the weir carries the difference.
#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/snapshot_file.hpp"

namespace mixload::post {

struct BedLayer {
    double x = 0;         // the layer's cell centres along the shaft (the x axis) [m]
    double massKg = 0;    // alpha * V * bulk density over the layer
    double denseKg = 0;   // the same over the layer's cells with alpha > denseAlpha
    double topZ = 0;      // highest centre (z, up) of a dense cell; NaN when the layer has none
};

struct BedProfile {
    double time = 0, loadingKg = 0, bulkDensity = 0;
    std::vector<BedLayer> layers;  // in x order
    nlohmann::json toJson() const;
};

// timeIndex into file.times(). Cells group into layers by their centres' x (equal to 1e-6 m; the
// O-grid's axial stations are the same at every radius). A moving mesh's centres are read at that
// time. InputError for a file without alpha or with no bulk density in its params.
BedProfile bedProfile(const store::SnapshotFile& file, size_t timeIndex, double denseAlpha = 0.5);

// profile.dat and profile.png in dir: each labelled profile's mass per layer and dense top against
// x, on one pair of axes, so two runs (MRF and SM at one point) read side by side. The PNG's path,
// or nothing and the reason in warning (a plot is a convenience, never a failed command).
std::optional<std::filesystem::path> plotBedProfiles(const std::vector<std::pair<std::string, BedProfile>>& profiles,
                                                     const std::filesystem::path& dir, std::string& warning);

}  // namespace mixload::post
