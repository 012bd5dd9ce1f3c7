// SPDX-License-Identifier: GPL-3.0-or-later
// What a mixer mesh simulates of its scene's impeller, computed before anything is meshed, and the
// refusal when that is not the scene's: a run simulates its scene's geometry on every mesh or does
// not start (the O-grid once thickened the 4 mm paddles to 14 mm on 1 cm cells, unseen).
#pragma once
#include <nlohmann/json.hpp>

#include "scene/mixer_scene.hpp"

namespace mixload::cases {

// How far the meshed paddle may depart from the scene's (relative, on its thickness).
inline constexpr double kGeometryTolerance = 0.02;

struct MeshedGeometry {
    double paddleThickness = 0;     // [m] what the mesh cuts
    double minPaddleThickness = 0;  // [m] the thinnest paddle this mesh closes to flow
    double paddleWidth = 0;         // [m] across the pitch direction, as cut
    double paddleRadial = 0;        // [m] from the shaft's surface to the tip, as cut
    double paddleVolume = 0;        // [m3] solid volume of the paddles in the barrel (the boxes)
    double sweptVolume = 0;         // [m3] annulus from the shaft to the tips over the rotating zone
    nlohmann::json toJson() const;
};

MeshedGeometry meshedGeometry(const scene::MixerScene& s);

// Throws InputError (exit 2) when the scene's mesh cannot cut the scene's paddles: it names the
// key, the scene's value, the thinnest paddle the mesh can represent and the largest cell size that
// would represent the scene's.
void requireSceneGeometry(const scene::MixerScene& s);

// Throws InputError (exit 2, naming key and value: the option that brought b in) unless the meshes of
// a and b simulate the same impeller (the paddles as cut, within kGeometryTolerance): results of
// two different impellers are never compared as two resolutions of one.
void requireSameImpeller(const scene::MixerScene& a, const scene::MixerScene& b, const std::string& key,
                         const std::string& value);

}  // namespace mixload::cases
