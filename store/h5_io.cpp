// SPDX-License-Identifier: GPL-3.0-or-later
#include "store/h5_io.hpp"

#include "common/atomic_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace mixload::h5 {

namespace {

// HDF5 prints its error stack to stderr by default; mixload reports one clear line instead.
const bool kQuiet = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
}();

hid_t check(hid_t id, const std::string& what) {
    (void)kQuiet;
    if (id < 0) throw std::runtime_error("HDF5: cannot " + what);
    return id;
}
void check(herr_t e, const std::string& what, int) {
    if (e < 0) throw std::runtime_error("HDF5: cannot " + what);
}

hid_t memType(Stored t) {
    return t == Stored::Int32 ? H5T_NATIVE_INT32 : H5T_NATIVE_DOUBLE;
}
hid_t fileType(Stored t) {
    switch (t) {
        case Stored::Float32: return H5T_IEEE_F32LE;
        case Stored::Float64: return H5T_IEEE_F64LE;
        case Stored::Int32: return H5T_STD_I32LE;
    }
    return H5T_IEEE_F64LE;
}

Handle space(const std::vector<hsize_t>& dims) {
    return {check(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                  "create a dataspace"),
            H5Sclose};
}

}  // namespace

Handle createFile(const std::filesystem::path& path) {
    // The 1.8 format at least: its object headers move an attribute above 64 KiB (a campaign's
    // kept progress with its monitors' histories) to dense storage, where the default refuses it.
    Handle fapl(check(H5Pcreate(H5P_FILE_ACCESS), "create a file access property list"), H5Pclose);
    check(H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_LATEST), "set the file format bounds", 0);
    return {check(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), "create " + path.string()),
            H5Fclose};
}

Handle openFile(const std::filesystem::path& path) {
    (void)kQuiet;
    if (!std::filesystem::is_regular_file(path))
        throw std::runtime_error(path.string() + ": no such file");
    const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (id < 0)
        throw std::runtime_error(path.string() +
                                 ": not a readable HDF5 file (truncated or corrupt)");
    return {id, H5Fclose};
}

Handle createGroup(hid_t loc, const std::string& name) {
    return {check(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  "create group " + name),
            H5Gclose};
}

Handle openGroup(hid_t loc, const std::string& name) {
    return {check(H5Gopen2(loc, name.c_str(), H5P_DEFAULT), "open group " + name), H5Gclose};
}

Handle openDataset(hid_t loc, const std::string& name) {
    return {check(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), "open dataset " + name), H5Dclose};
}

