// SPDX-License-Identifier: GPL-3.0-or-later
// What a collapse calibration fits to: the CSV of measurements (every malformed row refused with
// its line and field) and the shipped published law (values where its authors fit one, nothing in
// the transition between its regimes).
#include <gtest/gtest.h>

#include <cmath>

#include "calibrate/collapse_data.hpp"
#include "common/input_error.hpp"

using namespace mixload::experiments;
using mixload::InputError;

namespace {
const char* kHeader = "aspect,runout_star,runout_sd,height_star,height_sd\n";
}

TEST(CollapseData, ReadsPointsWithEitherQuantity) {
    const auto d = parseCollapseData(std::string("# my rig, 2026\n") + kHeader +
                                         "2,2.4,0.2,0.4,0.02\n0.5,,,1.0,0.01\n1, 1.3 ,0.1,,\n",
                                     "t.csv");
    EXPECT_EQ(d.source, "my rig, 2026");
    ASSERT_EQ(d.points.size(), 3u);
    EXPECT_DOUBLE_EQ(d.points[0].aspect, 0.5);  // sorted by aspect
    EXPECT_FALSE(d.points[0].runout);
    EXPECT_DOUBLE_EQ(*d.points[0].height, 1.0);
    EXPECT_DOUBLE_EQ(*d.points[1].runout, 1.3);
    EXPECT_FALSE(d.points[1].height);
    EXPECT_DOUBLE_EQ(*d.points[2].heightSd, 0.02);
}

TEST(CollapseData, RefusesMalformedRowsNamingLineAndField) {
    const auto refuses = [](const std::string& body, const std::string& needle) {
        try {
            parseCollapseData(std::string(kHeader) + body, "t.csv");
            ADD_FAILURE() << "accepted: " << body;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    refuses("1,1.3,,0.4,0.02\n", "t.csv:2: runout_sd");  // a value without its uncertainty
    refuses("1,1.3,-0.1,,\n", "runout_sd");              // uncertainty not positive
    refuses("1,,,,\n", "t.csv:2");                        // nothing to fit
    refuses("12,1.3,0.1,,\n", "aspect");                  // outside what the scene runs
    refuses("1,1.3,0.1,1.4,0.1\n", "height_star");        // H*f above 1
    refuses("1,x,0.1,,\n", "runout_star");
    refuses("1,1.3,0.1,,\n1,1.4,0.1,,\n", "each aspect once");
    EXPECT_THROW(parseCollapseData("a,b\n1,2\n", "t.csv"), InputError);  // wrong header
    EXPECT_THROW(parseCollapseData(kHeader, "t.csv"), InputError);      // no rows
}

TEST(CollapseLaw, ShippedLube2005HasValuesOnlyInItsRegimes) {
    const auto law = loadCollapseLaw("lube2005");
    EXPECT_NE(law.citation.find("Phys. Rev. E 72"), std::string::npos);
    const auto d = collapseDataFromLaw(law, {1.0, 4.0});
    EXPECT_DOUBLE_EQ(*d.points[0].runout, 1.2);
    EXPECT_NEAR(*d.points[1].runout, 1.9 * std::pow(4.0, 2.0 / 3.0), 1e-12);
    EXPECT_NEAR(*d.points[1].runoutSd, 0.1 * *d.points[1].runout, 1e-12);
    EXPECT_FALSE(d.points[0].height);  // no height law shipped with it
    EXPECT_THROW(collapseDataFromLaw(law, {2.3}), InputError);  // between the regimes
    EXPECT_THROW(collapseDataFromLaw(law, {}), InputError);
    EXPECT_THROW(loadCollapseLaw("no-such-law"), InputError);
}
