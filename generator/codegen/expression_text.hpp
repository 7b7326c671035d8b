// One expression as text: GiNaC's own syntax (what JSON carries and the parser reads back) or
// LaTeX. Shared by the derivation, inverse-problem and equilibria printers.
#pragma once

#include <sstream>
#include <string>

#include <ginac/ginac.h>

namespace eomc::codegen {

inline std::string text(const GiNaC::ex& e) {
    std::ostringstream os;
    os << GiNaC::dflt << e;
    return os.str();
}

inline std::string latex(const GiNaC::ex& e) {
    std::ostringstream os;
    os << GiNaC::latex << e;
    return os.str();
}

}  // namespace eomc::codegen
