// SPDX-License-Identifier: GPL-3.0-or-later
#include "cases/mixer_geometry.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "common/atomic_file.hpp"

namespace mixload::cases {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kSectors = 96;  // around the bore: 3.3 mm chords on a 0.1 m bore

// Adds a triangle, flipped if needed so that its normal points along `outward`.
void add(std::vector<Triangle>& tris, Vec3 a, Vec3 b, Vec3 c, Vec3 outward) {
    if (dot(cross(b - a, c - a), outward) < 0) std::swap(b, c);
    tris.push_back({a, b, c});
}

Vec3 polar(double x, double r, double phi) { return {x, r * std::cos(phi), r * std::sin(phi)}; }

// Cylinder side between x0 and x1, normals pointing away from the axis (or towards it).
void cylinderSide(std::vector<Triangle>& tris, double r, double x0, double x1, int axial,
                  bool outward) {
    for (int k = 0; k < kSectors; ++k) {
        const double p0 = 2 * kPi * k / kSectors, p1 = 2 * kPi * (k + 1) / kSectors;
        const double pm = 0.5 * (p0 + p1);
        const Vec3 n = (outward ? 1.0 : -1.0) * Vec3{0, std::cos(pm), std::sin(pm)};
        for (int j = 0; j < axial; ++j) {
            const double xa = x0 + (x1 - x0) * j / axial, xb = x0 + (x1 - x0) * (j + 1) / axial;
            add(tris, polar(xa, r, p0), polar(xb, r, p0), polar(xb, r, p1), n);
            add(tris, polar(xa, r, p0), polar(xb, r, p1), polar(xa, r, p1), n);
        }
    }
}

// A disc at x in polar cells (rings x sectors starting at angle phi0); each triangle goes to the
// solid that classify(y, z) of its centroid names. Sector edges start at phi0 so that a chord
// through the centre at that angle is reproduced exactly.
template <class Classify>
void disc(Surface& s, double x, double r, double phi0, double outwardX, int rings,
          Classify classify) {
    const Vec3 n{outwardX, 0, 0};
    auto put = [&](Vec3 a, Vec3 b, Vec3 c) {
        const Vec3 m = (1.0 / 3.0) * (a + b + c);
        add(s.solid(classify(m[1], m[2])).triangles, a, b, c, n);
    };
    for (int k = 0; k < kSectors; ++k) {
        const double p0 = phi0 + 2 * kPi * k / kSectors, p1 = phi0 + 2 * kPi * (k + 1) / kSectors;
        put({x, 0, 0}, polar(x, r / rings, p0), polar(x, r / rings, p1));
        for (int j = 1; j < rings; ++j) {
            const double ra = r * j / rings, rb = r * (j + 1) / rings;
            put(polar(x, ra, p0), polar(x, rb, p0), polar(x, rb, p1));
            put(polar(x, ra, p0), polar(x, rb, p1), polar(x, ra, p1));
        }
    }
}

void discCap(std::vector<Triangle>& tris, double x, double r, double outwardX) {
    const Vec3 n{outwardX, 0, 0};
    for (int k = 0; k < kSectors; ++k) {
        const double p0 = 2 * kPi * k / kSectors, p1 = 2 * kPi * (k + 1) / kSectors;
        add(tris, {x, 0, 0}, polar(x, r, p0), polar(x, r, p1), n);
    }
}

}  // namespace

Surface::Solid& Surface::solid(const std::string& name) {
    for (auto& s : solids)
        if (s.name == name) return s;
    solids.push_back({name, {}});
    return solids.back();
}

double Surface::area(const std::string& name) const {
    double a = 0;
    for (const auto& s : solids)
        if (s.name == name)
            for (const auto& t : s.triangles) a += 0.5 * norm(cross(t.b - t.a, t.c - t.a));
    return a;
}

void Surface::write(const std::filesystem::path& file) const {
    std::ostringstream os;
    os.precision(9);
    for (const auto& s : solids) {
        os << "solid " << s.name << '\n';
        for (const auto& t : s.triangles) {
            Vec3 n = cross(t.b - t.a, t.c - t.a);
            n = (1.0 / norm(n)) * n;
            os << "facet normal " << n[0] << ' ' << n[1] << ' ' << n[2] << "\n outer loop\n";
            for (const auto& v : {t.a, t.b, t.c})
                os << "  vertex " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
            os << " endloop\nendfacet\n";
        }
        os << "endsolid " << s.name << '\n';
    }
    writeFileAtomic(file, os.str());
}

