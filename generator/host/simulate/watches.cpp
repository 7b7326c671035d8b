// The watches of a run (watches.hpp).
#include "host/simulate/watches.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/program/erugin.hpp"
#include "host/simulate/output.hpp"

namespace eomc::host {

using runtime::State;

double track_max(double current_max, double drift) {
    if (std::isnan(current_max)) return current_max;
    return std::isnan(drift) || drift > current_max ? drift : current_max;
}

InvariantWatch::InvariantWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters)
    : lib_(lib), parameters_(parameters), value_(lib.invariant_names().size()), initial_(value_.size()),
      max_drift_(value_.size(), 0.0), phase_start_(value_.size()), jump_change_(value_.size(), 0.0) {}

void InvariantWatch::observe(double t, const State<double>& xs) {
    if (jump_pending_) before_jump_ = value_;  // the last value before the jump (no copy on other steps)
    lib_.invariants(t, xs.data(), value_.data(), parameters_);
    if (!started_) initial_ = phase_start_ = value_, started_ = true;
    if (jump_pending_) {
        for (std::size_t i = 0; i < value_.size(); ++i) jump_change_[i] += value_[i] - before_jump_[i];
        phase_start_ = value_;
        ++jumps_;
        jump_pending_ = false;
    }
    for (std::size_t i = 0; i < value_.size(); ++i)
        max_drift_[i] = track_max(max_drift_[i], std::abs(value_[i] - phase_start_[i]));
}

std::vector<InvariantReport> InvariantWatch::reports() const {
    std::vector<InvariantReport> out;
    for (std::size_t i = 0; i < value_.size(); ++i)
        out.push_back({lib_.invariant_names()[i], initial_[i], value_[i], max_drift_[i], jumps_, jump_change_[i]});
    return out;
}

ConstraintWatch::ConstraintWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters)
    : lib_(lib), parameters_(parameters), residual_(lib.constraint_names().size()),
      max_residual_(residual_.size(), 0.0) {}

void ConstraintWatch::observe(double t, const State<double>& xs) {
    if (residual_.empty()) return;
    lib_.constraint_residuals(t, xs.data(), residual_.data(), parameters_);
    for (std::size_t i = 0; i < residual_.size(); ++i)
        max_residual_[i] = track_max(max_residual_[i], std::abs(residual_[i]));
}

std::vector<ConstraintReport> ConstraintWatch::reports() const {
    std::vector<ConstraintReport> out;
    for (std::size_t i = 0; i < residual_.size(); ++i) out.push_back({lib_.constraint_names()[i], max_residual_[i]});
    return out;
}

StiffnessWatch::StiffnessWatch(const runtime::IntegratorInfo& method, bool variational, const KernelLibrary& lib,
                               const KernelLibrary::Parameters& parameters)
    : method_(method), lib_(lib), parameters_(parameters),
      boundary_(method.fixed_step() ? 0.0 : method.real_stability_boundary) {
    if (!lib.has_jacobian() || variational) boundary_ = 0.0;
    const std::size_t n = lib.state_names().size();
    every_ = std::max<std::size_t>(1, n * n / 16);  // the O(n³) eigenvalues cost about what n² / 16 steps do
    buffer_.resize(n * n);
}

void StiffnessWatch::step(double t_old, double t, const State<double>& xs) {
    if (boundary_ <= 0.0 || ++steps_ % every_ != 0) return;
    const Eigen::Index n = Eigen::Index(xs.size());
    lib_.jacobian(t, xs.data(), buffer_.data(), parameters_);
    const Eigen::MatrixXd J =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(buffer_.data(), n, n);
    if (!J.allFinite()) return;
    const Eigen::EigenSolver<Eigen::MatrixXd> eig(J, false);
    double rho = 0.0;  // the largest |λ| with Re λ < 0
    for (Eigen::Index i = 0; i < n; ++i)
        if (eig.eigenvalues()[i].real() < 0.0) rho = std::max(rho, std::abs(eig.eigenvalues()[i]));
    ++samples_;
    const double hl = std::abs(t - t_old) * rho;
    if (hl >= 0.7 * boundary_) {
        ++at_boundary_;
        max_hl_ = std::max(max_hl_, hl);
    }
}

std::string StiffnessWatch::hint() const {
    if (at_boundary_ < 15 || 2 * at_boundary_ < samples_) return "";
    const std::string stiff_methods = runtime::integrator_list(
        [](const runtime::IntegratorInfo& i) { return i.implicit() && !i.fixed_step(); }, " or ");
    return fmt::format("{} of {} sampled steps sit at {}'s stability boundary (h |λ| up to {:.3g}, boundary {:.3g}): "
                       "the system is stiff and the step is limited by stability, not accuracy; try --integrator {}",
                       at_boundary_, samples_, method_.name, max_hl_, boundary_, stiff_methods);
}

SingularSetWatch::SingularSetWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters)
    : lib_(lib), parameters_(parameters), value_(lib.singular_set_names().size()), previous_(value_.size(), 0.0),
      scale_(value_.size(), 0.0) {}

