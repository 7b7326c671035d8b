#include "report/equilibria_printer.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "support/json.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::report {

using symbolic::text;

namespace {

void print_json(const model::Model& model, const std::vector<mechanics::Equilibrium>& found, std::ostream& out) {
    out << "{\"equilibria\": [";
    for (std::size_t i = 0; i < found.size(); ++i) {
        out << (i ? ",\n  " : "\n  ") << "{\"q\": {";
        for (std::size_t k = 0; k < found[i].q.size(); ++k)
            out << (k ? ", " : "") << json_string(model.coordinates[k].name) << fmt::format(": {:.17g}", found[i].q[k]);
        out << "}, \"free\": [";
        for (std::size_t k = 0, listed = 0; k < found[i].free.size(); ++k)
            if (found[i].free[k]) out << (listed++ ? ", " : "") << json_string(model.coordinates[k].name);
        out << "], \"eigenvalues\": [";
        for (std::size_t k = 0; k < found[i].eigenvalues.size(); ++k)
            out << (k ? ", " : "")
                << fmt::format("[{:.17g}, {:.17g}]", found[i].eigenvalues[k].real(), found[i].eigenvalues[k].imag());
        out << "], \"verdict\": \"" << found[i].verdict << "\"";
        // The closed forms, in GiNaC syntax, when the equilibrium was solved symbolically.
        out << ", \"exact\": ";
        if (found[i].exact.empty()) {
            out << "null";
        } else {
            out << "{";
            for (std::size_t k = 0, listed = 0; k < found[i].exact.size(); ++k)
                if (!found[i].free[k])
                    out << (listed++ ? ", " : "") << json_string(model.coordinates[k].name) << ": "
                        << json_string(text(found[i].exact[k]));
            out << "}";
        }
        out << ", \"lambda_squared\": "
            << (found[i].lambda_squared ? json_string(text(*found[i].lambda_squared)) : "null") << "}";
    }
    out << (found.empty() ? "]}\n" : "\n]}\n");
}

void print_text(const model::Model& model, const std::vector<mechanics::Equilibrium>& found, std::ostream& out) {
    out << fmt::format("{} relative equilibri{} of {} (q̇ = 0, parameters at their defaults)\n", found.size(),
                       found.size() == 1 ? "um" : "a", model.name);
    if (!found.empty() && std::find(found[0].free.begin(), found[0].free.end(), true) != found[0].free.end())
        out << "(\"any\": a coordinate absent from the equations at rest; each equilibrium is a family in it)\n";
    for (const auto& e : found) {
        out << "\n ";
        for (std::size_t k = 0; k < e.q.size(); ++k)
            out << (e.free[k] ? fmt::format(" {} = any", model.coordinates[k].name)
                              : fmt::format(" {} = {:.12g}", model.coordinates[k].name, e.q[k]));
        for (std::size_t k = 0, listed = 0; k < e.exact.size(); ++k)
            if (!e.free[k])
                out << fmt::format("{}{} = {}", listed++ ? ", " : "\n    closed form: ", model.coordinates[k].name,
                                   text(e.exact[k]));
        if (e.lambda_squared) out << "\n    λ² = (∂f/∂q)/M = " << text(*e.lambda_squared);
        out << "\n    " << e.verdict;
        // Growth rates above the eigensolver's noise (the tolerance the verdict used).
        double largest = 0;
        for (const auto& l : e.eigenvalues) largest = std::max(largest, std::abs(l));
        std::string rates;
        for (const auto& l : e.eigenvalues) {
            if (e.verdict == "unstable" && l.real() > 1e-9 * (1 + largest)) rates += fmt::format(" {:.9g}", l.real());
            if (e.verdict != "unstable" && l.imag() > 0) rates += fmt::format(" {:.9g}", l.imag());
        }
        out << (e.verdict == "unstable" ? ": growth rates" : ": frequencies") << rates << "\n    eigenvalues";
        for (const auto& l : e.eigenvalues) out << fmt::format(" ({:.6g}{:+.6g}i)", l.real(), l.imag());
        out << "\n";
    }
}

}  // namespace

void print_equilibria(const model::Model& model, const std::vector<mechanics::Equilibrium>& found,
                      const std::string& format, std::ostream& out) {
    if (format == "json") print_json(model, found, out);
    else print_text(model, found, out);
}

}  // namespace eomc::report