bool exists(hid_t loc, const std::string& path) {
    // Each link of the path must exist before the next one may be asked about.
    size_t pos = path[0] == '/' ? 1 : 0;
    for (;;) {
        const auto slash = path.find('/', pos);
        const std::string prefix = path.substr(0, slash);
        if (H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
        if (slash == std::string::npos) return true;
        pos = slash + 1;
    }
}

Handle createDataset(hid_t loc, const std::string& name, const std::vector<hsize_t>& dims,
                     Stored type, bool perRow) {
    const auto sp = space(dims);
    Handle plist(check(H5Pcreate(H5P_DATASET_CREATE), "create a property list"), H5Pclose);
    std::vector<hsize_t> chunk = dims;
    hsize_t rowElems = 1;
    for (size_t i = 1; i < dims.size(); ++i) rowElems *= std::max<hsize_t>(dims[i], 1);
    // Time series: one chunk per row, so a snapshot is read or written whole. Anything else: chunks
    // of about a million values (small chunks cost more in overhead than deflate saves).
    chunk[0] = perRow ? 1 : std::clamp<hsize_t>((1u << 20) / rowElems, 1, std::max<hsize_t>(dims[0], 1));
    for (auto& c : chunk) c = std::max<hsize_t>(c, 1);
    check(H5Pset_chunk(plist, static_cast<int>(chunk.size()), chunk.data()), "chunk " + name, 0);
    check(H5Pset_fletcher32(plist), "checksum " + name, 0);
    check(H5Pset_shuffle(plist), "shuffle " + name, 0);
    check(H5Pset_deflate(plist, 4), "compress " + name, 0);
    return {check(H5Dcreate2(loc, name.c_str(), fileType(type), sp, H5P_DEFAULT, plist, H5P_DEFAULT),
                  "create dataset " + name),
            H5Dclose};
}

std::vector<hsize_t> shape(hid_t dataset) {
    Handle sp(check(H5Dget_space(dataset), "get a dataspace"), H5Sclose);
    const int rank = H5Sget_simple_extent_ndims(sp);
    std::vector<hsize_t> dims(static_cast<size_t>(std::max(rank, 0)));
    H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
    return dims;
}

namespace {
// The file space of one row of the first dimension, and the row's length.
Handle selectRow(hid_t dataset, hsize_t row, hsize_t& n) {
    const auto dims = shape(dataset);
    if (dims.empty() || row >= dims[0])
        throw std::runtime_error("HDF5: row " + std::to_string(row) + " outside the dataset");
    Handle fs(check(H5Dget_space(dataset), "get a dataspace"), H5Sclose);
    std::vector<hsize_t> start(dims.size(), 0), count = dims;
    start[0] = row;
    count[0] = 1;
    check(H5Sselect_hyperslab(fs, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
          "select a row", 0);
    n = 1;
    for (size_t i = 1; i < dims.size(); ++i) n *= dims[i];
    return fs;
}
}  // namespace

void writeRow(hid_t dataset, hsize_t row, const std::vector<double>& values) {
    hsize_t n = 0;
    const auto fs = selectRow(dataset, row, n);
    if (values.size() != n) throw std::runtime_error("HDF5: row of the wrong size");
    const auto ms = space({n});
    check(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, values.data()), "write a row", 0);
}

void write(hid_t loc, const std::string& name, const std::vector<hsize_t>& dims,
           const std::vector<double>& values, Stored type) {
    const auto d = createDataset(loc, name, dims, type, false);
    check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          "write " + name, 0);
}

