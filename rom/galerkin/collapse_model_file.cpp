// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/collapse_model_file.hpp"

#include "common/input_error.hpp"
#include "rom/pod/pod_model.hpp"
#include "store/h5_io.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::rom {

namespace fs = std::filesystem;

namespace {
// A model file is a case file: the reader reaches its datasets through the open handle.
class ModelFile : public store::CaseFile {
  public:
    explicit ModelFile(const fs::path& f) : CaseFile(f, kCollapseModelSchema, 1, kCollapseModelSchemaVersion) {}
    hid_t handle() const { return file_; }
};

nlohmann::json buildOptions(const CollapseGalerkinOptions& o) {
    return {{"modes", o.modes},           {"energy", o.energy},         {"reduced_alpha", o.reducedAlpha},
            {"alpha_modes", o.alphaModes}, {"alpha_energy", o.alphaEnergy}, {"train_every", o.trainEvery}};
}

std::vector<double> rowMajor(const Eigen::MatrixXd& m) {  // m's columns become rows
    return {m.data(), m.data() + m.size()};
}
}  // namespace

void writeCollapseModel(const CollapseGalerkin& m, const store::CaseFile& source, const fs::path& file) {
    h5::writeFileAtomically(file, [&](hid_t f) {
        store::writeFileHeader(f, kCollapseModelSchema, kCollapseModelSchemaVersion);
        h5::attr(f, "mesh_fingerprint", m.meshFingerprint);
        h5::attr(f, "options", buildOptions(m.options).dump());
        h5::attr(f, "sources", m.sources.dump());
        h5::attr(f, "train_times", static_cast<long long>(m.trainTimes));
        h5::attr(f, "build_seconds", m.buildSeconds);
        source.copyCaseTo(f);
        writeBasis(h5::createGroup(f, "flow"), m.flow);
        const auto k = static_cast<hsize_t>(m.cellU.cols()), r = static_cast<hsize_t>(m.cellU.rows());
        h5::write(f, "cell_velocity", {k, r}, rowMajor(m.cellU));
        if (m.alpha) {
            writeBasis(h5::createGroup(f, "alpha"), *m.alpha);
            h5::write(f, "alpha_lift", {static_cast<hsize_t>(m.alphaLift.size())},
                      std::vector<double>(m.alphaLift.data(), m.alphaLift.data() + m.alphaLift.size()));
        }
    });
}

CollapseGalerkin readCollapseModel(const fs::path& file) {
    const ModelFile f(file);
    CollapseGalerkin m = CollapseGalerkin::fromCase(f);
    return namingFile(file, [&] {
        const auto a = h5::attrsJson(f.handle());
        m.meshFingerprint = f.meshFingerprint();
        if (a.value("mesh_fingerprint", std::string()) != m.meshFingerprint)
            throw std::runtime_error("its mesh is not the one it was built on");
        const auto o = nlohmann::json::parse(a.at("options").get<std::string>());
        m.options.modes = o.at("modes");
        m.options.energy = o.at("energy");
        m.options.reducedAlpha = o.at("reduced_alpha");
        m.options.alphaModes = o.at("alpha_modes");
        m.options.alphaEnergy = o.at("alpha_energy");
        m.options.trainEvery = o.at("train_every");
        m.sources = nlohmann::json::parse(a.at("sources").get<std::string>());
        for (const auto& s : m.sources) m.trainFiles.push_back(s.at("file"));
        m.trainTimes = static_cast<size_t>(a.at("train_times").get<double>());
        m.buildSeconds = a.at("build_seconds");
        m.flow = readBasis(h5::openGroup(f.handle(), "flow"));
        const auto shape = h5::shape(h5::openDataset(f.handle(), "cell_velocity"));
        const auto v = h5::readDoubles(f.handle(), "cell_velocity");
        m.cellU = Eigen::Map<const Eigen::MatrixXd>(v.data(), static_cast<Eigen::Index>(shape[1]),
                                                    static_cast<Eigen::Index>(shape[0]));
        if (m.flow.modes.rows() != m.mesh.faces() || m.cellU.rows() != 3 * m.mesh.cells || m.cellU.cols() != m.flow.modes.cols())
            throw std::runtime_error("its bases do not fit its mesh");
        if (m.options.reducedAlpha) {
            m.alpha = readBasis(h5::openGroup(f.handle(), "alpha"));
            const auto lift = h5::readDoubles(f.handle(), "alpha_lift");
            m.alphaLift = Eigen::Map<const Eigen::VectorXd>(lift.data(), static_cast<Eigen::Index>(lift.size()));
        }
        return m;
    });
}

void writeCollapseFields(const CollapseGalerkin& m, const fs::path& modelFile, const CollapseTrajectory& tr,
                         const fs::path& file) {
    const ModelFile source(modelFile);
    const auto nT = static_cast<Eigen::Index>(tr.times.size());
    Eigen::MatrixXd alpha(m.mesh.cells, nT), U(3 * m.mesh.cells, nT);
    for (Eigen::Index i = 0; i < nT; ++i) {
        alpha.col(i) = tr.alpha[static_cast<size_t>(i)];
        U.col(i) = m.cellU * tr.flow[static_cast<size_t>(i)];
    }
    store::writeDerivedSnapshots(source, tr.times, {{"alpha", alpha}, {"U", U}},
                                 {{"written_by", "mixload rom run (POD-Galerkin collapse model)"},
                                  {"model", fs::absolute(modelFile).string()},
                                  {"scene_kind", source.params().value("scene", std::string())},
                                  {"scene_hash", "none (reduced model)"},
                                  {"openfoam_version", "none (reduced model)"}},
                                 file);
}

}  // namespace mixload::rom
