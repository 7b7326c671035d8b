// A file's bytes, read whole: logs, cached outputs, kernel libraries. An unreadable file reads
// as empty; callers that must tell the two apart check the path first.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace eomc {

inline std::string read_whole_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace eomc
