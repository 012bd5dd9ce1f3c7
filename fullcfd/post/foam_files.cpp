// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/foam_files.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <regex>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"

namespace mixload::post {

namespace fs = std::filesystem;

namespace {

// One OpenFOAM file in memory with a cursor; every error names the file and the byte offset.
class FoamReader {
public:
    explicit FoamReader(const fs::path& file) : file_(file), s_(readFile(file)) {
        const auto h = s_.find("FoamFile");
        const auto open = h == std::string::npos ? h : s_.find('{', h);
        const auto close = open == std::string::npos ? open : s_.find('}', open);
        if (close == std::string::npos) fail("no FoamFile header");
        const std::string header = s_.substr(open, close - open);
        binary_ = entry(header, "format") == "binary";
        klass_ = entry(header, "class");
        const std::string arch = entry(header, "arch");
        if (binary_ && !arch.empty() && arch.find("label=32") == std::string::npos)
            fail("binary file with arch " + arch + " (mixload reads label=32;scalar=64)");
        if (binary_ && !arch.empty() && arch.find("scalar=64") == std::string::npos)
            fail("binary file with arch " + arch + " (mixload reads label=32;scalar=64)");
        pos_ = close + 1;
    }

    const std::string& klass() const { return klass_; }
    bool binary() const { return binary_; }

    [[noreturn]] void fail(const std::string& what) const {
        throw std::runtime_error(file_.string() + ": " + what + " (at byte " +
                                 std::to_string(pos_) + ")");
    }

    void skipSpace() {
        for (;;) {
            while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
            if (s_.compare(pos_, 2, "//") == 0) {
                pos_ = s_.find('\n', pos_);
                if (pos_ == std::string::npos) pos_ = s_.size();
            } else if (s_.compare(pos_, 2, "/*") == 0) {
                const auto e = s_.find("*/", pos_ + 2);
                pos_ = e == std::string::npos ? s_.size() : e + 2;
            } else {
                return;
            }
        }
    }

    char peek() {
        skipSpace();
        if (pos_ >= s_.size()) fail("unexpected end of file");
        return s_[pos_];
    }
    void expect(char c) {
        if (peek() != c) fail(std::string("expected '") + c + "'");
        ++pos_;
    }
    std::string word() {
        skipSpace();
        const auto b = pos_;
        while (pos_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[pos_])) &&
               !std::strchr("(){};", s_[pos_]))
            ++pos_;
        if (b == pos_) fail("expected a word");
        return s_.substr(b, pos_ - b);
    }
    template <class T>
    T number() {
        skipSpace();
        T v{};
        const auto [p, ec] = std::from_chars(s_.data() + pos_, s_.data() + s_.size(), v);
        if (ec != std::errc()) fail("expected a number");
        pos_ = static_cast<size_t>(p - s_.data());
        return v;
    }
    // Moves the cursor past the keyword at the start of a line-level entry.
    void seekKeyword(const std::string& key) {
        const std::regex re("(^|[\\s;}])" + key + "\\s");
        std::smatch m;
        const std::string::const_iterator from = s_.begin() + static_cast<long>(pos_);
        if (!std::regex_search(from, s_.cend(), m, re)) fail("no '" + key + "' entry");
        pos_ = static_cast<size_t>(m[0].second - s_.cbegin());
    }

    // "N(...)" or "N{value}" of T, where T is a scalar type or an array of them (vectors).
    template <class S, size_t K>
    std::vector<S> list() {
        const auto n = number<long long>();
        if (n < 0) fail("negative list size");
        std::vector<S> out(static_cast<size_t>(n) * K);
        const char c = peek();
        if (n == 0 && c != '(' && c != '{') return out;  // binary files write an empty list as "0"
        if (c == '{') {  // all elements equal
            ++pos_;
            const auto one = element<S, K>();
            for (size_t i = 0; i < out.size(); i += K) std::copy(one.begin(), one.end(), out.begin() + i);
            expect('}');
            return out;
        }
        expect('(');
        if (binary_) {
            const size_t bytes = out.size() * sizeof(S);
            if (pos_ + bytes > s_.size()) fail("binary list runs past the end of the file");
            std::memcpy(out.data(), s_.data() + pos_, bytes);
            pos_ += bytes;
        } else {
            for (size_t i = 0; i < out.size(); i += K) {
                const auto e = element<S, K>();
                std::copy(e.begin(), e.end(), out.begin() + i);
            }
        }
        expect(')');
        return out;
    }