void write(hid_t loc, const std::string& name, const std::vector<int32_t>& values) {
    const auto d = createDataset(loc, name, {values.size()}, Stored::Int32, false);
    check(H5Dwrite(d, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          "write " + name, 0);
}

namespace {
template <class T>
std::vector<T> readAll(hid_t loc, const std::string& name, hid_t mem) {
    const auto d = openDataset(loc, name);
    hsize_t n = 1;
    for (auto x : shape(d)) n *= x;
    std::vector<T> out(n);
    // A checksum mismatch (fletcher32) or a short file fails here rather than returning garbage.
    if (n > 0 && H5Dread(d, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
        throw std::runtime_error("HDF5: dataset " + name +
                                 " cannot be read (checksum mismatch: corrupt or truncated file)");
    return out;
}
}  // namespace

std::vector<double> readDoubles(hid_t loc, const std::string& name) {
    return readAll<double>(loc, name, H5T_NATIVE_DOUBLE);
}
std::vector<int32_t> readInts(hid_t loc, const std::string& name) {
    return readAll<int32_t>(loc, name, H5T_NATIVE_INT32);
}

std::vector<double> readRow(hid_t loc, const std::string& name, hsize_t row) {
    const auto d = openDataset(loc, name);
    hsize_t n = 0;
    const auto fs = selectRow(d, row, n);
    std::vector<double> out(n);
    const auto ms = space({n});
    if (H5Dread(d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, out.data()) < 0)
        throw std::runtime_error("HDF5: row " + std::to_string(row) + " of " + name +
                                 " cannot be read (checksum mismatch: corrupt or truncated file)");
    return out;
}

void attr(hid_t obj, const std::string& name, const std::string& value) {
    Handle type(check(H5Tcopy(H5T_C_S1), "copy a string type"), H5Tclose);
    H5Tset_size(type, std::max<size_t>(value.size(), 1));
    H5Tset_cset(type, H5T_CSET_UTF8);
    Handle sp(check(H5Screate(H5S_SCALAR), "create a scalar space"), H5Sclose);
    Handle a(check(H5Acreate2(obj, name.c_str(), type, sp, H5P_DEFAULT, H5P_DEFAULT),
                   "create attribute " + name),
             H5Aclose);
    const std::string padded = value.empty() ? std::string(1, '\0') : value;
    check(H5Awrite(a, type, padded.data()), "write attribute " + name, 0);
}

void attr(hid_t obj, const std::string& name, double value) {
    Handle sp(check(H5Screate(H5S_SCALAR), "create a scalar space"), H5Sclose);
    Handle a(check(H5Acreate2(obj, name.c_str(), H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT),
                   "create attribute " + name),
             H5Aclose);
    check(H5Awrite(a, H5T_NATIVE_DOUBLE, &value), "write attribute " + name, 0);
}

void attr(hid_t obj, const std::string& name, long long value) {
    Handle sp(check(H5Screate(H5S_SCALAR), "create a scalar space"), H5Sclose);
    Handle a(check(H5Acreate2(obj, name.c_str(), H5T_STD_I64LE, sp, H5P_DEFAULT, H5P_DEFAULT),
                   "create attribute " + name),
             H5Aclose);
    check(H5Awrite(a, H5T_NATIVE_LLONG, &value), "write attribute " + name, 0);
}

std::vector<Attr> attrs(hid_t obj) {
    std::vector<Attr> out;
    H5O_info_t info;
    check(H5Oget_info2(obj, &info, H5O_INFO_NUM_ATTRS), "read object info", 0);
    for (hsize_t i = 0; i < info.num_attrs; ++i) {
        Handle a(check(H5Aopen_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT,
                                      H5P_DEFAULT),
                       "open an attribute"),
                 H5Aclose);
        Attr r;
        const ssize_t len = H5Aget_name(a, 0, nullptr);
        r.name.resize(static_cast<size_t>(std::max<ssize_t>(len, 0)));
        H5Aget_name(a, r.name.size() + 1, r.name.data());
        Handle type(check(H5Aget_type(a), "read an attribute type"), H5Tclose);
        if (H5Tget_class(type) == H5T_STRING) {
            r.isString = true;
            r.text.resize(H5Tget_size(type));
            Handle mem(check(H5Tcopy(type), "copy a string type"), H5Tclose);
            check(H5Aread(a, mem, r.text.data()), "read attribute " + r.name, 0);
            r.text.resize(std::strlen(r.text.c_str()));
        } else {
            check(H5Aread(a, H5T_NATIVE_DOUBLE, &r.number), "read attribute " + r.name, 0);
        }
        out.push_back(r);
    }
    return out;
}

void writeFileAtomically(const std::filesystem::path& path, const std::function<void(hid_t)>& fill) {
    const auto tmp = atomicTempPath(path);
    if (!path.parent_path().empty()) std::filesystem::create_directories(path.parent_path());
    try {
        {
            auto f = createFile(tmp);
            fill(f);
            H5Fflush(f, H5F_SCOPE_GLOBAL);
        }
        commitAtomic(tmp, path);
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw;
    }
}

std::vector<std::string> members(hid_t group) {
    H5G_info_t info;
    if (H5Gget_info(group, &info) < 0) throw std::runtime_error("HDF5: cannot list a group");
    std::vector<std::string> out;
    for (hsize_t i = 0; i < info.nlinks; ++i) {
        const ssize_t len = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0,
                                               H5P_DEFAULT);
        std::string name(static_cast<size_t>(std::max<ssize_t>(len, 0)), '\0');
        H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1,
                           H5P_DEFAULT);
        out.push_back(name);
    }
    return out;
}

nlohmann::json attrsJson(hid_t obj) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& a : h5::attrs(obj)) j[a.name] = a.isString ? nlohmann::json(a.text) : nlohmann::json(a.number);
    return j;
}

}  // namespace mixload::h5
