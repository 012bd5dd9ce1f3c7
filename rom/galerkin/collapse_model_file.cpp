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
            {"alpha_modes", o.alphaModes}, {"alpha_energy", o.alphaEnergy}, {"train_every", o.trainEvery},
            {"hyper_points", o.hyperPoints}, {"hyper_method", o.hyperMethod == HyperMethod::deim ? "deim" : "ecsw"},
            {"hyper_tolerance", o.hyperTolerance}, {"hyper_convection", o.hyperConvection}};
}

std::vector<double> rowMajor(const Eigen::MatrixXd& m) {  // m's columns become rows
    return {m.data(), m.data() + m.size()};
}

void writeMatrix(hid_t g, const std::string& name, const Eigen::MatrixXd& m) {
    h5::write(g, name, {static_cast<hsize_t>(m.cols()), static_cast<hsize_t>(m.rows())}, rowMajor(m));
}

Eigen::MatrixXd readMatrix(hid_t g, const std::string& name) {
    const auto shape = h5::shape(h5::openDataset(g, name));
    const auto v = h5::readDoubles(g, name);
    return Eigen::Map<const Eigen::MatrixXd>(v.data(), static_cast<Eigen::Index>(shape[1]), static_cast<Eigen::Index>(shape[0]));
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
        writeMatrix(f, "cell_velocity", m.cellU);
        if (m.alpha) {
            writeBasis(h5::createGroup(f, "alpha"), *m.alpha);
            h5::write(f, "alpha_lift", {static_cast<hsize_t>(m.alphaLift.size())},
                      std::vector<double>(m.alphaLift.data(), m.alphaLift.data() + m.alphaLift.size()));
        }
        if (m.hyper) {
            const auto g = h5::createGroup(f, "hyper");
            writeMatrix(g, "to_coefficients", m.hyper->toCoefficients);
            writeMatrix(g, "grad_at_points", m.hyper->gradAtPoints);
            writeMatrix(g, "viscous", m.hyper->viscous);
            h5::write(g, "points", std::vector<int32_t>(m.hyper->points.begin(), m.hyper->points.end()));
            h5::attr(g, "training_error", m.hyper->trainingError);
        }
        if (m.convectionHyper) {
            const auto& c = *m.convectionHyper;
            const auto g = h5::createGroup(f, "hyper_convection");
            h5::write(g, "cells", std::vector<int32_t>(c.cells.begin(), c.cells.end()));
            h5::write(g, "face_start", std::vector<int32_t>(c.faceStart.begin(), c.faceStart.end()));
            writeMatrix(g, "face_flux", c.faceFlux);
            writeMatrix(g, "face_velocity", c.faceVelocity);
            writeMatrix(g, "project", c.project);
            h5::attr(g, "training_error", c.trainingError);
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
        m.options.hyperPoints = o.value("hyper_points", 0);
        m.options.hyperMethod = o.value("hyper_method", "ecsw") == "deim" ? HyperMethod::deim : HyperMethod::ecsw;
        m.options.hyperTolerance = o.value("hyper_tolerance", 0.01);
        m.options.hyperConvection = o.value("hyper_convection", false);
        m.cellU = readMatrix(f.handle(), "cell_velocity");
        if (m.flow.modes.rows() != m.mesh.faces() || m.cellU.rows() != 3 * m.mesh.cells || m.cellU.cols() != m.flow.modes.cols())
            throw std::runtime_error("its bases do not fit its mesh");
        if (m.options.reducedAlpha) {
            m.alpha = readBasis(h5::openGroup(f.handle(), "alpha"));
            const auto lift = h5::readDoubles(f.handle(), "alpha_lift");
            m.alphaLift = Eigen::Map<const Eigen::VectorXd>(lift.data(), static_cast<Eigen::Index>(lift.size()));
        }
        if (m.options.hyperPoints > 0) {
            const auto g = h5::openGroup(f.handle(), "hyper");
            ViscousHyper h;
            h.method = m.options.hyperMethod;
            h.toCoefficients = readMatrix(g, "to_coefficients");
            h.gradAtPoints = readMatrix(g, "grad_at_points");
            h.viscous = readMatrix(g, "viscous");
            for (const auto p : h5::readInts(g, "points")) h.points.push_back(p);
            h.trainingError = h5::attrsJson(g).at("training_error");
            const auto P = static_cast<Eigen::Index>(h.points.size()), K = m.flow.modes.cols();
            if (P < 1 || h.toCoefficients.rows() != P || h.toCoefficients.cols() != P || h.gradAtPoints.rows() != 9 * P ||
                h.gradAtPoints.cols() != K || h.viscous.rows() != K * K || h.viscous.cols() != P)
                throw std::runtime_error("its hyper-reduction does not fit its modes");
            for (const auto p : h.points)
                if (p < 0 || p >= m.mesh.cells) throw std::runtime_error("its hyper-reduction names a cell outside its mesh");
            m.hyper = std::move(h);
        }
        if (m.options.hyperConvection) {
            const auto g = h5::openGroup(f.handle(), "hyper_convection");
            ConvectionHyper c;
            for (const auto i : h5::readInts(g, "cells")) c.cells.push_back(i);
            for (const auto i : h5::readInts(g, "face_start")) c.faceStart.push_back(i);
            c.faceFlux = readMatrix(g, "face_flux");
            c.faceVelocity = readMatrix(g, "face_velocity");
            c.project = readMatrix(g, "project");
            c.trainingError = h5::attrsJson(g).at("training_error");
            const auto E = static_cast<Eigen::Index>(c.cells.size()), K = m.flow.modes.cols();
            const Eigen::Index F = c.faceStart.empty() ? -1 : c.faceStart.back();
            if (E < 1 || static_cast<Eigen::Index>(c.faceStart.size()) != E + 1 || c.faceFlux.rows() != F || c.faceFlux.cols() != K ||
                c.faceVelocity.rows() != 3 * F || c.faceVelocity.cols() != K || c.project.rows() != K || c.project.cols() != 3 * E)
                throw std::runtime_error("its hyper-reduced convection does not fit its modes");
            for (const auto i : c.cells)
                if (i < 0 || i >= m.mesh.cells) throw std::runtime_error("its hyper-reduced convection names a cell outside its mesh");
            m.convectionHyper = std::move(c);
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