    template <class S, size_t K>
    std::array<S, K> element() {
        std::array<S, K> e{};
        if (K > 1) expect('(');
        for (auto& x : e) x = number<S>();
        if (K > 1) expect(')');
        return e;
    }

    // ascii faceList: N( k(a b c ...) ... )
    void faceList(std::vector<int32_t>& offsets, std::vector<int32_t>& labels) {
        if (binary_) fail("binary faceList (expected faceCompactList)");
        const auto n = number<long long>();
        expect('(');
        offsets.assign(1, 0);
        offsets.reserve(static_cast<size_t>(n) + 1);
        for (long long f = 0; f < n; ++f) {
            const auto k = number<int32_t>();
            expect('(');
            for (int32_t i = 0; i < k; ++i) labels.push_back(number<int32_t>());
            expect(')');
            offsets.push_back(static_cast<int32_t>(labels.size()));
        }
        expect(')');
    }

    const std::string& text() const { return s_; }
    size_t pos() const { return pos_; }

    // Whether a list ("N(", "N{", "List<T> N(") or a plain number follows the cursor.
    bool listAhead() {
        skipSpace();
        size_t p = pos_;
        if (s_.compare(p, 5, "List<") == 0) return true;
        while (p < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p]))) ++p;
        if (p == pos_) return false;
        while (p < s_.size() && std::isspace(static_cast<unsigned char>(s_[p]))) ++p;
        return p < s_.size() && (s_[p] == '(' || s_[p] == '{');
    }

private:
    static std::string entry(const std::string& header, const std::string& key) {
        std::smatch m;
        if (std::regex_search(header, m, std::regex("\\b" + key + "\\s+(\"([^\"]*)\"|([^;]*));")))
            return m[2].matched ? m[2].str() : m[3].str();
        return {};
    }

    fs::path file_;
    std::string s_;
    size_t pos_ = 0;
    bool binary_ = false;
    std::string klass_;
};

std::vector<int32_t> labelList(const fs::path& file) { return FoamReader(file).list<int32_t, 1>(); }

// One patch's dictionary in a field file: its type and, if written, its `value` (n x K numbers,
// a uniform value expanded). Other entries (inletValue, refValue, ...) are read past.
struct PatchEntry {
    std::string type;
    std::vector<double> value;
    bool hasValue = false;
};

std::vector<double> anyList(FoamReader& r, const std::string& type) {
    if (type == "List<scalar>") return r.list<double, 1>();
    if (type == "List<vector>") return r.list<double, 3>();
    if (type == "List<symmTensor>") return r.list<double, 6>();
    if (type == "List<tensor>") return r.list<double, 9>();
    r.fail("a list of type " + type);
}

// A field entry's value after its keyword: "uniform X" (expanded to n elements) or "nonuniform
// List<T> N(...)" with N = n, of k components each (1: scalar, 3: vector). what and of name the
// entry and its elements in errors ("internalField", "cells").
std::vector<double> fieldValues(FoamReader& r, size_t n, int k, const std::string& what, const std::string& of) {
    const std::string kind = r.word();
    std::vector<double> out;
    if (kind == "uniform") {
        std::vector<double> one(static_cast<size_t>(k));
        if (k == 1) one[0] = r.number<double>();
        else {
            const auto e = r.element<double, 3>();
            one.assign(e.begin(), e.end());
        }
        out.resize(n * k);
        for (size_t i = 0; i < out.size(); ++i) out[i] = one[i % k];
        return out;
    }
    if (kind != "nonuniform") r.fail(what + " is neither uniform nor nonuniform");
    // An empty list may come without its type: "nonuniform 0()".
    if (std::isdigit(static_cast<unsigned char>(r.peek()))) out = r.list<double, 1>();
    else {
        const std::string type = r.word();
        if (type != (k == 1 ? "List<scalar>" : "List<vector>")) r.fail(what + " of type " + type);
        out = k == 1 ? r.list<double, 1>() : r.list<double, 3>();
    }
    if (out.size() != n * k)
        r.fail(what + " has " + std::to_string(out.size() / k) + " values for " + std::to_string(n) + " " + of);
    return out;
}

// Reads past the rest of an entry up to its ';': words, numbers, (...) groups and nonuniform lists
// (binary lists included, which is why this cannot just search for the ';').
void skipEntry(FoamReader& r) {
    while (r.peek() != ';') {
        if (r.peek() == '(') {
            r.expect('(');
            while (r.peek() != ')') (void)r.number<double>();
            r.expect(')');
            continue;
        }
        if (r.word() != "nonuniform") continue;
        if (std::isdigit(static_cast<unsigned char>(r.peek()))) (void)r.list<double, 1>();
        else (void)anyList(r, r.word());
    }
    r.expect(';');
}