// Chord direction (sin a, cos a) in (y, z) is the polar angle pi/2 - a.
double weirChordPhi(const scene::MixerGeometry& g) { return kPi / 2 - g.weirChordDeg * kPi / 180.0; }

bool onWeir(const scene::MixerGeometry& g, double y, double z) {
    // The chord runs through the axis at weirChordDeg from vertical; its normal is (cos a, -sin a).
    const double a = g.weirChordDeg * kPi / 180.0;
    return g.weirCovers * (y * std::cos(a) - z * std::sin(a)) > 0;
}

Surface barrelSurface(const scene::MixerGeometry& g) {
    Surface s;
    const double R = g.radius(), L = g.length;
    const int axial = std::max(1, static_cast<int>(std::ceil(L / 0.01)));
    cylinderSide(s.solid("wall").triangles, R, 0, L, axial, true);
    const int rings = std::max(4, static_cast<int>(std::ceil(R / 0.001)));
    const double ri = 0.5 * g.inletDiameter;
    disc(s, 0.0, R, 0.0, -1.0, rings, [&](double y, double z) {
        return y * y + (z - g.inletHeight) * (z - g.inletHeight) < ri * ri ? "inlet" : "wall";
    });
    disc(s, L, R, weirChordPhi(g), 1.0, rings,
         [&](double y, double z) { return onWeir(g, y, z) ? "weir" : "outlet"; });
    return s;
}

Surface shaftSurface(const scene::MixerGeometry& g) {
    Surface s;
    auto& t = s.solid("shaft").triangles;
    const double over = 0.1 * g.bore;  // well past both end faces
    const int axial = std::max(1, static_cast<int>(std::ceil((g.length + 2 * over) / 0.01)));
    cylinderSide(t, g.shaftRadius(), -over, g.length + over, axial, true);
    discCap(t, -over, g.shaftRadius(), -1.0);
    discCap(t, g.length + over, g.shaftRadius(), 1.0);
    return s;
}

PaddleBox paddleBox(const scene::MixerGeometry& g, int i, double thickness) {
    const double beta = g.pitchDeg * kPi / 180.0;
    // Rooted halfway into the shaft so that snappy sees one connected impeller.
    const double r0 = 0.5 * g.shaftRadius(), r1 = g.tipRadius();
    const double phi = g.paddleAngleDeg(i) * kPi / 180.0;
    const Vec3 er{0, std::cos(phi), std::sin(phi)};
    const Vec3 ephi{0, -std::sin(phi), std::cos(phi)};  // direction of motion for rpm > 0
    const Vec3 np = std::cos(beta) * ephi + std::sin(beta) * Vec3{1, 0, 0};
    const Vec3 ew = cross(np, er);
    return {Vec3{g.paddleX(i), 0, 0} + 0.5 * (r0 + r1) * er,
            {0.5 * (r1 - r0) * er, 0.5 * g.paddleWidth * ew, 0.5 * thickness * np}};
}

Surface paddleSurface(const scene::MixerGeometry& g) {
    Surface s;
    auto& t = s.solid("paddles").triangles;
    for (int i = 0; i < g.paddleCount; ++i) {
        const PaddleBox b = paddleBox(g, i, g.paddleThickness);
        const auto& h = b.half;
        auto corner = [&](int a, int c, int d) {
            return b.centre + double(a) * h[0] + double(c) * h[1] + double(d) * h[2];
        };
        // Each of the 6 faces: fixed axis k at sign sk, spanned by the other two.
        for (int k = 0; k < 3; ++k)
            for (int sk : {-1, 1}) {
                const int u = (k + 1) % 3, v = (k + 2) % 3;
                Vec3 q[4];
                const int su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
                for (int m = 0; m < 4; ++m) {
                    int idx[3];
                    idx[k] = sk;
                    idx[u] = su[m];
                    idx[v] = sv[m];
                    q[m] = corner(idx[0], idx[1], idx[2]);
                }
                const Vec3 out = double(sk) * h[k];
                add(t, q[0], q[1], q[2], out);
                add(t, q[0], q[2], q[3], out);
            }
    }
    return s;
}

}  // namespace mixload::cases
