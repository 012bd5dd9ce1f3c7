// SPDX-License-Identifier: GPL-3.0-or-later
// The regime model (kind "regimes", issue 64): one kriging model per flow regime of the calibrated
// mixer, because the loading falls tenfold between neighbouring runs across the bed-to-film band
// and one stationary kriging model cannot bend that sharply without smearing the error over the
// bed and the film (shipped kriging on v2-holdout: bed 13.5%, film 54.9% with one bistable label).
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/input_error.hpp"
#include "error_stats.hpp"
#include "model.hpp"
#include "regime.hpp"

namespace mixload::surrogates {

namespace {

// Below this weight a part takes no part in the answer (its model may not even know the point).
constexpr double kMinWeight = 1e-3;

bool ownRegime(const Row& r, int part) { return static_cast<int>(regimeOf(r.x)) == part; }

// Mean relative leave-one-out error of a fitted part over the runs of its own regime.
double ownLoo(const Surrogate& s, const std::vector<Row>& rows, int part) {
    ErrorStats e;
    for (const auto& r : rows)
        if (ownRegime(r, part) && s.loo().contains(r.id)) {
            const auto& l = s.loo()[r.id];
            e.add(r.m, l[0].get<double>(), l[1].get<double>(), l[2].get<double>());
        }
    return e.n ? e.mean().get<double>() : std::numeric_limits<double>::infinity();
}

}  // namespace

Surrogate Surrogate::fitRegimes(const std::vector<Row>& train, const FitOptions& o, nlohmann::json provenance) {
    // The bed persists into the band at high feeds (v2: 0.21 kg at 144 rpm x 38 kg/h, 0.15 kg at
    // 183 rpm x 52 kg/h), so the bed part also learns from the band's runs; the film part only from
    // films; the transition part from every run, so that it knows both sides of the band.
    const std::array<const char*, 3> sets{"runs up to the film's boundary", "every run", "the film's runs"};
    std::array<std::vector<Row>, 3> rows;
    for (const auto& r : train) {
        const auto g = regimeOf(r.x);
        if (g != Regime::Film) rows[0].push_back(r);
        rows[1].push_back(r);
        if (g == Regime::Film) rows[2].push_back(r);
    }
    for (int p = 0; p < 3; ++p)
        if (rows[static_cast<size_t>(p)].size() < 5)
            throw InputError(std::string(regimeName(static_cast<Regime>(p))) + " runs",
                             std::to_string(rows[static_cast<size_t>(p)].size()),
                             std::string("at least 5 finished, steady runs for the regime model's ") + regimeName(static_cast<Regime>(p)) +
                                 " part (" + sets[static_cast<size_t>(p)] + "; bed below " + formatNumber(kBedMaxRpm) +
                                 " rpm, film above " + formatNumber(kFilmMinRpm) + " rpm)");
    // Candidates per part: the options as given, and power laws in the feed (and rpm): a film's
    // loading is its feed times a residence time of a few seconds, a power of the feed.
    const std::string feed = o.similarity ? "feed/rho" : "feed_kg_h";
    std::vector<FitOptions> candidates;
    FitOptions given = o;
    given.kind = "kriging";
    candidates.push_back(given);
    for (const auto& trend : std::vector<std::vector<std::string>>{{feed}, {feed, "rpm"}}) {
        FitOptions c = given;
        c.transform = "log";
        c.trendInputs = trend;
        candidates.push_back(c);
    }
    nlohmann::json partProvenance = nlohmann::json::object();
    if (provenance.contains("full_barrel_m3")) partProvenance["full_barrel_m3"] = provenance["full_barrel_m3"];

    Surrogate s;
    nlohmann::json parts = nlohmann::json::array();
    for (int p = 0; p < 3; ++p) {
        const auto& set = rows[static_cast<size_t>(p)];
        std::optional<Surrogate> best;
        std::string bestTrend;
        double bestErr = std::numeric_limits<double>::infinity();
        nlohmann::json tried = nlohmann::json::array();
        for (const auto& c : candidates) {
            std::string trend;
            for (const auto& t : c.trendInputs) trend += (trend.empty() ? "" : ",") + t;
            try {
                auto part = fit(set, c, partProvenance);
                const double err = ownLoo(part, set, p);
                tried.push_back({{"transform", part.validation()["transform"]}, {"trend_inputs", trend}, {"own_loo_mean_rel_error", err}});
                // An inadmissible part (less than none or more than a full barrel in its box) loses to an admissible one.
                const bool admissible = !part.validation().contains("non_physical");
                const bool bestAdmissible = best && !best->validation().contains("non_physical");
                if (!best || (admissible && !bestAdmissible) || (admissible == bestAdmissible && err < bestErr))
                    bestErr = err, bestTrend = trend, best = std::move(part);
            } catch (const InputError& e) {
                tried.push_back({{"trend_inputs", trend}, {"failed", e.what()}});
            }
        }
        if (!best) throw InputError(std::string("the regime model's ") + regimeName(static_cast<Regime>(p)) + " part could not be fitted: " + tried.dump());
        parts.push_back({{"regime", regimeName(static_cast<Regime>(p))},
                         {"trained_on", sets[static_cast<size_t>(p)]},
                         {"n_train", set.size()},
                         {"transform", best->validation()["transform"]},
                         {"trend_inputs", bestTrend},
                         {"own_loo_mean_rel_error", bestErr},
                         {"candidates", tried}});
        s.parts_.push_back(std::move(*best));
    }
    // The composite answers box questions through its parts; its own box (the transition part's,
    // which saw every run) names the model's inputs and scales coordinates().
    const Surrogate& all = s.parts_[1];
    s.kind_ = "regimes";
    s.tf_ = all.tf_;
    s.in_ = all.in_;
    s.min_ = all.min_, s.max_ = all.max_, s.dmin_ = all.dmin_, s.dmax_ = all.dmax_, s.umin_ = all.umin_, s.umax_ = all.umax_;
    // Leave-one-out: each run by the part of its own regime (near a boundary the blend is not replayed).
    ErrorStats stats;
    std::array<ErrorStats, 3> by;
    s.loo_ = nlohmann::json::object();
    for (const auto& r : train) {
        const auto g = static_cast<size_t>(regimeOf(r.x));
        const auto& l = s.parts_[g].loo()[r.id];
        s.loo_[r.id] = l;
        stats.add(r.m, l[0].get<double>(), l[1].get<double>(), l[2].get<double>());
        by[g].add(r.m, l[0].get<double>(), l[1].get<double>(), l[2].get<double>());
    }
    nlohmann::json byRegime = nlohmann::json::object();
    for (size_t g = 0; g < 3; ++g)
        byRegime[regimeName(static_cast<Regime>(g))] = {{"n", by[g].n}, {"mean_rel_error", by[g].mean()}, {"coverage95", by[g].coverage()}};
    std::string transform = "per regime:";
    for (size_t p = 0; p < 3; ++p) {
        const auto trend = parts[p]["trend_inputs"].get<std::string>();
        transform += std::string(p ? ";" : "") + " " + regimeName(static_cast<Regime>(p)) + " " +
                     parts[p]["transform"].get<std::string>() + (trend.empty() ? "" : ", linear trend in " + trend);
    }
    s.validation_ = {{"method", "leave-one-out of each run in its own regime's part (closed form, hyperparameters fixed)"},
                     {"n", train.size()},
                     {"mean_rel_error", stats.mean()},
                     {"max_rel_error", stats.maxJson()},
                     {"coverage95", stats.coverage()},
                     {"by_regime", byRegime},
                     {"transform", transform},
                     {"parts", parts},
                     {"regimes", {{"bed_max_rpm", kBedMaxRpm}, {"film_min_rpm", kFilmMinRpm}, {"blend_rpm", kRegimeBlendRpm}}}};
    for (const auto& r : train) s.trained_.push_back(r.id);
    s.provenance_ = std::move(provenance);
    s.setFullBarrel();
    return s;
}

bool Surrogate::inBoxRegimes(const Point& x) const {
    const auto w = regimeWeights(x[kRpm]);
    for (size_t r = 0; r < parts_.size(); ++r)
        if (w[r] >= kMinWeight && !parts_[r].inBox(x)) return false;
    return true;
}

double Surrogate::outsideRegimes(const Point& x) const {
    const auto w = regimeWeights(x[kRpm]);
    double d = 0;
    for (size_t r = 0; r < parts_.size(); ++r)
        if (w[r] >= kMinWeight) d = std::max(d, parts_[r].outsideDistance(x));
    return d;
}

std::vector<std::string> Surrogate::outsideBoxRegimes(const Point& x) const {
    const auto w = regimeWeights(x[kRpm]);
    std::vector<std::string> out;
    for (size_t r = 0; r < parts_.size(); ++r)
        if (w[r] >= kMinWeight)
            for (const auto& o : parts_[r].outsideBox(x)) out.push_back(o + " in the " + regimeName(static_cast<Regime>(r)) + " part");
    return out;
}

Prediction Surrogate::predictRegimes(const Point& x, Workspace& ws) const {
    const auto w = regimeWeights(x[kRpm]);
    Prediction p;
    double weight = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo, outside = 0;
    bool inside = true;
    for (size_t r = 0; r < parts_.size(); ++r) {
        if (w[r] < kMinWeight) continue;
        const auto q = parts_[r].predict(x, ws.parts[r]);
        p.m += w[r] * q.m;
        weight += w[r];
        // Where two parts share a point, the full run may follow either: the interval spans both.
        lo = std::min(lo, q.lo);
        hi = std::max(hi, q.hi);
        outside = std::max(outside, q.outside);
        inside = inside && q.inBox;
        p.clipped = p.clipped || q.clipped;
    }
    p.m /= weight;
    p.lo = lo;
    p.hi = hi;
    physicalBounds(x, p);
    p.inBox = inside;
    p.outside = outside;
    return p;
}

Difference Surrogate::predictDifferenceRegimes(const Point& a, const Point& b) const {
    const auto wa = regimeWeights(a[kRpm]), wb = regimeWeights(b[kRpm]);
    for (size_t r = 0; r < parts_.size(); ++r)
        if (wa[r] > 1 - kMinWeight && wb[r] > 1 - kMinWeight) return parts_[r].predictDifference(a, b);
    // Two regimes (or a blend): the parts' errors are not modelled jointly, so take them as
    // unrelated and bound the difference by the two intervals' extremes, which is wider than
    // the 95% interval of independent normal errors.
    auto ws = makeWorkspace();
    const auto pa = predict(a, ws), pb = predict(b, ws);
    Difference d;
    d.dm = pb.m - pa.m;
    d.lo = d.loIndependent = pb.lo - pa.hi;
    d.hi = d.hiIndependent = pb.hi - pa.lo;
    d.correlation = 0;
    return d;
}

nlohmann::json Surrogate::regimesJson() const {
    nlohmann::json parts = nlohmann::json::array();
    for (const auto& p : parts_) parts.push_back(p.toJson());
    return {{"bed_max_rpm", kBedMaxRpm}, {"film_min_rpm", kFilmMinRpm}, {"blend_rpm", kRegimeBlendRpm}, {"parts", parts}};
}

void Surrogate::regimesFromJson(const nlohmann::json& model) {
    // A model cut at other boundaries would be answered by the wrong parts: refuse it.
    if (model.value("bed_max_rpm", 0.0) != kBedMaxRpm || model.value("film_min_rpm", 0.0) != kFilmMinRpm ||
        model.value("blend_rpm", 0.0) != kRegimeBlendRpm)
        throw std::runtime_error("regime model cut at other boundaries than this mixload's (bed below " +
                                 formatNumber(kBedMaxRpm) + " rpm, film above " + formatNumber(kFilmMinRpm) + " rpm)");
    if (!model.contains("parts") || !model["parts"].is_array() || model["parts"].size() != 3)
        throw std::runtime_error("field 'model.parts' must hold the bed, transition and film models");
    parts_.clear();
    for (const auto& p : model["parts"]) {
        parts_.push_back(fromJson(p));
        if (parts_.back().kind_ == "regimes") throw std::runtime_error("a regime model's part is itself a regime model");
    }
}

}  // namespace mixload::surrogates