PatchEntry readPatchEntry(FoamReader& r, size_t faces, int components) {
    PatchEntry e;
    r.expect('{');
    while (r.peek() != '}') {
        const std::string key = r.word();
        if (key == "type") {
            e.type = r.word();
            r.expect(';');
        } else if (key == "value" && e.type != "empty") {  // an empty patch has no faces in fields
            e.value = fieldValues(r, faces, components, "value of a patch", "faces");
            e.hasValue = true;
            r.expect(';');
        } else {
            skipEntry(r);
        }
    }
    r.expect('}');
    return e;
}



std::vector<FoamPatch> readBoundary(const fs::path& file) {
    FoamReader r(file);
    const auto n = r.number<long long>();
    r.expect('(');
    std::vector<FoamPatch> patches;
    for (long long i = 0; i < n; ++i) {
        FoamPatch p;
        p.name = r.word();
        r.expect('{');
        while (r.peek() != '}') {
            const std::string key = r.word();
            std::string value;
            // Values may be words, numbers or lists: read up to the entry's ';'.
            while (r.peek() != ';') {
                if (r.peek() == '(' || r.peek() == ')') {
                    r.expect(r.peek());
                    continue;
                }
                value += (value.empty() ? "" : " ") + r.word();
            }
            r.expect(';');
            if (key == "type") p.type = value;
            else if (key == "startFace") p.start = std::stoi(value);
            else if (key == "nFaces") p.size = std::stoi(value);
        }
        r.expect('}');
        patches.push_back(p);
    }
    return patches;
}

}  // namespace

std::vector<Vec3> readPoints(const fs::path& pointsFile) {
    const auto flat = FoamReader(pointsFile).list<double, 3>();
    std::vector<Vec3> pts(flat.size() / 3);
    std::memcpy(pts.data(), flat.data(), flat.size() * sizeof(double));
    return pts;
}

FoamMesh readPolyMesh(const fs::path& dir) {
    FoamMesh m;
    m.points = readPoints(dir / "points");
    {
        FoamReader r(dir / "faces");
        if (r.klass() == "faceCompactList") {
            m.faceOffsets = r.list<int32_t, 1>();
            m.facePoints = r.list<int32_t, 1>();
        } else {
            r.faceList(m.faceOffsets, m.facePoints);
        }
    }
    m.owner = labelList(dir / "owner");
    m.neighbour = labelList(dir / "neighbour");
    m.patches = readBoundary(dir / "boundary");

    const auto bad = [&](const std::string& what) {
        throw std::runtime_error(dir.string() + ": inconsistent polyMesh: " + what);
    };
    if (m.faceOffsets.empty() || m.faceOffsets.size() != m.owner.size() + 1)
        bad("faces and owner sizes differ");
    if (m.faceOffsets.back() != static_cast<int32_t>(m.facePoints.size()))
        bad("face offsets do not end at the label count");
    if (m.neighbour.size() > m.owner.size()) bad("more neighbours than faces");
    for (const auto l : m.facePoints)
        if (l < 0 || static_cast<size_t>(l) >= m.points.size()) bad("face point label out of range");
    int32_t maxCell = -1;
    for (const auto c : m.owner) maxCell = std::max(maxCell, c);
    for (const auto c : m.neighbour) maxCell = std::max(maxCell, c);
    m.nCells = maxCell + 1;
    for (const auto& p : m.patches)
        if (p.start < 0 || p.size < 0 || static_cast<size_t>(p.start) + p.size > m.owner.size())
            bad("patch " + p.name + " lies outside the face list");
    return m;
}

FoamField readInternalField(const fs::path& file, int32_t nCells) {
    FoamReader r(file);
    FoamField f;
    const std::string& k = r.klass();
    if (k == "volScalarField") f.components = 1;
    else if (k == "volVectorField") f.components = 3;
    else r.fail("class " + k + " (mixload exports volScalarField and volVectorField)");
    r.seekKeyword("internalField");
    f.values = fieldValues(r, static_cast<size_t>(nCells), f.components, "internalField", "cells");
    return f;
}

