// SPDX-License-Identifier: GPL-3.0-or-later
// The surrogate model file around response surfaces and kriging: fitting in physical units with
// the transform chosen by leave-one-out error, bit-identical round trips, refusal of files from
// another schema or with missing fields, the training box, allocation-free prediction, checks.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include <unistd.h>

#include "alloc_counter.hpp"
#include "check.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "model.hpp"

using namespace mixload::surrogates;
namespace fs = std::filesystem;

namespace {

// A smooth loading law with the trends of the real one (grows with feed, falls with rpm).
double law(const Point& x) {
    return 0.03 * std::pow(x[5] / 20, 0.65) * std::pow(x[6] / 100, -0.4) * (1 + 0.3 * (x[0] - 0.3)) *
           (1 + 0.1 * (x[2] - 0.3)) * std::pow(x[4] / 400, 0.2);
}

std::vector<Row> rows(int n, unsigned seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Row> out;
    for (int i = 0; i < n; ++i) {
        Row r;
        r.id = "run" + std::to_string(seed) + "-" + std::to_string(i);
        const double mus = 0.2 + 0.25 * u(g);
        r.x = {mus, mus + 0.05 + 0.25 * u(g), 0.1 + 0.5 * u(g), 100e-6 + 300e-6 * u(g), 250 + 350 * u(g), 5 + 40 * u(g),
               39 + 215 * u(g)};
        r.m = law(r.x);
        out.push_back(r);
    }
    return out;
}

fs::path scratch(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("mixload-surrogate-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d / name;
}

}  // namespace

TEST(SurrogateModel, FitsAndRoundTripsBitIdenticallyForBothKinds) {
    const auto train = rows(40, 1), test = rows(20, 2);
    for (const char* kind : {"rsm", "kriging"}) {
        FitOptions o;
        o.kind = kind;
        const auto m = Surrogate::fit(train, o, {{"campaign", "synthetic"}});
        EXPECT_EQ(m.trainingIds().size(), 40u);
        EXPECT_LT(m.validation()["mean_rel_error"].get<double>(), 0.05) << kind;
        // A power law: the log transform must win the leave-one-out comparison.
        EXPECT_TRUE(m.transform().logOutput) << kind;
        const fs::path f = scratch(std::string(kind) + ".json");
        m.save(f);
        const auto r = Surrogate::load(f);
        auto w1 = m.makeWorkspace(), w2 = r.makeWorkspace();
        double err = 0;
        for (const auto& t : test) {
            const auto a = m.predict(t.x, w1), b = r.predict(t.x, w2);
            EXPECT_EQ(a.m, b.m);
            EXPECT_EQ(a.lo, b.lo);
            EXPECT_EQ(a.hi, b.hi);
            EXPECT_LE(a.lo, a.m);
            EXPECT_GE(a.hi, a.m);
            err += std::abs(a.m - t.m) / t.m;
        }
        EXPECT_LT(err / test.size(), 0.05) << kind;
        // The same text again: nothing lost, nothing added.
        EXPECT_EQ(r.toJson().dump(), m.toJson().dump());
    }
}

TEST(SurrogateModel, RejectsOtherSchemasAndMissingFields) {
    FitOptions o;
    o.kind = "rsm";
    const auto j = Surrogate::fit(rows(30, 3), o, {}).toJson();
    const auto rejected = [](nlohmann::json bad, const std::string& needle) {
        const fs::path f = scratch("bad.json");
        mixload::writeFileAtomic(f, bad.dump());
        try {
            Surrogate::load(f);
            ADD_FAILURE() << "accepted a model with " << needle;
        } catch (const mixload::InputError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
        }
    };
    auto v = j;
    v["schema_version"] = 2;
    rejected(v, "schema version 2");
    v = j;
    v["schema"] = "something-else";
    rejected(v, "not a mixload surrogate");
    for (const char* field : {"training_ids", "inputs", "model", "validation", "provenance"}) {
        v = j;
        v.erase(field);
        rejected(v, field);
    }
    v = j;
    v["model"].erase("coefficients");
    rejected(v, "coefficients");
}

TEST(SurrogateModel, KnowsItsTrainingBox) {
    FitOptions o;
    o.kind = "rsm";
    const auto train = rows(30, 4);
    const auto m = Surrogate::fit(train, o, {});
    EXPECT_TRUE(m.inBox(train[0].x));
    auto x = train[0].x;
    x[6] = m.boxMax()[6] * 1.5;
    EXPECT_FALSE(m.inBox(x));
    const auto out = m.outsideBox(x);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NE(out[0].find("rpm"), std::string::npos);
    auto ws = m.makeWorkspace();
    EXPECT_FALSE(m.predict(x, ws).inBox);
}

TEST(SurrogateModel, PredictionDoesNotAllocate) {
    for (const char* kind : {"rsm", "kriging"}) {
        FitOptions o;
        o.kind = kind;
        const auto m = Surrogate::fit(rows(40, 5), o, {});
        const auto pts = rows(200, 6);
        auto ws = m.makeWorkspace();
        double sum = 0;
        mixload::testing::startCountingAllocations();
        for (const auto& p : pts) sum += m.predict(p.x, ws).m;
        EXPECT_EQ(mixload::testing::stopCountingAllocations(), 0) << kind;
        EXPECT_TRUE(std::isfinite(sum));
    }
}

TEST(SurrogateModel, CheckSeparatesHoldOutFromTraining) {
    const auto all = rows(45, 7);
    const std::vector<Row> train(all.begin(), all.begin() + 35);
    FitOptions o;
    o.kind = "kriging";
    const auto m = Surrogate::fit(train, o, {});
    Table t;
    t.rows = all;
    const auto c = checkModel(m, t);
    EXPECT_EQ(c["n_holdout"], 10);
    EXPECT_EQ(c["loo"]["n"], 35);
    EXPECT_LT(c["mean_rel_error"].get<double>(), 0.05);
    EXPECT_GE(c["max_rel_error"].get<double>(), c["mean_rel_error"].get<double>());
    EXPECT_GE(c["coverage95"].get<double>(), 0.0);
    EXPECT_LE(c["coverage95"].get<double>(), 1.0);
    // The closed-form LOO errors are the validation statistics recorded at fit time.
    EXPECT_NEAR(c["loo"]["mean_rel_error"].get<double>(), m.validation()["mean_rel_error"].get<double>(), 1e-12);
}
