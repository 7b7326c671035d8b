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
