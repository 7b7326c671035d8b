#include "host/simulate/program_stiffness.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include <fmt/format.h>

#include "mechanics/control/control.hpp"

namespace eomc::host {

namespace {

// The method's stability function R(z) = Σ c_k z^k, by Horner's rule.
std::complex<double> stability(const runtime::IntegratorInfo& method, std::complex<double> z) {
    std::complex<double> r = 0.0;
    for (auto c = method.stability_polynomial.rbegin(); c != method.stability_polynomial.rend(); ++c) r = r * z + *c;
    return r;
}

// The largest r with |R(r e^{iθ})| ≤ 1 on [0, r], along the direction of λ (Re λ < 0).
double reach(const runtime::IntegratorInfo& method, std::complex<double> lambda) {
    const std::complex<double> unit = lambda / std::abs(lambda);
    double r = 0.0;
    while (r < 4.0 && std::abs(stability(method, (r + 1e-3) * unit)) <= 1.0) r += 1e-3;
    return r;
}

std::string gains(const model::Program& p) {
    return p.configuration ? fmt::format("alpha = {:g}, beta = {:g}", p.alpha, p.beta)
                           : fmt::format("kappa = {:g}", p.kappa);
}

std::string complex_text(std::complex<double> z) {
    return z.imag() == 0 ? fmt::format("{:.4g}", z.real())
                         : fmt::format("{:.4g} ± {:.4g}i", z.real(), std::abs(z.imag()));
}

}  // namespace

std::vector<std::string> program_stiffness_warnings(const model::Model& model, const runtime::IntegratorInfo& method,
                                                    double step, double t_end) {
    std::vector<std::string> out;
    for (const auto& p : model.programs) {
        // The residual's eigenvalues; the fastest one (largest |λ|) decides.
        const std::vector<std::complex<double>> eigen = mechanics::residual_eigenvalues(p);
        if (eigen.empty()) continue;
        const std::string law = p.configuration ? "omega_ddot + 2 alpha omega_dot + beta^2 omega = 0"
                                                : "phi_dot + kappa phi = 0";
        if (method.fixed_step() && method.has_stability_polynomial()) {
            for (const auto& lambda : eigen) {
                if (std::abs(lambda) == 0.0) continue;
                const std::complex<double> z = step * lambda;
                if (std::abs(stability(method, z)) <= 1.0) continue;
                const double h_max = reach(method, lambda) / std::abs(lambda);
                out.push_back(fmt::format(
                    "the program '{}' with {} makes the closed loop stiff for {} at step {:g}: its residual law {} "
                    "has the eigenvalue {} and h lambda = {} lies outside {}'s stability region "
                    "(|R(h lambda)| = {:.3g} > 1), so the residual will grow instead of decaying; take --step below "
                    "{:.3g}, lower the gains, or use {} (A-stable)",
                    p.name, gains(p), method.name, step, law, complex_text(lambda), complex_text(z), method.name,
                    std::abs(stability(method, z)), h_max,
                    runtime::integrator_list([](const auto& i) { return i.implicit() && i.fixed_step(); }, ", ")));
                break;
            }
        } else if (!method.fixed_step() && method.stability_limited()) {
            const double boundary = method.real_stability_boundary;
            double fastest = 0.0;
            for (const auto& lambda : eigen) fastest = std::max(fastest, std::abs(lambda));
            const double steps = t_end * fastest / boundary;
            if (steps > 1e6)
                out.push_back(fmt::format(
                    "the program '{}' with {} makes the closed loop stiff for {}: its residual law {} has |lambda| = "
                    "{:.4g}, so the step-size control holds h below about {:g}/|lambda| = {:.3g} and the run to "
                    "t = {:g} costs about {:.3g} steps; lower the gains or use {} (A-stable) with a fixed --step",
                    p.name, gains(p), method.name, law, fastest, boundary, boundary / fastest, t_end, steps,
                    runtime::integrator_list([](const auto& i) { return i.implicit() && i.fixed_step(); }, ", ")));
        }
    }
    return out;
}

}  // namespace eomc::host
