// SPDX-License-Identifier: GPL-3.0-or-later
// The XDMF sidecar of a snapshot file: ParaView (Xdmf3 reader) shows the stored fields on the cell
// centres, one grid per stored time, reading the HDF5 datasets by hyperslab. Full runs' exports and
// reduced models' outputs write it the same way.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mixload::store {

// fields: (name under /fields, components 1 or 3); moving: cell centres per time in /fields/cell_centres.
void writeXdmf(const std::filesystem::path& xdmf, const std::string& h5name, const std::vector<double>& times,
               int32_t cells, const std::vector<std::pair<std::string, int>>& fields, bool float64, bool moving);

}  // namespace mixload::store