namespace eomc::report {

namespace {

namespace rigid = mechanics::rigid;

std::string complex_json(const std::vector<std::complex<double>>& values) {
    std::string out = "[";
    for (std::size_t k = 0; k < values.size(); ++k)
        out += fmt::format("{}[{:.17g}, {:.17g}]", k ? ", " : "", values[k].real(), values[k].imag());
    return out + "]";
}

std::string rotation_json(const rigid::PermanentRotation& r) {
    return fmt::format("{{\"label\": {}, \"gamma\": [{:.17g}, {:.17g}, {:.17g}], \"spin\": {:.17g}, \"any_spin\": {}, "
                       "\"eigenvalues\": {}, \"leaf_eigenvalues\": {}, \"verdict\": {}}}",
                       json_string(r.label), r.gamma[0], r.gamma[1], r.gamma[2], r.spin, r.any_spin ? "true" : "false",
                       complex_json(r.eigenvalues), complex_json(r.reduced), json_string(r.verdict));
}

void print_rigid_json(const rigid::RigidEquilibria& found, std::ostream& out) {
    out << "{\"rigid\": true, \"gyrostat\": " << (found.gyrostat ? "true" : "false")
        << ",\n \"cone\": " << json_string(text(found.cone))
        << ",\n \"spin_on_cone\": {\"" << (found.gyrostat ? "Omega" : "Omega^2") << "\": "
        << json_string(text(found.spin_on_cone)) << "}"
        << fmt::format(",\n \"spin\": {:.17g}", found.spin) << ",\n \"rotations\": [";
    for (std::size_t i = 0; i < found.rotations.size(); ++i)
        out << (i ? ",\n  " : "\n  ") << rotation_json(found.rotations[i]);
    out << (found.rotations.empty() ? "]" : "\n ]") << ",\n \"initial\": "
        << (found.initial ? rotation_json(*found.initial) : "null");
    if (!found.initial) out << ", \"initial_note\": " << json_string(found.initial_note);
    out << ",\n \"lagrange\": [";
    for (std::size_t i = 0; i < found.lagrange.size(); ++i) {
        const auto& c = found.lagrange[i];
        out << (i ? ",\n  " : "\n  ")
            << fmt::format("{{\"gamma\": [0, 0, {}], \"spin\": {}, \"quartic\": {}, \"criterion\": {}, "
                           "\"critical_spin\": {}}}",
                           c.sign, json_string(c.spin.get_name()), json_string(text(c.quartic)),
                           json_string(text(c.criterion) + " > 0"),
                           c.critical_spin ? json_string(text(*c.critical_spin)) : "null");
    }
    out << (found.lagrange.empty() ? "]}\n" : "\n ]}\n");
}

void print_rotation_text(const rigid::PermanentRotation& r, std::ostream& out) {
    out << fmt::format("  {}: γ = ({:.12g}, {:.12g}, {:.12g}), Ω = {:.12g}{}\n", r.label, r.gamma[0], r.gamma[1],
                       r.gamma[2], r.spin, r.any_spin ? " (any Ω: linearised at this spin)" : "");
    out << "    " << r.verdict << "\n    eigenvalues on the leaf";
    for (const auto& l : r.reduced) out << fmt::format(" ({:.12g}{:+.12g}i)", l.real(), l.imag());
    out << "\n    all six";
    for (const auto& l : r.eigenvalues) out << fmt::format(" ({:.6g}{:+.6g}i)", l.real(), l.imag());
    out << "\n";
}

void print_rigid_text(const model::Model& model, const rigid::RigidEquilibria& found, std::ostream& out) {
    out << "permanent rotations of " << model.name
        << " (ω = Ω γ about the vertical, γ fixed: Ω² γ × Iγ + Ω γ × k = P γ × r_c; Staude 1894)\n";
    if (!found.gyrostat) {
        out << "\nStaude's cone det[γ, Iγ, r_c] = 0:\n  " << text(found.cone) << " = 0"
            << (found.cone.is_zero() ? "  (identically: every vertical where γ × Iγ ∥ γ × r_c, or r_c = 0)" : "") << "\n"
            << "  on it Ω² = P (γ × r_c)·(γ × Iγ)/|γ × Iγ|² = " << text(found.spin_on_cone)
            << "  (a rotation where positive)\n";
    } else {
        out << "\nthe gyrostat's cone P det[γ, Iγ, r_c]² = det[γ, r_c, k] det[γ, Iγ, k]:\n  " << text(found.cone)
            << " = 0\n  on it Ω = P det[γ, Iγ, r_c]/det[γ, Iγ, k] = " << text(found.spin_on_cone) << "\n";
    }
    out << fmt::format("\nabout the principal axes (parameters at their defaults; families linearised at Ω = {:.12g}):\n",
                       found.spin);
    if (found.rotations.empty()) out << "  none (no principal axis holds r_c)\n";
    for (const auto& r : found.rotations) print_rotation_text(r, out);
    out << "\nthrough the initial state:\n";
    if (found.initial) print_rotation_text(*found.initial, out);
    else out << "  none: " << found.initial_note << "\n";
    for (const auto& c : found.lagrange) {
        out << fmt::format("\nLagrange case, sleeping top γ = (0, 0, {}), ω = (0, 0, {}):\n", c.sign, c.spin.get_name());
        out << "  det(λ − J) = λ² (" << text(c.quartic) << ")\n";
        out << "  spectrally stable iff " << text(c.criterion) << " > 0\n";
        if (c.critical_spin) out << "  critical spin |" << c.spin.get_name() << "| = " << text(*c.critical_spin) << "\n";
        else out << "  (no critical spin: the criterion holds at every spin for the default parameters)\n";
    }
}

}  // namespace

void print_rigid_equilibria(const model::Model& model, const rigid::RigidEquilibria& found, const std::string& format,
                            std::ostream& out) {
    if (format == "json") print_rigid_json(found, out);
    else print_rigid_text(model, found, out);
}

}  // namespace eomc::report
