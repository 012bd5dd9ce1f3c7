// SPDX-License-Identifier: GPL-3.0-or-later
#include "scene/mixer_scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include <toml++/toml.h>

#include "common/atomic_file.hpp"
#include "common/hash.hpp"
#include "common/input_error.hpp"
#include "muILaw.H"
#include "steadyLoading.H"

namespace mixload::scene {

namespace {
constexpr double kPi = std::numbers::pi;
double rad(double deg) { return deg * kPi / 180.0; }
}  // namespace

double MixerGeometry::paddleAxialHalf() const {
    const double b = rad(pitchDeg);
    return 0.5 * paddleWidth * std::abs(std::cos(b)) + 0.5 * paddleThickness * std::abs(std::sin(b));
}

double MixerGeometry::openVolume() const {
    const double R = radius(), rs = shaftRadius();
    const double paddles = paddleCount * (tipRadius() - rs) * paddleWidth * paddleThickness;
    return kPi * (R * R - rs * rs) * length - paddles;
}

void MixerGeometry::validate() const {
    requireRange("barrel.length_m", length, 0.02, 5.0);
    requireRange("barrel.bore_m", bore, 0.01, 2.0);
    requireRange("impeller.shaft_diameter_m", shaftDiameter, 0.0, 0.8 * bore, false, true);
    requireRange("impeller.paddle_count", paddleCount, 1, 100);
    // The paddle must fit between the shaft and the bore, with room for the rotating zone's edge.
    requireRange("impeller.paddle_tip_clearance_m", tipClearance, 0.0,
                 radius() - shaftRadius() - 0.005, false, false);
    requireRange("impeller.paddle_width_m", paddleWidth, 0.0, length, false, true);
    requireRange("impeller.paddle_thickness_m", paddleThickness, 0.0, 0.5 * paddleWidth + 0.01, false,
                 true);
    requireRange("impeller.paddle_pitch_deg", pitchDeg, -89.0, 89.0);
    requireRange("impeller.paddle_offset_deg", offsetDeg, -360.0, 360.0);
    requireRange("impeller.paddle_phase_deg", phaseDeg, -360.0, 360.0);
    requireRange("impeller.end_gap_m", endGap, 0.0, 0.25 * length, false, true);
    requireRange("impeller.end_clearance_m", endClearance, 0.0, 0.25 * length);
    // Successive paddles must not overlap along the shaft, nor poke out of the rotating zone.
    const double half = paddleAxialHalf();
    if (impellerX1() <= impellerX0() || 2.0 * half > paddleSpacing())
        throw InputError("impeller.paddle_count", std::to_string(paddleCount),
                         "at most " +
                             std::to_string(static_cast<int>((impellerX1() - impellerX0()) /
                                                             (2.0 * half))) +
                             " paddles of axial extent " + formatNumber(2.0 * half) +
                             " m in an impeller span of " +
                             formatNumber(impellerX1() - impellerX0()) + " m");
    requireRange("weir.chord_angle_deg", weirChordDeg, -90.0, 90.0, false, false);
    if (weirCovers != 1 && weirCovers != -1)
        throw InputError("weir.covers", std::to_string(weirCovers), "\"+y\" or \"-y\"");
    requireRange("inlet.diameter_m", inletDiameter, 0.0, bore, false, false);
    // The feed port lies on the end face, clear of the shaft and inside the bore: above the axis
    // (the powder falls to the bed) or below it (the port opens into the bed).
    const double r = 0.5 * inletDiameter;
    if (!(std::abs(inletHeight) > shaftRadius() + r && std::abs(inletHeight) < radius() - r))
        throw InputError("inlet.height_m", formatNumber(inletHeight),
                         "a port clear of the shaft and inside the bore: " + formatNumber(shaftRadius() + r) +
                             " < |height| < " + formatNumber(radius() - r));
}

MixerNumerics MixerNumerics::named(const std::string& name) {
    MixerNumerics n;
    n.preset = name;
    if (name == "legacy") return n;
    if (name != "fast") throw InputError("numerics", name, "legacy|fast");
    // The O-grid's non-orthogonality is about 1e-6 degrees: its corrections vanish, and the
    // pressure equation is solved once per corrector instead of twice (loading unchanged to six
    // digits over 2 s of flow, README "Cost of a steady point"). The time step stays set by the
    // Courant number of every cell: the limits that exempt air or dilute cells moved the loading
    // by 1-4% (same section).
    n.nonOrthCorrectors = 0;
    return n;
}

bool MixerNumerics::sameSettings(const MixerNumerics& o) const {
    return airViscosity == o.airViscosity && courantAlphaMin == o.courantAlphaMin &&
           nonOrthCorrectors == o.nonOrthCorrectors && maxDeltaT == o.maxDeltaT &&
           alphaSubCycles == o.alphaSubCycles;
}

void MixerNumerics::validate() const {
    if (preset != "legacy" && preset != "fast") throw InputError("numerics", preset, "legacy|fast");
    requireRange("air-viscosity", airViscosity, 1e-6, 1.0);
    requireRange("courant-alpha-min", courantAlphaMin, 0.0, 0.99);
    requireRange("non-orth-correctors", nonOrthCorrectors, 0, 5);
    requireRange("max-delta-t", maxDeltaT, 1e-5, 1.0);
    requireRange("alpha-sub-cycles", alphaSubCycles, 1, 10);
}

void MixerScene::setMesh(const std::string& level) {
    static const char* names[] = {"coarse", "medium", "fine"};
    for (int i = 0; i < 3; ++i)
        if (level == names[i]) {
            mesh = level;
            cellSize = levelCells[i];
            return;
        }
    throw InputError("mesh", level, "coarse|medium|fine");
}

std::string MixerScene::meshLabel() const {
    return (mesh == "custom" ? formatNumber(cellSize) + " m" : mesh) +
           (method != "sm" && mesher == "snappy" ? " snappy" : "");
}

double MixerScene::courantLimit() const {
    return method == "sm" ? std::min(maxCourant, kSlidingMeshMaxCourant) : maxCourant;
}

void MixerScene::validate() const {
    geometry.validate();
    requireRange("max-courant", maxCourant, 0.01, 5.0);
    numerics.validate();
    material.validate();
    if (convention != "standard" && convention != "paper")
        throw InputError("convention", convention, "standard|paper");
    if (rheology != "muI" && rheology != "muIRegularised" && rheology != "schaeffer")
        throw InputError("rheology", rheology, "muI|muIRegularised|schaeffer");
    if (method != "mrf" && method != "lts" && method != "sm")
        throw InputError("method", method, "mrf|lts|sm");
    if (mesher != "ogrid" && mesher != "snappy") throw InputError("mesher", mesher, "ogrid|snappy");
    if (method == "sm" && mesher != "ogrid")
        throw InputError("mesher", mesher, "ogrid for --method sm (the AMI needs the O-grid)");
    // snappy's castellated cells are up to 60 degrees non-orthogonal.
    if (mesher == "snappy" && numerics.nonOrthCorrectors < 1)
        throw InputError("non-orth-correctors", std::to_string(numerics.nonOrthCorrectors),
                         "at least 1 on the snappy mesh (--numerics legacy or --non-orth-correctors 1)");
    if (etaMax) requirePositive("eta-max", *etaMax);
    if (etaMaxH) requireRange("powder.eta_max_h_m", *etaMaxH, 1e-6, 100.0);
    requirePositive("p-min", pMin);
    requireRange("rpm", rpm, 0.0, 2000.0);  // 0: a resting bed (checks)
    requireRange("feed-kg-h", feedKgH, 0.0, 1000.0);
    const double capacity = geometry.openVolume() * bulkDensity();
    requireRange("initial-loading-kg", initialLoadingKg, 0.0, 0.95 * capacity);
    // The finest level must still see the clearance-sized features at least roughly.
    requireRange("cell-size", cellSize, 0.2 * geometry.tipClearance, 0.25 * geometry.bore);
    requireRange("end-time", endTime, 0.01, 1e5, false, true);
    requireRange("lts-iterations", ltsIterations, 10, 10'000'000);
    requireRange("steady-window-revs", steadyWindowRevs, 0.5, 100.0);
    requireRange("steady-window-residence", steadyResidence, 0.0, 10.0);
    requireRange("steady-tol", steadyTol, 0.0, 0.5, false, true);
    requireRange("steady-flow-tol", steadyFlowTol, 0.0, 1.0, false, true);
    requireRange("min-time", minTime, 0.0, 1e5);
    const double cells = geometry.openVolume() / std::pow(cellSize, 3);
    if (cells > 5e6)
        throw InputError("cell-size", formatNumber(cellSize),
                         "a mesh of at most 5e6 background cells (this one has about " +
                             formatNumber(std::round(cells)) + ")");
}

double MixerScene::omega() const { return rpm * 2.0 * kPi / 60.0; }

double MixerScene::divergedPowderSpeed() const {
    return 10.0 * (omega() * geometry.tipRadius() + std::sqrt(2.0 * gravity * geometry.bore));
}

double MixerScene::etaMaxValue() const {
    return etaMax ? *etaMax
                  : rheology::rauterEtaMax(material.grainDensity, gravity, etaMaxH.value_or(geometry.bore));
}
double MixerScene::muSCase() const {
    return convention == "paper" ? material.muS / std::sqrt(2.0) : material.muS;
}
double MixerScene::muDCase() const {
    return convention == "paper" ? material.muD / std::sqrt(2.0) : material.muD;
}

double MixerScene::steadyWindow() const {
    // LTS has no physical time: its window is counted in pseudo-time iterations. Without rotation
    // a "revolution" is taken as 1 s.
    if (method == "lts") return std::max(200.0, 100.0 * steadyWindowRevs);
    return steadyWindowRevs * (rpm > 0 ? revolutionTime() : 1.0);
}

double MixerScene::steadyPeriod() const { return method == "lts" || rpm <= 0 ? 0.0 : revolutionTime(); }

double MixerScene::steadyResidenceFraction() const {
    return method == "lts" ? 0.0 : steadyResidence;
}

double MixerScene::steadyWindow(double loadingKg) const {
    return steady::windowLength(steadyWindow(), steadyPeriod(), steadyResidenceFraction(), loadingKg,
                                feedKgS());
}

nlohmann::json MixerScene::toJson() const {
    const auto& g = geometry;
    nlohmann::json j{{"scene", "mixer3d"},
            {"name", name},
            {"geometry",
             {{"length_m", g.length},
              {"bore_m", g.bore},
              {"shaft_diameter_m", g.shaftDiameter},
              {"paddle_count", g.paddleCount},
              {"paddle_tip_clearance_m", g.tipClearance},
              {"paddle_width_m", g.paddleWidth},
              {"paddle_thickness_m", g.paddleThickness},
              {"paddle_pitch_deg", g.pitchDeg},
              {"paddle_offset_deg", g.offsetDeg},
              {"end_gap_m", g.endGap},
              {"end_clearance_m", g.endClearance},
              {"weir_chord_angle_deg", g.weirChordDeg},
              {"weir_covers", g.weirCovers > 0 ? "+y" : "-y"},
              {"inlet_diameter_m", g.inletDiameter},
              {"inlet_height_m", g.inletHeight}}},
            {"material", material.toJson()},
            {"convention", convention},
            {"rheology", rheology},
            {"eta_max_pa_s", etaMaxValue()},
            {"p_min_pa", pMin},
            {"rpm", rpm},
            {"feed_kg_h", feedKgH},
            {"initial_loading_kg", initialLoadingKg},
            {"method", method},
            {"mesh", mesh},
            {"cell_size_m", cellSize},
            {"end_time_s", endTime},
            {"lts_iterations", ltsIterations},
            {"steady_window_revs", steadyWindowRevs},
            {"steady_tol", steadyTol},
            {"steady_flow_tol", steadyFlowTol},
            {"min_time_s", minTime},
            {"gravity_m_s2", gravity}};
    // Only a non-default limit or phase enters the record, so hashes of existing runs stay valid.
    if (g.phaseDeg != 0) j["geometry"]["paddle_phase_deg"] = g.phaseDeg;
    if (maxCourant != MixerScene{}.maxCourant) j["max_courant"] = maxCourant;
    // Sliding-mesh runs before the fragment transport lost powder across the AMI, and those with the
    // pairs' mean pressure coefficient diverged at 500 rpm: a new value keeps their results from
    // being taken for today's.
    if (method == "sm") {
        j["sm_transport"] = "fragments-kmax";
        j["sm_pcorr_rel_tol"] = kSlidingMeshPcorrRelTol;
    }
    // Runs before the numerics presets used the legacy settings and carry no key: theirs stay
    // valid. The values enter the record, not the preset's name.
    if (!numerics.sameSettings(MixerNumerics::named("legacy")))
        j["numerics"] = {{"air_viscosity_m2_s", numerics.airViscosity},
                         {"courant_alpha_min", numerics.courantAlphaMin},
                         {"non_orth_correctors", numerics.nonOrthCorrectors},
                         {"max_delta_t_s", numerics.maxDeltaT},
                         {"alpha_sub_cycles", numerics.alphaSubCycles}};
    // Frozen-rotor runs recorded before the O-grid existed were all on the snappy mesh, and the
    // sliding mesh has only ever used the O-grid: the key enters only where it is news.
    if (method != "sm" && mesher != "snappy") j["mesher"] = mesher;
    // Likewise the residence-time window: runs before it had windows of revolutions only.
    if (method != "lts" && steadyResidence > 0) j["steady_window_residence"] = steadyResidence;
    return j;
}

std::string MixerScene::hash() const { return stableHash(toJson().dump()); }

namespace {

// One [table] of the scene file: every key must be known, every number a number.
class Section {
public:
    Section(const toml::table& root, const std::string& name, const std::string& origin)
        : name_(name), origin_(origin) {
        if (const auto* t = root[name].as_table()) table_ = t;
    }
    double number(const std::string& key, double fallback) {
        seen_.insert(key);
        if (!table_) return fallback;
        const auto node = (*table_)[key];
        if (!node) return fallback;
        if (auto v = node.value<double>()) return *v;
        throw InputError(name_ + "." + key, "<not a number>", "a number (in " + origin_ + ")");
    }
    int whole(const std::string& key, int fallback) {
        const double v = number(key, fallback);
        if (v != std::floor(v) || std::abs(v) > 1e9)
            throw InputError(name_ + "." + key, formatNumber(v), "a whole number");
        return static_cast<int>(v);
    }
    std::string text(const std::string& key, const std::string& fallback) {
        seen_.insert(key);
        if (!table_) return fallback;
        const auto node = (*table_)[key];
        if (!node) return fallback;
        if (auto v = node.value<std::string>()) return *v;
        throw InputError(name_ + "." + key, "<not a string>", "a string (in " + origin_ + ")");
    }
    void checkKnown() const {
        if (!table_) return;
        for (const auto& [k, v] : *table_)
            if (!seen_.count(std::string(k.str())))
                throw InputError(origin_ + ": unknown key " + name_ + "." + std::string(k.str()));
    }

private:
    std::string name_, origin_;
    const toml::table* table_ = nullptr;
    std::set<std::string> seen_;
};

}  // namespace

MixerScene parseMixerScene(const std::string& text, const std::string& origin, const SceneKeys& keys) {
    toml::table root;
    try {
        root = toml::parse(text, origin);
    } catch (const toml::parse_error& e) {
        const auto& src = e.source();
        throw InputError(origin + ":" + std::to_string(src.begin.line) + ":" +
                         std::to_string(src.begin.column) + ": malformed TOML: " +
                         std::string(e.description()));
    }
    static const std::set<std::string> tables{"barrel", "impeller", "weir", "inlet",   "powder",
                                              "operation", "mesh", "numerics", "steady"};
    for (const auto& [key, value] : keys) {
        const auto dot = key.find('.');
        const std::string table = key.substr(0, dot);
        if (dot == std::string::npos || !tables.count(table))
            throw InputError("set", key, "TABLE.KEY with TABLE one of barrel, impeller, weir, inlet, powder, "
                                         "operation, mesh, numerics, steady");
        if (!root.contains(table)) root.insert(table, toml::table{});
        root[table].as_table()->insert_or_assign(key.substr(dot + 1), value);
    }
    for (const auto& [k, v] : root)
        if (!tables.count(std::string(k.str())))
            throw InputError(origin + ": unknown table [" + std::string(k.str()) + "]");

    MixerScene s;
    s.name = std::filesystem::path(origin).stem().string();
    auto& g = s.geometry;
    Section barrel(root, "barrel", origin), imp(root, "impeller", origin), weir(root, "weir", origin),
        inlet(root, "inlet", origin), powder(root, "powder", origin), op(root, "operation", origin),
        mesh(root, "mesh", origin), num(root, "numerics", origin), steady(root, "steady", origin);
    g.length = barrel.number("length_m", g.length);
    g.bore = barrel.number("bore_m", g.bore);
    g.shaftDiameter = imp.number("shaft_diameter_m", g.shaftDiameter);
    g.paddleCount = imp.whole("paddle_count", g.paddleCount);
    g.tipClearance = imp.number("paddle_tip_clearance_m", g.tipClearance);
    g.paddleWidth = imp.number("paddle_width_m", g.paddleWidth);
    g.paddleThickness = imp.number("paddle_thickness_m", g.paddleThickness);
    g.pitchDeg = imp.number("paddle_pitch_deg", g.pitchDeg);
    g.offsetDeg = imp.number("paddle_offset_deg", g.offsetDeg);
    g.phaseDeg = imp.number("paddle_phase_deg", g.phaseDeg);
    g.endGap = imp.number("end_gap_m", g.endGap);
    g.endClearance = imp.number("end_clearance_m", g.endClearance);
    g.weirChordDeg = weir.number("chord_angle_deg", g.weirChordDeg);
    const std::string covers = weir.text("covers", "+y");
    if (covers != "+y" && covers != "-y") throw InputError("weir.covers", covers, "+y|-y");
    g.weirCovers = covers == "+y" ? 1 : -1;
    g.inletDiameter = inlet.number("diameter_m", g.inletDiameter);
    g.inletHeight = inlet.number("height_m", g.inletHeight);
    s.material = loadMaterial(powder.text("material", "avicel"));
    s.convention = powder.text("convention", s.convention);
    s.rheology = powder.text("rheology", s.rheology);
    if (const double h = powder.number("eta_max_h_m", std::nan("")); !std::isnan(h)) s.etaMaxH = h;
    s.rpm = op.number("rpm", s.rpm);
    s.feedKgH = op.number("feed_kg_h", s.feedKgH);
    s.initialLoadingKg = op.number("initial_loading_kg", s.initialLoadingKg);
    s.levelCells = {mesh.number("coarse_cell_m", s.levelCells[0]),
                    mesh.number("medium_cell_m", s.levelCells[1]),
                    mesh.number("fine_cell_m", s.levelCells[2])};
    s.mesher = mesh.text("mesher", s.mesher);
    s.numerics = MixerNumerics::named(num.text("preset", s.numerics.preset));
    auto& n = s.numerics;
    n.airViscosity = num.number("air_viscosity_m2_s", n.airViscosity);
    n.courantAlphaMin = num.number("courant_alpha_min", n.courantAlphaMin);
    n.nonOrthCorrectors = num.whole("non_orth_correctors", n.nonOrthCorrectors);
    n.maxDeltaT = num.number("max_delta_t_s", n.maxDeltaT);
    n.alphaSubCycles = num.whole("alpha_sub_cycles", n.alphaSubCycles);
    // The steady test and the cap on simulated time belong to the scene when its residence time
    // is minutes (a deep bed): the defaults suit the thin-film scene.
    s.endTime = steady.number("end_time_s", s.endTime);
    s.steadyWindowRevs = steady.number("window_revs", s.steadyWindowRevs);
    s.steadyResidence = steady.number("window_residence", s.steadyResidence);
    s.steadyTol = steady.number("tol", s.steadyTol);
    s.steadyFlowTol = steady.number("flow_tol", s.steadyFlowTol);
    for (auto* sec : {&barrel, &imp, &weir, &inlet, &powder, &op, &mesh, &num, &steady}) sec->checkKnown();
    for (int i = 0; i < 3; ++i)
        requireRange(std::string("mesh.") + (i == 0 ? "coarse" : i == 1 ? "medium" : "fine") +
                         "_cell_m",
                     s.levelCells[i], 1e-4, 0.1);
    s.setMesh("coarse");
    s.validate();
    return s;
}

namespace {
std::string shippedScenes() {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dataDir() / "scenes"))
        if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}
}  // namespace

