// SPDX-License-Identifier: GPL-3.0-or-later
#include "calibrate/collapse_data.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <toml++/toml.h>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "scene/material.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) {
        const auto b = cell.find_first_not_of(" \t\r"), e = cell.find_last_not_of(" \t\r");
        out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
    }
    if (!line.empty() && line.back() == ',') out.push_back("");
    return out;
}

const char* kColumns[] = {"aspect", "runout_star", "runout_sd", "height_star", "height_sd"};

}  // namespace

nlohmann::json CollapseData::toJson() const {
    nlohmann::json pts = nlohmann::json::array();
    for (const auto& p : points) {
        nlohmann::json j{{"aspect", p.aspect}};
        if (p.runout) j["runout_star"] = *p.runout, j["runout_sd"] = *p.runoutSd;
        if (p.height) j["height_star"] = *p.height, j["height_sd"] = *p.heightSd;
        pts.push_back(j);
    }
    return {{"source", source}, {"points", pts}};
}

CollapseData parseCollapseData(const std::string& text, const std::string& origin) {
    CollapseData d;
    std::stringstream in(text);
    bool header = false;
    int lineNo = 0;
    for (std::string line; std::getline(in, line);) {
        ++lineNo;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos) continue;
        if (line[first] == '#') {
            if (d.source.empty()) d.source = line.substr(line.find_first_not_of("# \t", first));
            continue;
        }
        const auto cells = splitCsv(line);
        const std::string where = origin + ":" + std::to_string(lineNo);
        if (!header) {
            std::string want;
            for (const char* c : kColumns) want += (want.empty() ? "" : ",") + std::string(c);
            if (cells.size() != 5 || !std::equal(cells.begin(), cells.end(), std::begin(kColumns)))
                throw InputError(where + ": header", line, want);
            header = true;
            continue;
        }
        if (cells.size() != 5) throw InputError(where, line, "5 comma-separated fields");
        std::optional<double> v[5];
        for (int i = 0; i < 5; ++i) {
            if (cells[i].empty()) continue;
            v[i] = parseNumber(cells[i]);
            if (!v[i] || !std::isfinite(*v[i])) throw InputError(where + ": " + kColumns[i], cells[i], "a number or empty");
        }
        CollapseMeasurement p;
        if (!v[0]) throw InputError(where + ": aspect", "<empty>", "a number in [0.2, 10]");
        p.aspect = *v[0];
        requireRange(where + ": aspect", p.aspect, 0.2, 10.0);
        // A value and its uncertainty come together: a point without one cannot be weighed.
        for (int q = 0; q < 2; ++q) {
            const int vi = 1 + 2 * q, si = vi + 1;
            if (v[vi].has_value() != v[si].has_value())
                throw InputError(where + ": " + kColumns[si], cells[si].empty() ? "<empty>" : cells[si],
                                 std::string("given together with ") + kColumns[vi]);
            if (!v[vi]) continue;
            requireRange(where + ": " + kColumns[vi], *v[vi], 0.0, q == 0 ? 100.0 : 1.0, false, true);
            requireRange(where + ": " + kColumns[si], *v[si], 0.0, 100.0, false, true);
            (q == 0 ? p.runout : p.height) = v[vi];
            (q == 0 ? p.runoutSd : p.heightSd) = v[si];
        }
        if (!p.runout && !p.height)
            throw InputError(where, line, "a runout_star or a height_star (with its _sd)");
        for (const auto& o : d.points)
            if (o.aspect == p.aspect) throw InputError(where + ": aspect", cells[0], "each aspect once");
        d.points.push_back(p);
    }
    if (!header) throw InputError(origin, "<no header>", "a CSV with the header aspect,runout_star,runout_sd,height_star,height_sd");
    if (d.points.empty()) throw InputError(origin, "<no rows>", "at least one data row");
    if (d.source.empty()) d.source = origin;
    std::sort(d.points.begin(), d.points.end(), [](const auto& a, const auto& b) { return a.aspect < b.aspect; });
    return d;
}

CollapseData readCollapseData(const fs::path& file) {
    if (!fs::is_regular_file(file)) throw InputError("data", file.string(), "an existing CSV file");
    return parseCollapseData(readFile(file), file.string());
}

std::optional<double> CollapseLaw::value(const std::vector<PowerPiece>& law, double a) {
    for (const auto& p : law)
        if (a >= p.aMin && a <= p.aMax) return p.c * std::pow(a, p.e);
    return std::nullopt;
}

std::string CollapseLaw::regimes() const {
    std::string s;
    for (const auto& p : runout) s += (s.empty() ? "[" : " or [") + formatNumber(p.aMin) + ", " + formatNumber(p.aMax) + "]";
    return s;
}

