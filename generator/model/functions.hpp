// The functions a scene's expressions may call. One list: the parser accepts these (and
// sqrt, which GiNaC turns into a power), and every later stage — differentiation, numeric
// probing, the C++ emitter — must handle each of them (tests/codegen checks that they do).
#pragma once

#include <algorithm>
#include <array>
#include <string_view>

namespace eomc::model {

inline constexpr std::array<std::string_view, 11> elementary_functions{"sin",  "cos",  "tan",  "exp",
                                                                      "log",  "asin", "acos", "atan",
                                                                      "sinh", "cosh", "tanh"};

inline bool is_elementary_function(std::string_view name) {
    return std::find(elementary_functions.begin(), elementary_functions.end(), name) != elementary_functions.end();
}

}  // namespace eomc::model
