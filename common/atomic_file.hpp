// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>

namespace mixload {
// Writes text to a temporary beside path, then commits it (commitAtomic): readers, and a machine
// back from a crash, see the old file or the complete new one, never half of it. Throws
// std::runtime_error naming the file and the cause, leaving no temporary behind.
void writeFileAtomic(const std::filesystem::path& path, const std::string& text);

// The two halves, for writers that fill a file themselves (HDF5): a temporary name beside path
// (path.tmp.<pid>.<n>), and the commit: sync it, rename it over path, sync the folder. The commit
// removes the temporary when it fails.
std::filesystem::path atomicTempPath(const std::filesystem::path& path);
void commitAtomic(const std::filesystem::path& tmp, const std::filesystem::path& path);

std::string readFile(const std::filesystem::path& path);
}  // namespace mixload
