// SPDX-License-Identifier: GPL-3.0-or-later
#include "store/snapshot_file.hpp"

#include <algorithm>
#include <cstring>

#include "common/hash.hpp"
#include "common/input_error.hpp"
#include "store/ledger.hpp"
#include "store/xdmf.hpp"

namespace mixload::store {

namespace fs = std::filesystem;

std::string storedFieldName(const std::string& field) { return field == "alpha" ? "alpha.powder" : field; }

namespace {

nlohmann::json datasetJson(hid_t loc, const std::string& path, bool verify) {
    const auto d = h5::openDataset(loc, path);
    const h5::Handle type(H5Dget_type(d), H5Tclose);
    const size_t size = H5Tget_size(type);
    const char* kind = H5Tget_class(type) == H5T_INTEGER ? "int" : "float";
    hsize_t n = 1;
    const auto dims = h5::shape(d);
    for (auto x : dims) n *= x;
    if (verify) (void)h5::readDoubles(loc, path);
    return {{"path", path},
            {"shape", dims},
            {"type", std::string(kind) + std::to_string(8 * size)},
            {"raw_bytes", n * size},
            {"stored_bytes", H5Dget_storage_size(d)}};
}


}  // namespace

SnapshotFile::SnapshotFile(const fs::path& file) : CaseFile(file, kSnapshotSchema, 1, kSnapshotSchemaVersion) {
    namingFile(file, [&] {
        for (const char* need : {"/time", "/fields"})
            if (!h5::exists(file_, need)) throw std::runtime_error(std::string("missing ") + need);
        times_ = h5::readDoubles(file_, "time");
        return 0;
    });
}

std::vector<std::string> SnapshotFile::fields() const {
    return namingFile(path_, [&] {
        std::vector<std::string> out;
        for (const auto& m : h5::members(h5::openGroup(file_, "fields")))
            if (m != "cell_centres") out.push_back(m);
        return out;
    });
}

int SnapshotFile::components(const std::string& field) const {
    const std::string path = "/fields/" + storedFieldName(field);
    if (!h5::exists(file_, path)) throw InputError("field", field, "a field stored in " + path_.string());
    return namingFile(path_, [&] {
        const auto dims = h5::shape(h5::openDataset(file_, path));
        return dims.size() == 3 ? static_cast<int>(dims[2]) : 1;
    });
}

namespace {
Eigen::VectorXd rowOf(const h5::Handle& file, const fs::path& path, const std::string& dataset, size_t t,
                      size_t times, const std::string& what) {
    if (!h5::exists(file, dataset))
        throw InputError(what, dataset, "a dataset of " + path.string() + " (snapshots exported by mixload 2 or later)");
    if (t >= times) throw InputError("time index", std::to_string(t), "0.." + std::to_string(times - 1));
    return namingFile(path, [&] {
        const auto row = h5::readRow(file, dataset, t);
        return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(row.data(), static_cast<Eigen::Index>(row.size())));
    });
}
}  // namespace

Eigen::VectorXd SnapshotFile::column(const std::string& field, size_t timeIndex) const {
    (void)components(field);  // names the field if it is missing
    return rowOf(file_, path_, "/fields/" + storedFieldName(field), timeIndex, times_.size(), "field");
}

Eigen::VectorXd SnapshotFile::boundaryColumn(const std::string& field, size_t t) const {
    auto b = rowOf(file_, path_, "/boundary/" + storedFieldName(field), t, times_.size(), "boundary values");
    if (b.hasNaN())
        throw InputError("boundary values", field + " at t = " + std::to_string(times_[t]),
                         "a time whose field file holds every patch value (see the dataset's missing_times in " +
                             path_.string() + ")");
    return b;
}

Eigen::VectorXd SnapshotFile::faceColumn(const std::string& field, size_t t) const {
    return rowOf(file_, path_, "/faces/" + field, t, times_.size(), "face field");
}

bool SnapshotFile::hasFaceField(const std::string& field) const { return h5::exists(file_, "/faces/" + field); }

std::vector<double> SnapshotFile::cellCentres(size_t t) const {
    if (!h5::exists(file_, "/fields/cell_centres")) return meshDoubles("cell_centres");
    const Eigen::VectorXd c = rowOf(file_, path_, "/fields/cell_centres", t, times_.size(), "cell centres");
    return {c.data(), c.data() + c.size()};
}



Eigen::MatrixXd SnapshotFile::matrix(const std::string& field, const std::vector<size_t>& timeIndices) const {
    std::vector<size_t> idx = timeIndices;
    if (idx.empty())
        for (size_t t = 0; t < times_.size(); ++t) idx.push_back(t);
    Eigen::MatrixXd m(static_cast<Eigen::Index>(cells() * components(field)), static_cast<Eigen::Index>(idx.size()));
    for (size_t j = 0; j < idx.size(); ++j) m.col(static_cast<Eigen::Index>(j)) = column(field, idx[j]);
    return m;
}