namespace {

std::vector<PowerPiece> readPieces(const toml::table& t, const std::string& table, const std::string& origin,
                                   bool required) {
    const auto* arr = t[table]["pieces"].as_array();
    if (!arr || arr->empty()) {
        if (!required) return {};
        throw InputError(origin + ": " + table + ".pieces", "<missing>", "an array of {a_min, a_max, c, e}");
    }
    std::vector<PowerPiece> out;
    for (const auto& node : *arr) {
        const auto* p = node.as_table();
        const auto num = [&](const char* k) { return p ? (*p)[k].value<double>() : std::nullopt; };
        const auto aMin = num("a_min"), aMax = num("a_max"), c = num("c"), e = num("e");
        if (!aMin || !aMax || !c || !e)
            throw InputError(origin + ": " + table + ".pieces", "<entry>", "{a_min, a_max, c, e} numbers");
        if (!(*aMax > *aMin && *aMin > 0 && *c > 0) || (!out.empty() && *aMin < out.back().aMax))
            throw InputError(origin + ": " + table + ".pieces", formatNumber(*aMin) + ".." + formatNumber(*aMax),
                             "0 < a_min < a_max, c > 0, pieces in increasing order without overlap");
        out.push_back({*aMin, *aMax, *c, *e});
    }
    return out;
}

}  // namespace

CollapseLaw loadCollapseLaw(const std::string& nameOrPath) {
    fs::path p(nameOrPath);
    if (p.extension() != ".toml") {
        p = scene::dataDir() / "collapse-laws" / (nameOrPath + ".toml");
        if (!fs::exists(p)) {
            std::string names;
            for (const auto& n : shippedCollapseLaws()) names += (names.empty() ? "" : "|") + n;
            throw InputError("law", nameOrPath, names + " or a .toml file");
        }
    }
    if (!fs::exists(p)) throw InputError("law", nameOrPath, "an existing .toml file");
    const std::string origin = p.string();
    toml::table t;
    try {
        t = toml::parse(readFile(p), origin);
    } catch (const toml::parse_error& e) {
        throw InputError(origin + ":" + std::to_string(e.source().begin.line) + ": malformed TOML: " +
                         std::string(e.description()));
    }
    CollapseLaw law;
    law.name = t["name"].value_or(p.stem().string());
    law.citation = t["citation"].value_or(std::string());
    law.material = t["material"].value_or(std::string());
    law.geometry = t["geometry"].value_or(std::string());
    law.provenance = t["provenance"].value_or(std::string());
    if (law.citation.empty()) throw InputError(origin + ": citation", "<missing>", "the law's source");
    law.runout = readPieces(t, "runout", origin, true);
    law.height = readPieces(t, "height", origin, false);
    law.runoutRelSd = t["runout"]["relative_sd"].value_or(0.1);
    law.heightRelSd = t["height"]["relative_sd"].value_or(0.05);
    requireRange(origin + ": runout.relative_sd", law.runoutRelSd, 0.0, 1.0, false, true);
    requireRange(origin + ": height.relative_sd", law.heightRelSd, 0.0, 1.0, false, true);
    return law;
}

std::vector<std::string> shippedCollapseLaws() {
    std::vector<std::string> names;
    const fs::path dir = scene::dataDir() / "collapse-laws";
    if (fs::is_directory(dir))
        for (const auto& e : fs::directory_iterator(dir))
            if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

CollapseData collapseDataFromLaw(const CollapseLaw& law, const std::vector<double>& aspects) {
    if (aspects.empty()) throw InputError("aspects", "<none>", "at least one aspect ratio");
    CollapseData d;
    d.source = law.name + " (" + law.citation + ")";
    for (double a : aspects) {
        CollapseMeasurement p;
        p.aspect = a;
        p.runout = CollapseLaw::value(law.runout, a);
        if (!p.runout) throw InputError("aspects", formatNumber(a), "inside the regimes " + law.name + " fits: " + law.regimes());
        p.runoutSd = law.runoutRelSd * *p.runout;
        if (const auto h = CollapseLaw::value(law.height, a)) {
            p.height = std::min(1.0, *h);
            p.heightSd = law.heightRelSd * *p.height;
        }
        for (const auto& o : d.points)
            if (o.aspect == a) throw InputError("aspects", formatNumber(a), "each aspect once");
        d.points.push_back(p);
    }
    std::sort(d.points.begin(), d.points.end(), [](const auto& a, const auto& b) { return a.aspect < b.aspect; });
    return d;
}

}  // namespace mixload::experiments