MixerScene loadMixerScene(const std::string& nameOrPath, const SceneKeys& keys) {
    std::filesystem::path p(nameOrPath);
    if (p.extension() != ".toml") p = dataDir() / "scenes" / (nameOrPath + ".toml");
    if (!std::filesystem::exists(p)) throw InputError("scene", nameOrPath, "a shipped scene (data/scenes: " + shippedScenes() + ") or a scene .toml file");
    return parseMixerScene(readFile(p), p.string(), keys);
}

void parseSceneKey(const std::string& assignment, SceneKeys& keys) {
    const auto eq = assignment.find('=');
    const std::string key = assignment.substr(0, eq);
    if (eq == std::string::npos || key.find('.') == std::string::npos)
        throw InputError("set", assignment, "TABLE.KEY=NUMBER, e.g. weir.chord_angle_deg=70");
    const std::string text = assignment.substr(eq + 1);
    const auto v = parseNumber(text);
    if (!v || !std::isfinite(*v)) throw InputError("set " + key, text, "a finite number");
    keys[key] = *v;
}

double depositHeight(double volume, double R, double L) {
    // Segment area A(h) = R^2 acos(1 - h/R) - (R - h) sqrt(2Rh - h^2) for depth h from the bottom;
    // monotone in h, so bisection is exact enough and never fails.
    const double target = volume / L;
    double lo = 0, hi = 2 * R;
    for (int i = 0; i < 100; ++i) {
        const double h = 0.5 * (lo + hi);
        const double a = R * R * std::acos(1 - h / R) - (R - h) * std::sqrt(std::max(0.0, 2 * R * h - h * h));
        (a < target ? lo : hi) = h;
    }
    return 0.5 * (lo + hi) - R;
}

}  // namespace mixload::scene
