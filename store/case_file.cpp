// SPDX-License-Identifier: GPL-3.0-or-later
#include "store/case_file.hpp"

#include <algorithm>

#include "common/clock.hpp"
#include "common/hash.hpp"
#include "common/input_error.hpp"
#include "mixload_version.hpp"

namespace mixload::store {

namespace fs = std::filesystem;

namespace {
std::string bytesOf(const std::vector<double>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
}
std::string bytesOf(const std::vector<int32_t>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(int32_t));
}
}  // namespace

void writeFileHeader(hid_t file, const std::string& schema, int version) {
    h5::attr(file, "schema", schema);
    h5::attr(file, "schema_version", static_cast<long long>(version));
    h5::attr(file, "mixload_version", std::string(kVersion));
    h5::attr(file, "git_commit", std::string(kGitCommit));
    h5::attr(file, "created_utc", utcNow());
}

CaseFile::CaseFile(const fs::path& file, const std::string& schema, int minVersion, int maxVersion) : path_(file) {
    namingFile(file, [&] {
        file_ = h5::openFile(file);
        const auto a = h5::attrsJson(file_);
        if (a.value("schema", std::string()) != schema)
            throw std::runtime_error("not a " + schema + " file (no schema = " + schema + ")");
        version_ = static_cast<int>(a.value("schema_version", 0.0));
        if (version_ < minVersion || version_ > maxVersion)
            throw std::runtime_error(schema + " schema version " + std::to_string(version_) + ", this mixload reads " +
                                     std::to_string(minVersion) + " to " + std::to_string(maxVersion));
        for (const char* need : {"/mesh/cell_volumes", "/mesh/owner", "/params"})
            if (!h5::exists(file_, need)) throw std::runtime_error(std::string("missing ") + need);
        const auto vol = h5::readDoubles(file_, "/mesh/cell_volumes");
        volumes_ = Eigen::Map<const Eigen::VectorXd>(vol.data(), static_cast<Eigen::Index>(vol.size()));
        std::string key = bytesOf(vol) + bytesOf(h5::readInts(file_, "/mesh/owner"));
        if (h5::exists(file_, "/mesh/neighbour")) key += bytesOf(h5::readInts(file_, "/mesh/neighbour"));
        fingerprint_ = stableHash(key);
        return 0;
    });
}

nlohmann::json CaseFile::provenance() const { return h5::attrsJson(file_); }

nlohmann::json CaseFile::params() const {
    return namingFile(path_, [&] {
        auto p = h5::attrsJson(h5::openGroup(file_, "params"));
        p.erase("scene_json");
        return p;
    });
}

nlohmann::json CaseFile::powderTransport() const {
    if (!h5::exists(file_, "/params/powder_transport"))
        throw InputError("powder transport", path_.string(), "a snapshot file exported by this mixload (re-export the run)");
    return namingFile(path_, [&] { return h5::attrsJson(h5::openGroup(file_, "/params/powder_transport")); });
}

std::vector<CaseFile::Patch> CaseFile::patches() const {
    return namingFile(path_, [&] {
        std::vector<Patch> out;
        const auto g = h5::openGroup(file_, "/mesh/patches");
        for (const auto& name : h5::members(g)) {
            Patch p;
            p.name = name;
            for (const auto& a : h5::attrs(h5::openGroup(g, name))) {
                if (a.name == "type") p.type = a.text;
                else if (a.name == "start_face") p.start = static_cast<long long>(a.number);
                else if (a.name == "n_faces") p.size = static_cast<long long>(a.number);
            }
            out.push_back(p);
        }
        // Groups list by name; operators need the mesh's face order.
        std::sort(out.begin(), out.end(), [](const Patch& a, const Patch& b) { return a.start < b.start; });
        return out;
    });
}

std::vector<CaseFile::MrfZone> CaseFile::mrfZones() const {
    return namingFile(path_, [&] {
        std::vector<MrfZone> out;
        if (!h5::exists(file_, "/mesh/mrf")) return out;
        const auto g = h5::openGroup(file_, "/mesh/mrf");
        for (const auto& name : h5::members(g)) {
            const auto attrs = h5::attrsJson(h5::openGroup(g, name));
            MrfZone z;
            z.name = name;
            z.omega = attrs.at("omega_rad_s").get<double>();
            z.cells = h5::readInts(file_, "/mesh/zones/" + attrs.at("cell_zone").get<std::string>());
            const auto o = h5::readDoubles(g, name + "/origin"), a = h5::readDoubles(g, name + "/axis");
            z.origin = Eigen::Vector3d(o.at(0), o.at(1), o.at(2));
            z.axis = Eigen::Vector3d(a.at(0), a.at(1), a.at(2)).normalized();
            out.push_back(std::move(z));
        }
        return out;
    });
}

std::vector<double> CaseFile::meshDoubles(const std::string& name) const {
    return namingFile(path_, [&] { return h5::readDoubles(file_, "/mesh/" + name); });
}

std::vector<int32_t> CaseFile::meshInts(const std::string& name) const {
    return namingFile(path_, [&] { return h5::readInts(file_, "/mesh/" + name); });
}

void CaseFile::copyCaseTo(hid_t to) const {
    namingFile(path_, [&] {
        for (const char* g : {"mesh", "params"})
            if (H5Ocopy(file_, g, to, g, H5P_DEFAULT, H5P_DEFAULT) < 0)
                throw std::runtime_error(std::string("HDF5: cannot copy /") + g);
        return 0;
    });
}

}  // namespace mixload::store
