#include "report/linearize_printer.hpp"

#include <cmath>
#include <complex>

#include <fmt/format.h>

#include "support/json.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::report {

namespace {

using mechanics::Linearization;

std::string names(const model::Model& model, const std::vector<std::size_t>& indices, const char* suffix,
                  const char* none = "none") {
    std::string out;
    for (std::size_t k : indices) out += (out.empty() ? "" : ", ") + model.coordinates[k].name + suffix;
    return out.empty() ? none : out;
}

std::string complex_text(std::complex<double> v) {
    if (v.imag() == 0.0) return fmt::format("{:.10g}", v.real());
    return fmt::format("{:.10g} {} {:.10g}i", v.real(), v.imag() < 0 ? '-' : '+', std::abs(v.imag()));
}

std::string json_number(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : "null"; }

void print_text(const model::Model& model, const Linearization& lin, const std::string& about, std::ostream& out) {
    out << fmt::format("Linearisation of {} about {}\n", model.name,
                       about == "equilibrium" ? "the equilibrium nearest the initial configuration"
                                              : "the initial state (a steady motion)");
    out << "  operating point:";
    for (std::size_t k = 0; k < lin.q.size(); ++k) out << fmt::format(" {} = {:.12g}", model.coordinates[k].name, lin.q[k]);
    out << ";";
    for (std::size_t k = 0; k < lin.u.size(); ++k) out << fmt::format(" {}_dot = {:.12g}", model.coordinates[k].name, lin.u[k]);
    out << "\n";
    for (std::size_t a = 0; a < lin.multipliers.size(); ++a)
        out << fmt::format("  lambda_{} = {:.12g}\n", model.constraints[a].name, lin.multipliers[a] + 0.0);
    out << fmt::format("  independent coordinates: {}; dependent: {}\n", names(model, lin.independent_coordinates, ""),
                       names(model, lin.dependent_coordinates, ""));
    out << fmt::format("  independent speeds: {}; dependent: {}\n", names(model, lin.independent_speeds, "_dot"),
                       names(model, lin.dependent_speeds, "_dot"));
    out << fmt::format("  ignorable coordinates (absent from the linear equations): {}\n",
                       names(model, lin.ignorable, ""));
    out << "\nd/dt (";
    for (std::size_t i = 0; i < lin.state.size(); ++i) out << (i ? ", " : "") << "δ" << lin.state[i];
    out << ") = A (…), A =\n";
    for (Eigen::Index i = 0; i < lin.A.rows(); ++i) {
        out << "  [";
        for (Eigen::Index j = 0; j < lin.A.cols(); ++j) out << fmt::format("{}{:>14.8g}", j ? " " : "", lin.A(i, j) + 0.0);
        out << " ]\n";
    }
    out << "\nEigenvalues (by decreasing real part, then imaginary part) and modes (largest component 1):\n";
    for (std::size_t j = 0; j < lin.eigenvalues.size(); ++j) {
        out << fmt::format("  λ{} = {}\n     mode:", j + 1, complex_text(lin.eigenvalues[j]));
        for (std::size_t i = 0; i < lin.state.size(); ++i)
            out << fmt::format(" {} {}", lin.state[i], complex_text(lin.modes(Eigen::Index(i), Eigen::Index(j))));
        out << "\n";
    }
    out << fmt::format("\nVerdict: {} ({})\n", mechanics::stability_name(lin.verdict), lin.reason);
}

std::string latex_name(const std::string& name) { return "\\mathrm{" + symbolic::latex_escape(name) + "}"; }

void print_latex(const model::Model& model, const Linearization& lin, std::ostream& out) {
    out << "% eomc linearize " << symbolic::latex_escape(model.name) << "\n\\[\n\\frac{d}{dt}\\begin{pmatrix}";
    for (std::size_t i = 0; i < lin.state.size(); ++i) out << (i ? " \\\\ " : "") << "\\delta " << latex_name(lin.state[i]);
    out << "\\end{pmatrix} = \\begin{pmatrix}\n";
    for (Eigen::Index i = 0; i < lin.A.rows(); ++i) {
        for (Eigen::Index j = 0; j < lin.A.cols(); ++j) out << (j ? " & " : "") << fmt::format("{:.8g}", lin.A(i, j) + 0.0);
        out << (i + 1 < lin.A.rows() ? " \\\\\n" : "\n");
    }
    out << "\\end{pmatrix}\\begin{pmatrix}";
    for (std::size_t i = 0; i < lin.state.size(); ++i) out << (i ? " \\\\ " : "") << "\\delta " << latex_name(lin.state[i]);
    out << "\\end{pmatrix}\n\\]\n\\begin{align*}\n";
    for (std::size_t j = 0; j < lin.eigenvalues.size(); ++j) {
        const auto v = lin.eigenvalues[j];
        out << fmt::format("\\lambda_{{{}}} &= {:.10g}", j + 1, v.real());
        if (v.imag() != 0.0) out << fmt::format(" {} {:.10g}\\,i", v.imag() < 0 ? '-' : '+', std::abs(v.imag()));
        out << (j + 1 < lin.eigenvalues.size() ? " \\\\\n" : "\n");
    }
    out << "\\end{align*}\n";
    out << "Verdict: " << mechanics::stability_name(lin.verdict) << " (" << symbolic::latex_escape(lin.reason) << ").\n";
}

void print_json(const model::Model& model, const Linearization& lin, const std::string& about, std::ostream& out) {
    const auto list = [&](const std::vector<std::size_t>& indices, const char* suffix) {
        std::string s = "[";
        for (std::size_t i = 0; i < indices.size(); ++i)
            s += (i ? ", " : "") + json_string(model.coordinates[indices[i]].name + suffix);
        return s + "]";
    };
    out << "{\"scene\": " << json_string(model.name) << ", \"about\": " << json_string(about) << ", \"q\": {";
    for (std::size_t k = 0; k < lin.q.size(); ++k)
        out << (k ? ", " : "") << json_string(model.coordinates[k].name) << ": " << json_number(lin.q[k]);
    out << "}, \"q_dot\": {";
    for (std::size_t k = 0; k < lin.u.size(); ++k)
        out << (k ? ", " : "") << json_string(model.coordinates[k].name + "_dot") << ": " << json_number(lin.u[k]);
    out << "}, \"multipliers\": {";
    for (std::size_t a = 0; a < lin.multipliers.size(); ++a)
        out << (a ? ", " : "") << json_string("lambda_" + model.constraints[a].name) << ": " << json_number(lin.multipliers[a]);
    out << "},\n \"independent_coordinates\": " << list(lin.independent_coordinates, "")
        << ", \"dependent_coordinates\": " << list(lin.dependent_coordinates, "")
        << ", \"independent_speeds\": " << list(lin.independent_speeds, "_dot")
        << ", \"dependent_speeds\": " << list(lin.dependent_speeds, "_dot") << ", \"ignorable\": " << list(lin.ignorable, "")
        << ",\n \"state\": [";
    for (std::size_t i = 0; i < lin.state.size(); ++i) out << (i ? ", " : "") << json_string(lin.state[i]);
    out << "],\n \"A\": [";
    for (Eigen::Index i = 0; i < lin.A.rows(); ++i) {
        out << (i ? ", [" : "[");
        for (Eigen::Index j = 0; j < lin.A.cols(); ++j) out << (j ? ", " : "") << json_number(lin.A(i, j));
        out << "]";
    }
    out << "],\n \"eigenvalues\": [";
    for (std::size_t j = 0; j < lin.eigenvalues.size(); ++j) {
        out << (j ? ",\n  " : "\n  ") << "{\"re\": " << json_number(lin.eigenvalues[j].real())
            << ", \"im\": " << json_number(lin.eigenvalues[j].imag()) << ", \"mode\": [";
        for (std::size_t i = 0; i < lin.state.size(); ++i) {
            const auto c = lin.modes(Eigen::Index(i), Eigen::Index(j));
            out << (i ? ", " : "") << "[" << json_number(c.real()) << ", " << json_number(c.imag()) << "]";
        }
        out << "]}";
    }
    out << "],\n \"verdict\": " << json_string(mechanics::stability_name(lin.verdict))
        << ", \"reason\": " << json_string(lin.reason) << ", \"tolerance\": " << json_number(lin.tolerance) << "}\n";
}

}  // namespace

void print_linearization(const model::Model& model, const Linearization& lin, const std::string& about,
                         DerivationFormat format, std::ostream& out) {
    if (format == DerivationFormat::json) print_json(model, lin, about, out);
    else if (format == DerivationFormat::latex) print_latex(model, lin, out);
    else print_text(model, lin, about, out);
}

}  // namespace eomc::report
