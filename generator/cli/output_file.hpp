// Files are written whole or not at all: to a temporary name beside the target, then
// renamed (atomic on POSIX), so a failure never leaves a half-written output behind.
#pragma once

#include <filesystem>
#include <string>

namespace eomc::cli {

void write_file_atomically(const std::filesystem::path& path, const std::string& content);

}  // namespace eomc::cli
