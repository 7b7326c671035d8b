// The one rule for names that reach generated code, CSV headers or a compiler command line:
// ASCII letters, digits and '_', never a digit first. Checked byte by byte, not through
// <cctype>, so that no locale can widen it.
#pragma once

#include <algorithm>
#include <string_view>

namespace eomc {

inline bool is_ascii_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

inline bool is_ascii_word_char(char c) { return is_ascii_letter(c) || (c >= '0' && c <= '9') || c == '_'; }

// A C/C++ identifier (ASCII): a letter or '_' first.
inline bool is_identifier(std::string_view s) {
    return !s.empty() && (is_ascii_letter(s[0]) || s[0] == '_') && std::all_of(s.begin(), s.end(), is_ascii_word_char);
}

// What a scene may name (coordinates, parameters, bodies, events): an identifier that starts with
// a letter. A leading '_' is left to the generator's own names, and keeps scene names clear of the
// identifiers C++ reserves (_Upper, and __ at the start).
inline bool is_scene_identifier(std::string_view s) { return is_identifier(s) && is_ascii_letter(s[0]); }

}  // namespace eomc
