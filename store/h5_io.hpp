// SPDX-License-Identifier: GPL-3.0-or-later
// The few HDF5 operations snapshots need, over the C API with handles that close themselves.
// Every failure becomes a std::runtime_error naming the object, never a printed HDF5 error stack.
#pragma once
#include <functional>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <hdf5.h>

namespace mixload::h5 {

class Handle {
public:
    Handle() = default;
    Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
    Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
    Handle& operator=(Handle&& o) noexcept {
        std::swap(id_, o.id_);
        std::swap(close_, o.close_);
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle() {
        if (id_ >= 0 && close_) close_(id_);
    }
    hid_t get() const { return id_; }
    operator hid_t() const { return id_; }

private:
    hid_t id_ = -1;
    herr_t (*close_)(hid_t) = nullptr;
};

Handle createFile(const std::filesystem::path& path);
// Throws with "truncated or corrupt" in the message when the file cannot be opened.
Handle openFile(const std::filesystem::path& path);
// Writes a whole file under a temporary name (fill gets the open file) and renames it into place,
// so a file under its final name is complete; on any error the temporary file is removed.
void writeFileAtomically(const std::filesystem::path& path, const std::function<void(hid_t file)>& fill);
Handle createGroup(hid_t loc, const std::string& name);
Handle openGroup(hid_t loc, const std::string& name);
Handle openDataset(hid_t loc, const std::string& name);
bool exists(hid_t loc, const std::string& path);

enum class Stored { Float32, Float64, Int32 };

// A chunked, shuffled, deflated, checksummed (fletcher32) dataset; perRow: one chunk per row of
// the first dimension (time series).
Handle createDataset(hid_t loc, const std::string& name, const std::vector<hsize_t>& dims, Stored type,
                     bool perRow);
void writeRow(hid_t dataset, hsize_t row, const std::vector<double>& values);
// Whole datasets in one call.
void write(hid_t loc, const std::string& name, const std::vector<hsize_t>& dims,
           const std::vector<double>& values, Stored type = Stored::Float64);
void write(hid_t loc, const std::string& name, const std::vector<int32_t>& values);

std::vector<hsize_t> shape(hid_t dataset);
std::vector<double> readDoubles(hid_t loc, const std::string& name);
std::vector<double> readRow(hid_t loc, const std::string& name, hsize_t row);
std::vector<int32_t> readInts(hid_t loc, const std::string& name);

void attr(hid_t obj, const std::string& name, const std::string& value);
void attr(hid_t obj, const std::string& name, double value);
void attr(hid_t obj, const std::string& name, long long value);

// Attributes of an object as name -> number | string.
struct Attr {
    std::string name;
    bool isString = false;
    std::string text;
    double number = 0;
};
std::vector<Attr> attrs(hid_t obj);
// A group's members by name, and an object's attributes as JSON (numbers and strings).
std::vector<std::string> members(hid_t group);
nlohmann::json attrsJson(hid_t obj);

}  // namespace mixload::h5
