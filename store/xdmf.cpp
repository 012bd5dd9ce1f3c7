// SPDX-License-Identifier: GPL-3.0-or-later
#include "store/xdmf.hpp"

#include <iomanip>
#include <sstream>

#include "common/atomic_file.hpp"

namespace mixload::store {

namespace fs = std::filesystem;

void writeXdmf(const fs::path& xdmf, const std::string& h5name, const std::vector<double>& times,
               int32_t cells, const std::vector<std::pair<std::string, int>>& fields, bool float64,
               bool moving) {
    const std::string n = std::to_string(cells), nt = std::to_string(times.size());
    std::ostringstream x;
    x << "<?xml version=\"1.0\" ?>\n<!-- Cell centres as points: open in ParaView (Xdmf3 reader). -->\n"
      << "<Xdmf Version=\"3.0\">\n <Domain>\n"
      << "  <Grid Name=\"snapshots\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    const auto slab = [&](const std::string& path, int comps, size_t row, const char* prec) {
        const std::string dims = comps == 1 ? n : n + " 3";
        std::ostringstream s;
        s << "     <DataItem ItemType=\"HyperSlab\" Dimensions=\"" << dims << "\" Type=\"HyperSlab\">\n"
          << "      <DataItem Dimensions=\"3 " << (comps == 1 ? 2 : 3) << "\" Format=\"XML\">"
          << row << " 0" << (comps == 1 ? "" : " 0") << "  1 1" << (comps == 1 ? "" : " 1")
          << "  1 " << n << (comps == 1 ? "" : " 3") << "</DataItem>\n"
          << "      <DataItem Dimensions=\"" << nt << " " << dims << "\" NumberType=\"Float\" Precision=\""
          << prec << "\" Format=\"HDF\">" << h5name << ":" << path << "</DataItem>\n"
          << "     </DataItem>\n";
        return s.str();
    };
    for (size_t i = 0; i < times.size(); ++i) {
        x << std::setprecision(12) << "   <Grid Name=\"t" << i << "\" GridType=\"Uniform\">\n"
          << "    <Time Value=\"" << times[i] << "\"/>\n"
          << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
          << "\" NodesPerElement=\"1\"/>\n    <Geometry GeometryType=\"XYZ\">\n";
        if (moving) x << slab("/fields/cell_centres", 3, i, "8");
        else
            x << "     <DataItem Dimensions=\"" << n << " 3\" NumberType=\"Float\" Precision=\"8\" "
              << "Format=\"HDF\">" << h5name << ":/mesh/cell_centres</DataItem>\n";
        x << "    </Geometry>\n"
          << "    <Attribute Name=\"cell_volume\" AttributeType=\"Scalar\" Center=\"Node\">\n"
          << "     <DataItem Dimensions=\"" << n << "\" NumberType=\"Float\" Precision=\"8\" "
          << "Format=\"HDF\">" << h5name << ":/mesh/cell_volumes</DataItem>\n    </Attribute>\n";
        for (const auto& [name, comps] : fields) {
            x << "    <Attribute Name=\"" << name << "\" AttributeType=\""
              << (comps == 1 ? "Scalar" : "Vector") << "\" Center=\"Node\">\n"
              << slab("/fields/" + name, comps, i, float64 ? "8" : "4") << "    </Attribute>\n";
        }
        x << "   </Grid>\n";
    }
    x << "  </Grid>\n </Domain>\n</Xdmf>\n";
    writeFileAtomic(xdmf, x.str());
}

}  // namespace mixload::store