PowderTransport readPowderTransport(const fs::path& caseDir) {
    const fs::path file = caseDir / "constant" / "transportProperties";
    const std::string text = readFile(file);
    std::smatch m;
    // mixload writes the powder phase first: "powder { transportModel X; rho R; XCoeffs { k v; ... } }".
    if (!std::regex_search(text, m, std::regex("powder\\s*\\{\\s*transportModel\\s+(\\w+);\\s*rho\\s+([^;]+);\\s*(\\w+)Coeffs\\s*\\{([^}]*)\\}")))
        throw std::runtime_error(file.string() + ": no powder phase with transportModel, rho and its Coeffs");
    PowderTransport t;
    t.model = m[1];
    const auto rho = parseNumber(m[2].str());
    if (!rho) throw std::runtime_error(file.string() + ": powder rho is not a number");
    t.values.emplace_back("rho", *rho);
    const std::string coeffs = m[4];
    const std::regex entry("(\\w+)\\s+([^;\\s]+)\\s*;");
    for (auto it = std::sregex_iterator(coeffs.begin(), coeffs.end(), entry); it != std::sregex_iterator(); ++it)
        if (const auto v = parseNumber((*it)[2].str())) t.values.emplace_back((*it)[1].str(), *v);
    // The air as "air { transportModel Newtonian; nu N; rho R; }": a reduced model's mixture
    // density and viscosity need it.
    if (std::regex_search(text, m, std::regex("air\\s*\\{\\s*transportModel\\s+Newtonian;\\s*nu\\s+([^;]+);\\s*rho\\s+([^;]+);"))) {
        if (const auto nu = parseNumber(m[1].str())) t.values.emplace_back("airNu", *nu);
        if (const auto r = parseNumber(m[2].str())) t.values.emplace_back("airRho", *r);
    }
    return t;
}

std::vector<std::string> timeDirectories(const fs::path& caseDir) {
    std::vector<std::pair<double, std::string>> times;
    for (const auto& e : fs::directory_iterator(caseDir)) {
        if (!e.is_directory()) continue;
        const std::string name = e.path().filename();
        if (const auto t = parseNumber(name)) times.emplace_back(*t, name);
    }
    std::sort(times.begin(), times.end());
    std::vector<std::string> out;
    for (auto& t : times) out.push_back(t.second);
    return out;
}

std::vector<std::pair<std::string, std::vector<int32_t>>> readCellZones(const fs::path& polyMeshDir) {
    const fs::path file = polyMeshDir / "cellZones";
    std::vector<std::pair<std::string, std::vector<int32_t>>> out;
    if (!fs::exists(file)) return out;
    FoamReader r(file);
    const auto n = r.number<long long>();
    r.expect('(');
    for (long long i = 0; i < n; ++i) {
        std::string name = r.word();
        r.expect('{');
        r.seekKeyword("cellLabels");
        if (!std::isdigit(static_cast<unsigned char>(r.peek()))) r.word();  // "List<label>"
        out.emplace_back(std::move(name), r.list<int32_t, 1>());
        r.expect(';');
        r.expect('}');
    }
    return out;
}

std::vector<MrfZone> readMrfZones(const fs::path& caseDir) {
    const fs::path file = caseDir / "constant" / "MRFProperties";
    std::vector<MrfZone> out;
    if (!fs::exists(file)) return out;
    const std::string text = readFile(file);
    const auto entry = [&](const std::string& block, const std::string& key) {
        std::smatch m;
        if (!std::regex_search(block, m, std::regex("(^|[\\s;])" + key + "\\s+([^;]+);")))
            throw std::runtime_error(file.string() + ": an MRF zone without '" + key + "'");
        return m[2].str();
    };
    const auto vec = [&](const std::string& s) {
        std::smatch m;
        Vec3 v{};
        if (!std::regex_match(s, m, std::regex("\\s*\\(\\s*(\\S+)\\s+(\\S+)\\s+(\\S+)\\s*\\)\\s*")))
            throw std::runtime_error(file.string() + ": '" + s + "' is not a vector");
        for (size_t k = 0; k < 3; ++k) {
            const auto x = parseNumber(m[k + 1].str());
            if (!x) throw std::runtime_error(file.string() + ": '" + s + "' is not a vector");
            v[k] = *x;
        }
        return v;
    };
    // Every "name { ... }" block after the header is a zone (mixload writes no nested braces).
    const std::string body = text.substr(text.find('}', text.find("FoamFile")) + 1);
    const std::regex block("(\\w+)\\s*\\{([^{}]*)\\}");
    for (auto it = std::sregex_iterator(body.begin(), body.end(), block); it != std::sregex_iterator(); ++it) {
        const std::string b = (*it)[2];
        // OpenFOAM's default is active.
        std::smatch a;
        if (std::regex_search(b, a, std::regex("(^|[\\s;])active\\s+(no|off|false|0)\\s*;"))) continue;
        MrfZone z;
        z.name = (*it)[1];
        z.cellZone = entry(b, "cellZone");
        z.origin = vec(entry(b, "origin"));
        z.axis = vec(entry(b, "axis"));
        const auto omega = parseNumber(entry(b, "omega"));
        if (!omega) throw std::runtime_error(file.string() + ": omega of zone " + z.name + " is not a number");
        z.omega = *omega;
        out.push_back(z);
    }
    return out;
}

