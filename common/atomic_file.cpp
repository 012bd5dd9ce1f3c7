// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/atomic_file.hpp"

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mixload {

void writeFileAtomic(const std::filesystem::path& path, const std::string& text) {
    auto tmp = path;
    tmp += ".tmp." + std::to_string(::getpid());
    {
        std::ofstream os(tmp, std::ios::binary);
        if (!os) throw std::runtime_error("cannot write " + tmp.string());
        os << text;
        os.flush();
        if (!os) throw std::runtime_error("write failed: " + tmp.string());
    }
    std::filesystem::rename(tmp, path);
}

std::string readFile(const std::filesystem::path& path) {
    std::ifstream is(path, std::ios::binary);
    if (!is) throw std::runtime_error("cannot read " + path.string());
    std::ostringstream ss;
    ss << is.rdbuf();
    return ss.str();
}

}  // namespace mixload