void SingularSetWatch::check(double t, const State<double>& xs) {
    if (value_.empty()) return;
    lib_.singular_sets(t, xs.data(), value_.data(), parameters_);
    for (std::size_t k = 0; k < value_.size(); ++k) {
        const double s = value_[k];
        const int order = std::max(1, lib_.singular_set_orders()[k]);
        const double threshold =
            std::pow(std::numeric_limits<double>::epsilon(), 0.5 / order) * std::max(scale_[k], std::abs(s));
        const bool crossed = seen_ && std::isfinite(s) && s * previous_[k] < 0.0;
        if (!std::isfinite(s) || std::abs(s) <= threshold || crossed) fail(t, k, s, threshold, crossed);
        scale_[k] = std::max(scale_[k], std::abs(s));
        previous_[k] = s;
    }
    seen_ = true;
}

std::string SingularSetWatch::near(double t, const State<double>& xs) {
    if (value_.empty()) return "";
    lib_.singular_sets(t, xs.data(), value_.data(), parameters_);
    std::string out;
    for (std::size_t k = 0; k < value_.size(); ++k)
        if (scale_[k] > 0 && std::abs(value_[k]) < 1e-2 * scale_[k])
            out += fmt::format("; the last accepted state is near the singular set {} of the mass matrix "
                               "(indicator {:.3g}, {:.3g} of its scale)",
                               lib_.singular_set_names()[k], value_[k], std::abs(value_[k]) / scale_[k]);
    return out;
}

void SingularSetWatch::fail_if_near_control_set(double t, const State<double>& xs) {
    if (value_.empty()) return;
    lib_.singular_sets(t, xs.data(), value_.data(), parameters_);
    for (std::size_t k = 0; k < value_.size(); ++k)
        if (lib_.singular_set_names()[k].rfind("det(A M^-1 D)", 0) == 0 && scale_[k] > 0 &&
            std::abs(value_[k]) < 1e-6 * scale_[k])
            fail(t, k, value_[k], 1e-6 * scale_[k], false);
}

void SingularSetWatch::fail(double t, std::size_t k, double s, double threshold, bool crossed) const {
    const std::string& name = lib_.singular_set_names()[k];
    if (name.rfind("det(A M^-1 D)", 0) == 0)  // a program's control matrix (Mei ch. 3), not M
        throw runtime::IntegrationError(
            runtime::IntegrationError::Kind::singular_set, t,
            fmt::format("the programs cannot be realised past t = {}: the control matrix A M^-1 D became singular "
                        "({}); no control in the given directions keeps the programs there (eomc control prints "
                        "the singular set)",
                        number(t),
                        crossed ? fmt::format("det changed sign from {:.3g} to {:.3g} in one step", previous_[k], s)
                                : fmt::format("|det| = {:.3g} fell below {:.3g} of its scale {:.3g}",
                                              std::abs(s), threshold, std::max(scale_[k], std::abs(s)))));
    throw runtime::IntegrationError(
        runtime::IntegrationError::Kind::singular_set, t,
        fmt::format("the state reached the singular set {} of the mass matrix ({}: det M = 0 there, the "
                    "coordinates fail) at t = {}: {}; use coordinates without this singularity (or start away "
                    "from it)",
                    name,
                    name.find("sin(") != std::string::npos || name.find("cos(") != std::string::npos
                        ? "gimbal lock"
                        : "a coordinate singularity",
                    number(t),
                    crossed ? fmt::format("the indicator changed sign from {:.3g} to {:.3g} in one step",
                                          previous_[k], s)
                            : fmt::format("|{}| = {:.3g} fell below {:.3g} = eps^(1/{}) of its scale {:.3g}, where "
                                          "cond(M) would pass 1/sqrt(eps)",
                                          name.substr(0, name.rfind(" = 0")), std::abs(s), threshold, 2 * std::max(1, lib_.singular_set_orders()[k]),
                                          std::max(scale_[k], std::abs(s)))));
}

ProgramWatch::ProgramWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters)
    : lib_(lib), parameters_(parameters), value_(2 * lib.program_names().size()) {
    for (std::size_t i = 0; i < lib.program_names().size(); ++i) {
        ProgramReport r;
        r.name = lib.program_names()[i];
        const auto& law = lib.program_laws()[i];
        const bool configuration = law[0] != 0.0, open = law[1] == 0.0 && law[2] == 0.0 && law[3] == 0.0;
        r.law = open ? (configuration ? "omega_ddot = 0 (open loop)" : "phi_dot = 0 (open loop)")
                : configuration ? fmt::format("omega_ddot + {} omega_dot + {} omega = 0", number(2 * law[1]),
                                              number(law[2] * law[2]))
                                : fmt::format("phi_dot + {} phi = 0", number(law[3]));
        reports_.push_back(std::move(r));
    }
}

void ProgramWatch::observe(double t, const State<double>& xs) {
    if (reports_.empty()) return;
    lib_.program_residuals(t, xs.data(), value_.data(), parameters_);
    if (!started_) t0_ = t;
    for (std::size_t i = 0; i < reports_.size(); ++i) {
        ProgramReport& r = reports_[i];
        const auto& law = lib_.program_laws()[i];
        const double w = value_[2 * i], wd = value_[2 * i + 1];
        if (!started_) r.initial = w, r.initial_rate = wd;
        const double expected =
            law[0] != 0.0 ? runtime::program::erugin_configuration(law[1], law[2], r.initial, r.initial_rate, t - t0_)
                          : runtime::program::erugin_phase(law[3], r.initial, t - t0_);
        r.final = w;
        r.max_abs_residual = track_max(r.max_abs_residual, std::abs(w));
        r.max_departure = track_max(r.max_departure, std::abs(w - expected));
    }
    started_ = true;
}

}  // namespace eomc::host
