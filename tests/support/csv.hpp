// Reading the CSV files eomc writes: lines, numeric rows, the last row.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace test_support {

inline std::vector<std::string> read_lines(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// The comma-separated numbers of one row (std::stod: throws on a cell that is not a number).
inline std::vector<double> csv_numbers(const std::string& line) {
    std::vector<double> out;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) out.push_back(std::stod(cell));
    return out;
}

// The last non-empty row of a CSV file, as numbers.
inline std::vector<double> last_csv_row(const std::filesystem::path& csv) {
    std::string last;
    for (const std::string& line : read_lines(csv))
        if (!line.empty()) last = line;
    return csv_numbers(last);
}

}  // namespace test_support
