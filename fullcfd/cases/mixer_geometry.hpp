// SPDX-License-Identifier: GPL-3.0-or-later
// Surfaces of the mixer, generated from its scene for snappyHexMesh (ASCII STL, metres).
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/mixer_scene.hpp"

namespace mixload::cases {

using Vec3 = std::array<double, 3>;

struct Triangle {
    Vec3 a, b, c;
};

// One STL file may hold several named solids; snappyHexMesh turns each into a patch region.
struct Surface {
    struct Solid {
        std::string name;
        std::vector<Triangle> triangles;
    };
    std::vector<Solid> solids;
    Solid& solid(const std::string& name);
    void write(const std::filesystem::path& file) const;
    double area(const std::string& solid) const;
};

// Barrel: bore (wall), feed end face (wall + inlet), discharge face split by the weir chord into
// weir and outlet. Closed, normals outward.
Surface barrelSurface(const scene::MixerGeometry& g);
// Shaft: closed cylinder running through both end faces (snappy trims it to the barrel).
Surface shaftSurface(const scene::MixerGeometry& g);
// The flat pitched paddles, rooted inside the shaft.
Surface paddleSurface(const scene::MixerGeometry& g);
// The closed cylinder bounding the rotating zone.
Surface rotorSurface(const scene::MixerGeometry& g);

// Which side of the weir chord a point (y, z) of the discharge face lies on: true = weir (wall).
bool onWeir(const scene::MixerGeometry& g, double y, double z);

}  // namespace mixload::cases
