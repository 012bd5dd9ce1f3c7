// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/pod/pod_model.hpp"


#include <map>
#include <sstream>

#include "common/input_error.hpp"
#include "store/case_file.hpp"
#include "store/h5_io.hpp"

namespace mixload::rom {

namespace fs = std::filesystem;

std::vector<Eigen::Index> PodModel::fieldStarts() const {
    std::vector<Eigen::Index> s;
    Eigen::Index at = 0;
    for (int c : components) {
        s.push_back(at);
        at += static_cast<Eigen::Index>(cells) * c;
    }
    return s;
}

Eigen::MatrixXd stackedFields(const store::SnapshotFile& f, const std::vector<std::string>& fields) {
    std::vector<Eigen::MatrixXd> parts;
    Eigen::Index rows = 0;
    for (const auto& name : fields) {
        parts.push_back(f.matrix(name));
        rows += parts.back().rows();
    }
    Eigen::MatrixXd x(rows, parts.front().cols());
    Eigen::Index at = 0;
    for (const auto& p : parts) {
        x.middleRows(at, p.rows()) = p;
        at += p.rows();
    }
    return x;
}

PodModel buildPod(const store::SnapshotSet& set, const std::vector<std::string>& fields, const PodOptions& options) {
    if (fields.empty()) throw InputError("field", "(none)", "one or more stored fields (alpha, U, p, ...)");
    requireRange("energy", options.energy, 0.0, 1.0, false, true);
    requireRange("modes", options.maxModes, 0, 1 << 20);
    PodModel m;
    m.fields = fields;
    m.cells = set.cells();
    m.meshFingerprint = set.files().front().meshFingerprint();
    m.energyTarget = options.energy;
    Eigen::VectorXd weights;
    for (const auto& name : fields) {
        const int c = set.components(name);  // names a missing field
        m.components.push_back(c);
        const Eigen::VectorXd w = set.cellVolumes().replicate(1, c).transpose().reshaped();
        weights.conservativeResize(weights.size() + w.size());
        weights.tail(w.size()) = w;
    }
    PodOptions o = options;
    o.fieldStarts = fields.size() > 1 ? m.fieldStarts() : std::vector<Eigen::Index>{};
    m.basis = computePod(
        set.files().size(), [&](size_t i) { return stackedFields(set.files()[i], fields); }, weights, o);
    for (const auto& f : set.files())
        m.sources.push_back({{"file", fs::absolute(f.path()).string()},
                             {"scene_hash", f.provenance().value("scene_hash", std::string())},
                             {"times", f.times().size()}});
    return m;
}

namespace {
std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
    return s;
}

// HDF5 stores row-major: a mode is one row of /modes, read as one hyperslab.
std::vector<double> rowMajor(const Eigen::MatrixXd& m) {
    const Eigen::MatrixXd t = m.transpose();
    return {t.data(), t.data() + t.size()};
}

Eigen::MatrixXd fromRows(const std::vector<double>& v, hsize_t rows, hsize_t cols) {
    Eigen::MatrixXd out(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    for (hsize_t i = 0; i < rows; ++i)
        for (hsize_t j = 0; j < cols; ++j) out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = v[i * cols + j];
    return out;
}

Eigen::VectorXd vec(const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}
std::vector<double> std_(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }
}  // namespace

void writeBasis(hid_t loc, const PodBasis& b) {
    const auto r = static_cast<hsize_t>(b.weights.size()), k = static_cast<hsize_t>(b.modes.cols()),
               n = static_cast<hsize_t>(b.eigenvalues.size());
    h5::write(loc, "weights", {r}, std_(b.weights));
    h5::write(loc, "field_scales", {b.fieldScales.size()}, b.fieldScales);
    h5::write(loc, "mean", {r}, std_(b.mean));
    h5::write(loc, "modes", {k, r}, rowMajor(b.modes.transpose()));
    h5::write(loc, "eigenvalues", {n}, std_(b.eigenvalues));
    h5::write(loc, "coefficients", {n, k}, rowMajor(b.coefficients));
}

PodBasis readBasis(hid_t loc) {
    PodBasis b;
    b.weights = vec(h5::readDoubles(loc, "weights"));
    b.fieldScales = h5::readDoubles(loc, "field_scales");
    b.mean = vec(h5::readDoubles(loc, "mean"));
    b.eigenvalues = vec(h5::readDoubles(loc, "eigenvalues"));
    const auto ms = h5::shape(h5::openDataset(loc, "modes"));
    b.modes = fromRows(h5::readDoubles(loc, "modes"), ms[0], ms[1]).transpose();
    const auto cs = h5::shape(h5::openDataset(loc, "coefficients"));
    b.coefficients = fromRows(h5::readDoubles(loc, "coefficients"), cs[0], cs[1]);
    b.snapshots = static_cast<size_t>(b.eigenvalues.size());
    return b;
}

void writePod(const PodModel& m, const fs::path& file) {
    h5::writeFileAtomically(file, [&](hid_t f) {
        const auto& b = m.basis;
        store::writeFileHeader(f, kPodSchema, kPodSchemaVersion);
        h5::attr(f, "mesh_fingerprint", m.meshFingerprint);
        h5::attr(f, "fields", joined(m.fields));
        h5::attr(f, "cells", static_cast<long long>(m.cells));
        h5::attr(f, "snapshots", static_cast<long long>(b.snapshots));
        h5::attr(f, "sources", m.sources.dump());
        h5::attr(f, "energy_target", m.energyTarget);
        h5::attr(f, "energy_kept", b.keptEnergy());
        h5::attr(f, "subtract_mean", static_cast<long long>(b.mean.cwiseAbs().sum() > 0));
        h5::write(f, "components", std::vector<int32_t>(m.components.begin(), m.components.end()));
        writeBasis(f, b);
    });
}

PodModel readPod(const fs::path& file) {
    return namingFile(file, [&] {
        auto f = h5::openFile(file);
        std::map<std::string, h5::Attr> a;
        for (const auto& x : h5::attrs(f)) a[x.name] = x;
        if (!a.count("schema") || a["schema"].text != kPodSchema)
            throw std::runtime_error("not a mixload POD file (no schema = " + std::string(kPodSchema) + ")");
        if (static_cast<int>(a["schema_version"].number) != kPodSchemaVersion)
            throw std::runtime_error("POD schema version " + std::to_string(int(a["schema_version"].number)) +
                                     ", this mixload reads " + std::to_string(kPodSchemaVersion));
        PodModel m;
        std::stringstream fs_(a["fields"].text);
        for (std::string x; std::getline(fs_, x, ',');) m.fields.push_back(x);
        for (int32_t c : h5::readInts(f, "components")) m.components.push_back(c);
        m.cells = static_cast<size_t>(a["cells"].number);
        m.meshFingerprint = a["mesh_fingerprint"].text;
        m.sources = nlohmann::json::parse(a["sources"].text);
        m.energyTarget = a["energy_target"].number;
        for (const auto& [name, x] : a) m.provenance[name] = x.isString ? nlohmann::json(x.text) : nlohmann::json(x.number);
        m.basis = readBasis(f);
        return m;
    });
}

}  // namespace mixload::rom
