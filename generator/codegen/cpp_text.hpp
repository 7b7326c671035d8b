// Text that reaches generated C++: prose in comments, names in string literals and as
// identifiers, numbers as literals, and the one-pass filling of the kernel template.
//
// A scene is untrusted input: every string from it that ends up in a header passes through
// one of these functions, each of which either makes the text inert at its destination or
// refuses it. The emitter never pastes a scene string anywhere else.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace eomc::codegen {

// An emitter invariant broken by its input (a name that is no identifier, a constant double
// cannot hold): the kernel is not written.
struct EmitError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// `text` made safe to stand after "// " on one line: line breaks, other control characters,
// bytes that are not UTF-8 and a line-splicing backslash at the end become visible \xNN
// escapes, so nothing can end the comment or splice the next line into it.
std::string comment_text(std::string_view text);

// `text` as a C++ string literal: quote and backslash escaped, every byte outside printable
// ASCII as a three-digit octal escape (which cannot run into the next character).
std::string string_literal(std::string_view text);

// True for [A-Za-z_][A-Za-z0-9_]*.
bool is_cpp_identifier(std::string_view s);

// True when a kernel, its loader or the benchmark driver sees `name` as a macro of the
// headers they include (<cmath>'s M_PI, <cstdio>'s EOF, Eigen's, …, and the GNU dialect's
// `linux`/`unix`): such a name cannot stand in C++ as itself. The list is taken from the
// compiler's preprocessor when eomc is built (generator/CMakeLists.txt).
bool is_kernel_macro(std::string_view name);

// `name` checked to be an identifier, for a string literal or a C++ name; EmitError otherwise.
const std::string& checked_identifier(const std::string& name, std::string_view what);

// A finite double as a C++ literal that reads back as the same double; EmitError otherwise.
std::string double_literal(double value, std::string_view what);

// The template with every {{key}} replaced by its value in one pass: a value is never scanned
// for markers again. Unknown markers and unused fields are errors of the emitter itself.
std::string fill_template(std::string_view text, const std::vector<std::pair<std::string, std::string>>& fields);

}  // namespace eomc::codegen
