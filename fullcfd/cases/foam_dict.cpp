// SPDX-License-Identifier: GPL-3.0-or-later
#include "cases/foam_dict.hpp"

#include <sstream>

#include "common/atomic_file.hpp"

namespace mixload::cases {

std::string foamHeader(const std::string& cls, const std::string& object,
                       const std::string& location) {
    std::ostringstream os;
    os << "// written by mixload\nFoamFile\n{\n    version 2.0;\n    format ascii;\n    class "
       << cls << ";\n";
    if (!location.empty()) os << "    location \"" << location << "\";\n";
    os << "    object " << object << ";\n}\n\n";
    return os.str();
}

void writeFoamFile(const std::filesystem::path& caseDir, const std::string& rel,
                   const std::string& cls, const std::string& body) {
    const std::filesystem::path p = caseDir / rel;
    std::filesystem::create_directories(p.parent_path());
    const std::string loc = std::filesystem::path(rel).parent_path().string();
    writeFileAtomic(p, foamHeader(cls, p.filename().string(), loc) + body);
}

std::string num(double v) {
    std::ostringstream os;
    os.precision(12);
    os << v;
    return os.str();
}

}  // namespace mixload::cases
