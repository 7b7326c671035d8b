#include "support/diagnostic.hpp"

#include <algorithm>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace eomc {

std::string to_string(const SourcePos& pos) {
    const std::string_view file = pos.file.empty() ? std::string_view("<input>") : std::string_view(pos.file);
    if (pos.line <= 0) return std::string(file);
    if (pos.column <= 0) return fmt::format("{}:{}", file, pos.line);
    return fmt::format("{}:{}:{}", file, pos.line, pos.column);
}

std::string format_diagnostic(const SourcePos& pos, const std::string& message) {
    return to_string(pos) + ": error: " + message;
}

std::string format_warning(const Warning& w) { return to_string(w.pos) + ": warning: " + w.message; }

InputError::InputError(SourcePos pos, const std::string& message)
    : std::runtime_error(format_diagnostic(pos, message)), pos_(std::move(pos)), message_(message) {}

namespace {

// Optimal-string-alignment distance: insertions, deletions, substitutions and swaps of
// two neighbouring letters (the commonest typo, "Omgea") each cost one.
std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0u : 1u)});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[a.size()][b.size()];
}

template <class Range>
std::string nearest(const std::string& word, const Range& candidates) {
    std::string best;
    std::size_t best_d = std::string::npos;
    for (const auto& c : candidates) {
        const std::string cand(c);
        const std::size_t d = edit_distance(word, cand);
        if (d < best_d) best_d = d, best = cand;
    }
    // Suggest only plausible typos: at most a third of the word wrong (and at least one edit allowed).
    const std::size_t allowed = std::max<std::size_t>(1, std::max(word.size(), best.size()) / 3);
    return best_d <= allowed ? best : std::string();
}

}  // namespace

std::string nearest_name(const std::string& word, const std::initializer_list<const char*>& candidates) {
    return nearest(word, candidates);
}
std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates) {
    return nearest(word, candidates);
}

}  // namespace eomc
