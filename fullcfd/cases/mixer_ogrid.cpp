// SPDX-License-Identifier: GPL-3.0-or-later
#include "cases/mixer_ogrid.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "cases/foam_dict.hpp"
#include "cases/mixer_geometry.hpp"

namespace mixload::cases {

namespace {

constexpr double kPi = std::numbers::pi;

std::string vec(Vec3 v) { return "(" + num(v[0]) + " " + num(v[1]) + " " + num(v[2]) + ")"; }

// The O-grid's vertices. Radial stations: shaft, paddle tips, zone boundary, bore. Axial stations:
// feed face, rotor start, rotor end, discharge face. The stationary region owns a full set. For
// the sliding mesh the rotor owns its own copies at the interface, so that blockMesh leaves the
// two sides unmerged (they become the AMI pair); for the frozen rotor it shares them (one
// conformal mesh, the zone is only a cellZone).
class OGrid {
public:
    OGrid(const scene::MixerScene& s, bool split)
        : g_(s.geometry), grid_(ogridSize(s)), split_(split) {
        r_ = {g_.shaftRadius(), g_.tipRadius(), g_.rotorRadius(), g_.radius()};
        x_ = {0.0, g_.rotorX0(), g_.rotorX1(), g_.length};
        phi0_ = weirChordPhi(g_);
    }
    int sectors() const { return grid_.sectors; }
    double phi(double k) const { return phi0_ + 2 * kPi * k / grid_.sectors; }
    Vec3 point(int ir, double k, int ix) const {
        return {x_[ix], r_[ir] * std::cos(phi(k)), r_[ir] * std::sin(phi(k))};
    }
    // Stationary vertex (any ir, ix) or rotor vertex (ir <= 2, ix in 1..2).
    int id(bool rotor, int ir, int k, int ix) const {
        const int S = grid_.sectors;
        k = ((k % S) + S) % S;
        if (!rotor || !split_) return (ix * 4 + ir) * S + k;
        return 16 * S + ((ix - 1) * 3 + ir) * S + k;
    }
    std::string radialFace(bool rotor, int ir, int k, int xa, int xb) const {
        return quad(id(rotor, ir, k, xa), id(rotor, ir, k + 1, xa), id(rotor, ir, k + 1, xb),
                    id(rotor, ir, k, xb));
    }
    std::string axialFace(bool rotor, int ja, int jb, int k, int ix) const {
        return quad(id(rotor, ja, k, ix), id(rotor, jb, k, ix), id(rotor, jb, k + 1, ix),
                    id(rotor, ja, k + 1, ix));
    }
    // Local axes: radial, around (+phi), axial (+x); right-handed since e_r x e_phi = e_x.
    std::string hex(bool rotor, int ja, int jb, int k, int xa, int xb, int nr, int nx) const {
        std::ostringstream os;
        os << "    hex (" << id(rotor, ja, k, xa) << ' ' << id(rotor, jb, k, xa) << ' '
           << id(rotor, jb, k + 1, xa) << ' ' << id(rotor, ja, k + 1, xa) << ' '
           << id(rotor, ja, k, xb) << ' ' << id(rotor, jb, k, xb) << ' '
           << id(rotor, jb, k + 1, xb) << ' ' << id(rotor, ja, k + 1, xb) << ")"
           << (rotor ? " rotor" : "") << " (" << nr << ' ' << grid_.perSector << ' ' << nx
           << ") simpleGrading (1 1 1)\n";
        return os.str();
    }

private:
    static std::string quad(int a, int b, int c, int d) {
        return "(" + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + " " +
               std::to_string(d) + ")";
    }
    const scene::MixerGeometry& g_;
    OGridSize grid_;
    bool split_;
    std::array<double, 4> r_{}, x_{};
    double phi0_ = 0;
};

std::string patch(const std::string& name, const std::string& type,
                  const std::vector<std::string>& faces, const std::string& extra = "") {
    std::ostringstream os;
    os << "    " << name << "\n    {\n        type " << type << ";\n" << extra
       << "        faces\n        (\n";
    for (const auto& f : faces) os << "            " << f << '\n';
    os << "        );\n    }\n";
    return os.str();
}

}  // namespace

// A plate of cells is closed to flow only if its cells share faces, not just edges: for a plate
// with normal cos(b) e_phi + sin(b) e_x that needs a thickness of at least h_phi cos(b) + h_x sin(b)
// (a "standard" digital plane), here with 5% to spare. Thinner paddles would leak.
double ogridMinPaddleThickness(const scene::MixerScene& s, const OGridSize& c) {
    const auto& g = s.geometry;
    const double beta = g.pitchDeg * kPi / 180.0;
    const double hPhi = g.tipRadius() * 2 * kPi / (c.sectors * c.perSector);
    const double hX = (g.rotorX1() - g.rotorX0()) / c.axialMid;
    return 1.05 * (hPhi * std::abs(std::cos(beta)) + hX * std::abs(std::sin(beta)));
}

long OGridSize::cells() const {
    const long around = static_cast<long>(sectors) * perSector;
    const long radial = radialInner + radialTip + radialOuter;
    return around * (radial * 2 * axialEnd + radial * axialMid);
}

double ogridMinPaddleThickness(const scene::MixerScene& s) { return ogridMinPaddleThickness(s, ogridSize(s)); }

OGridSize ogridSize(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    const double h = s.cellSize;
    OGridSize c;
    c.perSector = std::max(2, static_cast<int>(std::ceil(g.radius() * 2 * kPi / c.sectors / h)));
    c.radialInner = std::max(2, static_cast<int>(std::ceil((g.tipRadius() - g.shaftRadius()) / h)));
    c.radialTip = std::max(1, static_cast<int>(std::lround((g.rotorRadius() - g.tipRadius()) / h)));
    c.radialOuter = std::max(1, static_cast<int>(std::lround((g.radius() - g.rotorRadius()) / h)));
    c.axialEnd = std::max(1, static_cast<int>(std::lround(g.endGap / h)));
    c.axialMid = std::max(2, static_cast<int>(std::ceil((g.rotorX1() - g.rotorX0()) / h)));
    c.paddleThickness = std::max(g.paddleThickness, ogridMinPaddleThickness(s, c));
    return c;
}

std::string ogridBlockMeshDict(const scene::MixerScene& s) {
    const bool ami = s.method == "sm";
    const OGrid o(s, ami);
    const OGridSize c = ogridSize(s);
    const int S = o.sectors();
    const int nr[3] = {c.radialInner, c.radialTip, c.radialOuter};
    const int nx[3] = {c.axialEnd, c.axialMid, c.axialEnd};
    std::ostringstream os;
    os << "convertToMeters 1;\n\nvertices\n(\n";
    for (int ix = 0; ix < 4; ++ix)
        for (int ir = 0; ir < 4; ++ir)
            for (int k = 0; k < S; ++k) os << "    " << vec(o.point(ir, k, ix)) << '\n';
    for (int ix = 1; ami && ix <= 2; ++ix)
        for (int ir = 0; ir < 3; ++ir)
            for (int k = 0; k < S; ++k) os << "    " << vec(o.point(ir, k, ix)) << '\n';
    os << ");\n\nblocks\n(\n";
    for (int k = 0; k < S; ++k) {
        for (int j = 0; j < 3; ++j) {
            os << o.hex(false, j, j + 1, k, 0, 1, nr[j], nx[0]);  // feed-end layer
            os << o.hex(false, j, j + 1, k, 2, 3, nr[j], nx[2]);  // discharge-end layer
        }
        os << o.hex(false, 2, 3, k, 1, 2, nr[2], nx[1]);  // stationary ring around the rotor
        for (int j = 0; j < 2; ++j) os << o.hex(true, j, j + 1, k, 1, 2, nr[j], nx[1]);
    }
    os << ");\n\nedges\n(\n";
    auto arcs = [&](bool rotor, int ir, int ix) {
        for (int k = 0; k < S; ++k)
            os << "    arc " << o.id(rotor, ir, k, ix) << ' ' << o.id(rotor, ir, k + 1, ix) << ' '
               << vec(o.point(ir, k + 0.5, ix)) << '\n';
    };
    for (int ix = 0; ix < 4; ++ix)
        for (int ir = 0; ir < 4; ++ir) arcs(false, ir, ix);
    for (int ix = 1; ami && ix <= 2; ++ix)
        for (int ir = 0; ir < 3; ++ir) arcs(true, ir, ix);
    os << ");\n\nboundary\n(\n";

    // Three AMI pairs (bore side, feed cap, discharge cap): a single pair over the whole closed
    // interface let AMI match faces of one cap with the other cap's partners (same y, z), which
    // blew up the first time step.
    std::vector<std::string> wall, outlet, weir, shaft, shaftEnds;
    std::array<std::vector<std::string>, 3> amiR, amiS;
    for (int k = 0; k < S; ++k) {
        for (auto [xa, xb] : {std::pair{0, 1}, std::pair{1, 2}, std::pair{2, 3}})
            wall.push_back(o.radialFace(false, 3, k, xa, xb));
        for (int j = 0; j < 3; ++j) {
            wall.push_back(o.axialFace(false, j, j + 1, k, 0));  // inlet split off by createPatch
            const Vec3 mid = o.point(1, k + 0.5, 3);
            (onWeir(s.geometry, mid[1], mid[2]) ? weir : outlet)
                .push_back(o.axialFace(false, j, j + 1, k, 3));
        }
        shaftEnds.push_back(o.radialFace(false, 0, k, 0, 1));
        shaftEnds.push_back(o.radialFace(false, 0, k, 2, 3));
        shaft.push_back(o.radialFace(true, 0, k, 1, 2));
        amiR[0].push_back(o.radialFace(true, 2, k, 1, 2));
        amiS[0].push_back(o.radialFace(false, 2, k, 1, 2));
        for (int j = 0; j < 2; ++j)
            for (int ix : {1, 2}) {
                amiR[ix].push_back(o.axialFace(true, j, j + 1, k, ix));
                amiS[ix].push_back(o.axialFace(false, j, j + 1, k, ix));
            }
    }
    os << patch("wall", "wall", wall) << patch("outlet", "patch", outlet)
       << patch("weir", "wall", weir) << patch("shaft", "wall", shaft)
       << patch("shaftEnds", "wall", shaftEnds) << patch("paddles", "wall", {})
       ;
    const char* part[3] = {"Side", "Feed", "Discharge"};
    for (int i = 0; ami && i < 3; ++i) {
        const std::string rotor = std::string("AMI") + part[i] + "Rotor";
        const std::string stator = std::string("AMI") + part[i] + "Stator";
        os << patch(rotor, "cyclicAMI", amiR[i],
                    "        neighbourPatch " + stator + ";\n        transform noOrdering;\n")
           << patch(stator, "cyclicAMI", amiS[i],
                    "        neighbourPatch " + rotor + ";\n        transform noOrdering;\n");
    }
    os << ");\n\nmergePatchPairs ();\n";
    return os.str();
}

std::string ogridTopoSetDict(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    const OGridSize c = ogridSize(s);
    std::ostringstream os;
    os << "actions\n(\n";
    for (int i = 0; i < g.paddleCount; ++i) {
        const PaddleBox b = paddleBox(g, i, c.paddleThickness);
        Vec3 e0 = 2.0 * b.half[0], e1 = 2.0 * b.half[1], e2 = 2.0 * b.half[2];
        // rotatedBoxToCell builds a hex from (origin, i, j, k): it must be right-handed.
        if (dot(cross(e0, e1), e2) < 0) e1 = -1.0 * e1;
        const Vec3 origin = b.centre - 0.5 * e0 - 0.5 * e1 - 0.5 * e2;
        os << "    { name paddleCells; type cellSet; action " << (i == 0 ? "new" : "add")
           << "; source rotatedBoxToCell; origin " << vec(origin) << "; i " << vec(e0) << "; j "
           << vec(e1) << "; k " << vec(e2) << "; }\n";
    }
    // A paddle cell on the interface would punch a hole in the AMI.
    if (s.method == "sm")
        os << "    { name paddleCells; type cellSet; action subtract; source patchToCell; "
              "patch \"AMI.*\"; }\n";
    os << "    { name keep; type cellSet; action new; source cellToCell; set paddleCells; }\n"
       << "    { name keep; type cellSet; action invert; }\n);\n";
    return os.str();
}

std::string ogridInletTopoSetDict(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    std::ostringstream os;
    os << "actions\n(\n"
       << "    { name inletFaces; type faceSet; action new; source patchToFace; patch wall; }\n"
       << "    { name inletFaces; type faceSet; action subset; source cylinderToFace; p1 "
       << vec({-1e-3, 0, g.inletHeight}) << "; p2 " << vec({1e-3, 0, g.inletHeight})
       << "; radius " << num(0.5 * g.inletDiameter) << "; }\n);\n";
    return os.str();
}

std::string ogridCreatePatchDict() {
    return "pointSync false;\n\npatches\n(\n    {\n        name inlet;\n"
           "        patchInfo { type patch; }\n        constructFrom set;\n"
           "        set inletFaces;\n    }\n);\n";
}

std::vector<std::vector<std::string>> ogridMeshSteps() {
    // createPatch drops patches without faces, so the paddles are cut out (and their patch
    // filled) first; the inlet faces are picked after that, on the final face numbering.
    return {{"blockMesh"},
            {"topoSet"},
            {"subsetMesh", "keep", "-patch", "paddles", "-overwrite"},
            {"topoSet", "-dict", "system/topoSetDict.inlet"},
            {"createPatch", "-overwrite"},
            {"checkMesh", "-constant"}};
}

}  // namespace mixload::cases