nlohmann::json SnapshotFile::info(bool verify) const {
    return namingFile(path_, [&] {
        nlohmann::json j;
        j["file"] = fs::absolute(path_).string();
        j["bytes"] = fs::file_size(path_);
        j["provenance"] = provenance();
        j["params"] = params();
        j["times"] = {{"count", times_.size()},
                      {"first", times_.empty() ? 0.0 : times_.front()},
                      {"last", times_.empty() ? 0.0 : times_.back()}};
        j["cells"] = cells();
        j["faces"] = h5::shape(h5::openDataset(file_, "/mesh/owner"))[0];
        j["mesh_fingerprint"] = meshFingerprint();
        nlohmann::json ds = nlohmann::json::array();
        for (const char* g : {"mesh", "fields", "boundary", "faces", "history"}) {
            if (!h5::exists(file_, g)) continue;
            auto grp = h5::openGroup(file_, g);
            for (const auto& m : h5::members(grp)) {
                const std::string path = std::string("/") + g + "/" + m;
                H5O_info_t oi;
                if (H5Oget_info_by_name2(file_, path.c_str(), &oi, H5O_INFO_BASIC, H5P_DEFAULT) < 0 ||
                    oi.type != H5O_TYPE_DATASET)
                    continue;
                ds.push_back(datasetJson(file_, path, verify));
            }
        }
        ds.push_back(datasetJson(file_, "/time", verify));
        j["datasets"] = ds;
        j["verified"] = verify;
        return j;
    });
}

SnapshotSet::SnapshotSet(const std::vector<fs::path>& files) {
    if (files.empty()) throw InputError("snapshots", "(none)", "at least one snapshot file");
    for (const auto& f : files) {
        files_.emplace_back(f);
        const auto& s = files_.back();
        if (s.meshFingerprint() != files_.front().meshFingerprint())
            throw InputError("snapshots", f.string(),
                             "files of one mesh (" + std::to_string(s.cells()) + " cells here, " +
                                 std::to_string(files_.front().cells()) + " in " + files.front().string() +
                                 "; or the same count on other cells)");
        columns_ += s.times().size();
    }
}

std::vector<LedgerRun> campaignRunsWithSnapshots(const fs::path& ledger, const std::string& campaign) {
    std::vector<LedgerRun> out;
    for (auto& r : finishedCampaignRuns(ledger, campaign))
        if (fs::exists(fs::path(r.runDir) / "snapshots.h5")) out.push_back(std::move(r));
    if (out.empty())
        throw InputError("campaign", campaign, "a campaign whose finished runs kept snapshots (campaign run --snapshots)");
    return out;
}

std::vector<fs::path> campaignSnapshotFiles(const fs::path& ledger, const std::string& campaign) {
    std::vector<fs::path> out;
    for (const auto& r : campaignRunsWithSnapshots(ledger, campaign)) out.push_back(fs::path(r.runDir) / "snapshots.h5");
    return out;
}

void writeDerivedSnapshots(const CaseFile& source, const std::vector<double>& times,
                           const std::vector<std::pair<std::string, Eigen::MatrixXd>>& fields,
                           const nlohmann::json& provenance, const fs::path& file) {
    const auto nT = static_cast<hsize_t>(times.size()), nC = static_cast<hsize_t>(source.cells());
    if (nT == 0) throw InputError("fields", file.string(), "at least one time");
    std::vector<std::pair<std::string, int>> written;
    for (const auto& [name, m] : fields) {
        const int comps = m.rows() == static_cast<Eigen::Index>(nC) ? 1 : 3;
        if (m.rows() != comps * static_cast<Eigen::Index>(nC) || m.cols() != static_cast<Eigen::Index>(nT))
            throw std::invalid_argument("derived snapshots: field " + name + " does not fit the mesh and times");
        written.emplace_back(storedFieldName(name), comps);
    }
    h5::writeFileAtomically(file, [&](hid_t f) {
        writeFileHeader(f, kSnapshotSchema, 1);
        h5::attr(f, "field_precision", std::string("float64"));
        h5::attr(f, "mesh_moves", 0LL);
        for (const auto& [k, v] : provenance.items())
            if (v.is_number()) h5::attr(f, k, v.get<double>());
            else h5::attr(f, k, v.is_string() ? v.get<std::string>() : v.dump());
        source.copyCaseTo(f);
        h5::write(f, "time", {nT}, times);
        auto g = h5::createGroup(f, "fields");
        for (size_t k = 0; k < fields.size(); ++k) {
            const auto& m = fields[k].second;
            const int comps = written[k].second;
            auto d = h5::createDataset(g, written[k].first, comps == 1 ? std::vector<hsize_t>{nT, nC} : std::vector<hsize_t>{nT, nC, 3},
                                       h5::Stored::Float64, true);
            for (hsize_t i = 0; i < nT; ++i) {
                const Eigen::VectorXd col = m.col(static_cast<Eigen::Index>(i));
                h5::writeRow(d, i, std::vector<double>(col.data(), col.data() + col.size()));
            }
        }
    });
    fs::path xdmf = file;
    xdmf.replace_extension(".xmf");
    writeXdmf(xdmf, file.filename().string(), times, static_cast<int32_t>(nC), written, true, false);
}

}  // namespace mixload::store
