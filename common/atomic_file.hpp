// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>

namespace mixload {
// Writes text to path.tmp.<pid>, flushes, then renames over path: readers see the old file or the
// complete new one, never half of it.
void writeFileAtomic(const std::filesystem::path& path, const std::string& text);
std::string readFile(const std::filesystem::path& path);
}  // namespace mixload
