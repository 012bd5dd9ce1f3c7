// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/design_space.hpp"

namespace mixload::experiments {

ParameterSpace rangesOf(const store::CampaignInfo& c, const std::string& name) {
    return parseRanges(c.rangesToml, name + " (ranges recorded in the ledger)");
}

std::vector<double> unitOf(const ParameterSpace& space, const store::LedgerRun& r) {
    std::vector<double> x;
    for (const auto& p : space.params) x.push_back(r.params.at(p.name).get<double>());
    return space.toUnit(x);
}

double distance2(const std::vector<double>& a, const std::vector<double>& b) {
    double d2 = 0;
    for (size_t k = 0; k < a.size(); ++k) d2 += (a[k] - b[k]) * (a[k] - b[k]);
    return d2;
}

}  // namespace mixload::experiments
