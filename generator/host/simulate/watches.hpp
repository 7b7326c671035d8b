// What a run watches at every observed point, besides writing it: the invariants' drift, the
// constraint rows' residuals, the programs' residuals against Erugin's law, the mass matrix's
// singular sets, and whether an explicit method's steps sit at its stability boundary.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "eomc/runtime/registry_info.hpp"
#include "eomc/runtime/state.hpp"
#include "host/kernel_loader.hpp"
#include "host/simulate.hpp"

namespace eomc::host {

// max |I(t) − I(0)| over the observed points; a NaN drift sticks, so it is reported, not hidden.
double track_max(double current_max, double drift);

// The kernel's invariants: I(0) at the first observed point, then the largest drift from it.
class InvariantWatch {
public:
    InvariantWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters);
    void observe(double t, const runtime::State<double>& xs);
    // The state jumps before the next observed point (an impact, a Zeno extrapolation): the change
    // there is counted apart, and the drift is measured from that point on (the integrator's error
    // between jumps, not the physics of the jumps).
    void jump() { jump_pending_ = true; }
    bool started() const { return started_; }
    const std::vector<double>& values() const { return value_; }  // at the last observed point
    std::vector<InvariantReport> reports() const;

private:
    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    std::vector<double> value_, initial_, max_drift_, phase_start_, jump_change_, before_jump_;
    std::size_t jumps_ = 0;
    bool started_ = false, jump_pending_ = false;
};

// The bilateral rows' largest |residual| (f or φ) at the observed points: the state the integration
// carries on from (the drivers project before the observer and the events see a step).
class ConstraintWatch {
public:
    ConstraintWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters);
    void observe(double t, const runtime::State<double>& xs);
    std::vector<ConstraintReport> reports() const;

private:
    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    std::vector<double> residual_, max_residual_;
};

// The stiffness hint for the explicit adaptive methods: a run is stability-limited when its
// accepted steps sit at the method's stability boundary, h |λ| ≈ the boundary for the fastest
// decaying eigenvalue λ of ∂ẋ/∂x, step after step (the test of Hairer's dopri5.f and dop853.f,
// after Shampine; [HW] E. Hairer, G. Wanner, Solving ODEs II, Sect. IV.2). Here λ comes from the
// kernel's Jacobian, sampled every few accepted steps; 15 samples at 70 % of the boundary or more
// make the hint, as 15 detections do in those codes, when they are at least half of the samples
// (a run stability-limited for most of its length).
class StiffnessWatch {
public:
    StiffnessWatch(const runtime::IntegratorInfo& method, bool variational, const KernelLibrary& lib,
                   const KernelLibrary::Parameters& parameters);
    // After each accepted step from t_old to t.
    void step(double t_old, double t, const runtime::State<double>& xs);
    // "" unless the run was stability-limited.
    std::string hint() const;

private:
    const runtime::IntegratorInfo& method_;
    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    double boundary_;
    std::size_t every_ = 1, steps_ = 0, samples_ = 0, at_boundary_ = 0;
    double max_hl_ = 0.0;
    std::vector<double> buffer_;
};

// The sets where the kernel's mass matrix is singular (gimbal lock): after every accepted step
// (and at t0) each indicator s_k must stay clear of zero. Near a set whose indicator divides
// det M to the power m, the smallest eigenvalue of M shrinks like |s_k|^m while the others stay,
// so cond(M) ≈ cond₀ (scale/|s_k|)^m with scale the size of |s_k| away from the set (the largest
// |s_k| seen so far). Past cond(M) = 1/√ε the solve of M u̇ = f keeps fewer than half of the
// digits: the run stops when |s_k| < ε^(1/2m) · scale, or when s_k changed sign between two
// accepted steps (the step went through the set), before any non-finite value is written.
class SingularSetWatch {
public:
    SingularSetWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters);

    // Throws IntegrationError(singular_set) naming the set the state at t has reached.
    void check(double t, const runtime::State<double>& xs);
    // The indicators at x (for the message of a run that failed otherwise), "" when none is near.
    std::string near(double t, const runtime::State<double>& xs);
    // A run that failed otherwise (the step collapsed, a value overflowed) next to the set where a
    // program's control matrix Ā M⁻¹ D is singular (|det| below 1e-6 of its scale, where the
    // control λ ~ 1/det has grown a millionfold) failed because of it: throws that reason instead.
    void fail_if_near_control_set(double t, const runtime::State<double>& xs);

private:
    [[noreturn]] void fail(double t, std::size_t k, double s, double threshold, bool crossed) const;

    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    std::vector<double> value_, previous_, scale_;
    bool seen_ = false;
};

// The kernel's programs (Mei ch. 3): at every observed point the residuals, and their departure
// from Erugin's closed-form law started from the residuals at t0 (runtime/program/erugin.hpp).
class ProgramWatch {
public:
    ProgramWatch(const KernelLibrary& lib, const KernelLibrary::Parameters& parameters);
    void observe(double t, const runtime::State<double>& xs);
    std::vector<ProgramReport> reports() const { return reports_; }

private:
    const KernelLibrary& lib_;
    const KernelLibrary::Parameters& parameters_;
    std::vector<double> value_;
    std::vector<ProgramReport> reports_;
    bool started_ = false;
    double t0_ = 0.0;
};

}  // namespace eomc::host
