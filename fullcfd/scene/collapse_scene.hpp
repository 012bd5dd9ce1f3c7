// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "scene/material.hpp"

namespace mixload::scene {

// The 2D granular column collapse (PHYSICS.md): a column Li x Hi against a free-slip left wall on a
// no-slip floor, open top and right side. The domain is sized to the expected runout so that no
// powder leaves it, and the mesh is uniform with dx = Li / cellsPerLength.
struct CollapseScene {
    Material material;
    double aspect = 2.0;          // a = Hi / Li, [0.2, 10]
    double length = 0.05;         // Li [m]
    int cellsPerLength = 30;      // Li / dx
    std::string rheology = "muI"; // muI | muIRegularised | schaeffer
    std::string convention = "standard";  // standard | paper (eta = mu p / (sqrt 2 gammaDot))
    std::optional<double> etaMax; // [Pa s]; default Rauter's with H = Hi ...
    double capHeightRatio = 1.0;  // ... times this (H = ratio x Hi): the cap keeps Hi^1.5 scaling
    double pMin = 1.0;            // [Pa]
    double gravity = 9.81;        // [m/s2]
    double restFraction = 0.01;   // rest: KE < restFraction * peak KE ...
    double restTimeTstar = 0.5;   // ... for this long (in t*)
    double capTstar = 15.0;       // end time cap (in t*)
    double maxCourant = 0.3;      // flow and interface Courant limit (campaign retries halve it)
    int writesPerTstar = 4;       // written times per t* (snapshots for reduced models want more)

    void validate() const;

    double height() const { return aspect * length; }
    double tStar() const { return std::sqrt(height() / gravity); }
    double dx() const { return length / cellsPerLength; }
    double etaMaxValue() const;
    // Friction coefficients as written to the case: the paper's convention divides mu by sqrt(2).
    double muSCase() const;
    double muDCase() const;
    // Domain, rounded to whole cells.
    int nx() const;
    int ny() const;
    double domainWidth() const { return nx() * dx(); }
    double domainHeight() const { return ny() * dx(); }
    long cells() const { return static_cast<long>(nx()) * ny(); }

    nlohmann::json toJson() const;  // canonical: every input that changes the result
    std::string hash() const;
};

// Runout estimate used only to size the domain (Lajeunesse et al. 2005 fit for low-friction
// grains: 1.2 a below a = 3, 1.9 a^(2/3) above), i.e. an upper bound for our powders.
double runoutEstimate(double aspect);

}  // namespace mixload::scene
