// The harmonic oscillator several tests vary, as scene text (no generator needed).
#pragma once

#include <string>

namespace test_support {

// q̈ = −(stiffness) q from q = 1 at rest: T = q̇²/2, V = stiffness·q²/2.
struct Oscillator {
    std::string name = "oscillator";
    std::string summary_line;      // a whole `summary = …` line, or nothing
    std::string parameter;         // its one parameter, or none
    std::string value = "1.0";     // the parameter's value
    std::string stiffness = "1";   // an expression in the parameter
    std::string tail;              // further tables ([simulate], [reference], …)
};

inline std::string oscillator_scene(const Oscillator& o) {
    std::string text = "[scene]\nname = \"" + o.name + "\"\n";
    if (!o.summary_line.empty()) text += o.summary_line + "\n";
    if (!o.parameter.empty()) text += "[parameters]\n" + o.parameter + " = " + o.value + "\n";
    text += "[coordinates]\nq = { initial = 1.0, rate = 0.0 }\n[lagrangian]\nT = \"q_dot^2/2\"\nV = \"" + o.stiffness +
            "*q^2/2\"\n";
    return text + o.tail;
}

}  // namespace test_support
