// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>

namespace mixload::cases {

// FoamFile header for an OpenFOAM dictionary or field file.
std::string foamHeader(const std::string& cls, const std::string& object,
                       const std::string& location = "");
// Writes caseDir/rel (creating folders) with the header prepended.
void writeFoamFile(const std::filesystem::path& caseDir, const std::string& rel,
                   const std::string& cls, const std::string& body);
// Number formatted with full precision for a dictionary.
std::string num(double v);

}  // namespace mixload::cases
