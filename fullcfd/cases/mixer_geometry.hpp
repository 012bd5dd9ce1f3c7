// SPDX-License-Identifier: GPL-3.0-or-later
// Surfaces of the mixer, generated from its scene for snappyHexMesh (ASCII STL, metres).
#pragma once
#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/mixer_scene.hpp"

namespace mixload::cases {

using Vec3 = std::array<double, 3>;

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a[0], s * a[1], s * a[2]}; }
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(Vec3 a, Vec3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

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
// One flat pitched paddle as a box: centre and half-extents along its radius, its width and its
// face normal (tilted from the direction of motion towards +x, so that it conveys to +x).
struct PaddleBox {
    Vec3 centre;
    std::array<Vec3, 3> half;
};
PaddleBox paddleBox(const scene::MixerGeometry& g, int i, double thickness);
// The flat pitched paddles, rooted inside the shaft.
Surface paddleSurface(const scene::MixerGeometry& g);

// Polar angle (in the y-z plane, from +y towards +z) of the weir chord through the axis.
double weirChordPhi(const scene::MixerGeometry& g);
// Which side of the weir chord a point (y, z) of the discharge face lies on: true = weir (wall).
bool onWeir(const scene::MixerGeometry& g, double y, double z);

}  // namespace mixload::cases