std::map<std::string, std::vector<double>> readFunctionObjectState(const fs::path& file, const std::string& object) {
    FoamReader r(file);
    r.seekKeyword(object);
    r.expect('{');
    std::map<std::string, std::vector<double>> out;
    while (r.peek() != '}') {
        const std::string key = r.word();
        if (r.listAhead()) {
            if (r.peek() == 'L') r.word();  // "List<scalar>"
            out[key] = r.list<double, 1>();
        } else {
            out[key] = {r.number<double>()};
        }
        r.expect(';');
    }
    return out;
}

}  // namespace mixload::post

namespace mixload::post {

namespace {
// The patches' entries of a field file, by patch name.
std::map<std::string, PatchEntry> boundaryEntries(FoamReader& r, const FoamMesh& mesh, int components) {
    r.seekKeyword("boundaryField");
    r.expect('{');
    std::map<std::string, PatchEntry> out;
    while (r.peek() != '}') {
        const std::string name = r.word();
        const auto p = std::find_if(mesh.patches.begin(), mesh.patches.end(), [&](const FoamPatch& q) { return q.name == name; });
        if (p == mesh.patches.end()) r.fail("boundaryField entry " + name + " is not a patch of the mesh");
        out[name] = readPatchEntry(r, static_cast<size_t>(p->size), components);
    }
    return out;
}
}  // namespace

std::vector<double> readBoundaryValues(const fs::path& file, const FoamMesh& mesh, const FoamField& internal,
                                       const std::vector<Vec3>& faceAreas) {
    FoamReader r(file);
    const auto entries = boundaryEntries(r, mesh, internal.components);
    const auto k = static_cast<size_t>(internal.components);
    std::vector<double> out;
    for (const auto& p : mesh.patches) {
        if (p.type == "empty") continue;
        const auto e = entries.find(p.name);
        if (e == entries.end()) r.fail("no boundaryField entry for patch " + p.name);
        if (e->second.hasValue) {
            out.insert(out.end(), e->second.value.begin(), e->second.value.end());
            continue;
        }
        // No value written: what the patch type implies, or a clear refusal (never a guess).
        const std::string& type = e->second.type;
        if (type == "noSlip") {
            out.insert(out.end(), static_cast<size_t>(p.size) * k, 0.0);
        } else if (type == "zeroGradient") {
            for (int32_t f = p.start; f < p.start + p.size; ++f)
                for (size_t c = 0; c < k; ++c) out.push_back(internal.values[static_cast<size_t>(mesh.owner[f]) * k + c]);
        } else if (type == "slip" || type == "symmetry" || type == "symmetryPlane") {
            // basicSymmetry: the cell value without its normal component (scalars: the cell value).
            for (int32_t f = p.start; f < p.start + p.size; ++f) {
                const double* u = &internal.values[static_cast<size_t>(mesh.owner[f]) * k];
                if (k != 3) {
                    out.insert(out.end(), u, u + k);
                    continue;
                }
                const auto& s = faceAreas.at(static_cast<size_t>(f));
                const double a = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
                const double un = (u[0] * s[0] + u[1] * s[1] + u[2] * s[2]) / a;
                for (int c = 0; c < 3; ++c) out.push_back(u[c] - un * s[c] / a);
            }
        } else {
            r.fail("patch " + p.name + " of type " + type +
                   " writes no value (mixload reads zeroGradient, noSlip, slip and symmetry)");
        }
    }
    return out;
}

std::vector<double> readSurfaceField(const fs::path& file, const FoamMesh& mesh) {
    FoamReader r(file);
    if (r.klass() != "surfaceScalarField") r.fail("class " + r.klass() + " (expected surfaceScalarField)");
    r.seekKeyword("internalField");
    const size_t nInternal = mesh.neighbour.size();
    std::vector<double> out = fieldValues(r, nInternal, 1, "internalField", "internal faces");
    const auto entries = boundaryEntries(r, mesh, 1);
    for (const auto& p : mesh.patches) {
        if (p.type == "empty") continue;
        const auto e = entries.find(p.name);
        if (e == entries.end() || !e->second.hasValue) r.fail("no value for patch " + p.name);
        out.insert(out.end(), e->second.value.begin(), e->second.value.end());
    }
    return out;
}

}  // namespace mixload::post
