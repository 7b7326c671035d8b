// eomc bench: the work-precision driver. `eomc bench` compiles this file (embedded in the
// generator) with a kernel.hpp and a bench_config.hpp it generates; it is plain C++ and the
// tests compile it on its own against a hand-written kernel (tests/bench/driver).
//
// For every method and setting (a tolerance for adaptive methods, a step count for fixed-step
// ones) it integrates the kernel from its initial state over [0, t_end], once observed (every
// accepted step: the invariants' drift) and then timed (median over repetitions), and writes
// one CSV row per run to standard output. Lines starting with '#' are notes. Ours and
// Boost.Odeint's steppers see the same kernel through the same counting wrapper.
//
// bench_config.hpp provides, in namespace eomc::bench:
//   using Model = eomc::models::<Struct>;                      the kernel
//   inline constexpr bool autonomous;                          the equations do not depend on t
//   inline constexpr bool has_reference;                       a closed-form solution exists
//   template <class S> void reference(S t, S* out, const Model::Parameters& p);
//   inline constexpr const char* reference_source;             where the closed form comes from
//
// Formulations (`eomc bench` on an [orbit] or a [rigid_body] scene) run one such program per
// formulation and judge them all by a few columns at t_end against one reference formulation's:
//   --judge A,B,...               the judged columns: each a state component's name, else an
//                                 output's (default x,y,z: an orbit's Cartesian position, the state
//                                 of Cowell's, outputs of the element formulations; a rigid body's
//                                 p,q,r,gamma1,gamma2,gamma3)
//   --reference-only              (the reference kernel) print the judged columns of a float128 run and exit
//   --reference-values V1,...     the error of a run is the Euclidean distance of its judged columns
//                                 from these
//   --drift-invariants A,...      the drift is measured on these invariants only (default: all)
//   --budget-s S                  a run (the reference's too) stops once its pace projects it past S
//                                 seconds (default 3600)

#include "bench_config.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <unistd.h>

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/integrate/integrate_n_steps.hpp>
#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_mclachlan.hpp>

#include <eomc/runtime/float128.hpp>
#include <eomc/runtime/kernel.hpp>
#include <eomc/runtime/runtime.hpp>

namespace {

namespace rt = eomc::runtime;
namespace odeint = boost::numeric::odeint;
using K = eomc::bench::Model;
using P = K::Parameters;
using Clock = std::chrono::steady_clock;
using State = rt::State<double>;
using Q = rt::float128;
constexpr std::size_t n_state = K::n_state, n_q = K::n_coordinates;

// The kernel's contract (runtime/kernel.hpp): the base for double and for float128 (the
// reference runs), and which optional parts it has.
static_assert(rt::Kernel<K> && rt::Kernel<K, Q>, "bench driver: the kernel lacks a part every eomc kernel has");
// A separable system also gives q'' = a(t, q) alone: the splitting methods need it.
constexpr bool separable = rt::SeparableKernel<K>;
// Kernels that edit their state after a step have project(t, x, p) (a unit quaternion put back
// on |e| = 1, Encke's rectification); the runtime's drivers call it through the system
// (runtime::Projecting) after every accepted step.
constexpr bool projects = rt::ProjectingKernel<K>;

// --- the judged columns ----------------------------------------------------------------------------

constexpr bool same_name(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) ++a, ++b;
  return *a == *b;
}

template <std::size_t N>
int index_of(const std::array<const char*, N>& names, const std::string& name) {
  for (std::size_t i = 0; i < N; ++i)
    if (same_name(names[i], name.c_str())) return static_cast<int>(i);
  return -1;
}

// A column a run is judged by at t_end: a state component, or else an output.
struct Column {
  bool in_state;
  int index;
};

template <class M = K>
int output_index(const std::string& name) {
  if constexpr (rt::KernelWithOutputs<M, Q>)
    return index_of(M::output_names, name);
  else
    return -1;
}

// The judged values at (t, x), evaluated in float128 from the given state (so that no round-off of
// a conversion enters the error).
template <class M = K>
std::vector<Q> judged_values(Q t, const Q* x, const std::vector<Column>& columns, const typename M::Parameters& p) {
  std::vector<Q> r;
  if constexpr (rt::KernelWithOutputs<M, Q>) {
    std::array<Q, (M::n_outputs > 0 ? M::n_outputs : 1)> out{};
    const bool need_outputs = std::any_of(columns.begin(), columns.end(), [](const Column& c) { return !c.in_state; });
    if (need_outputs) M::outputs(t, x, out.data(), p);
    for (const Column& c : columns) r.push_back(c.in_state ? x[c.index] : out[c.index]);
  } else {
    (void)t, (void)p;
    for (const Column& c : columns) r.push_back(x[c.index]);
  }
  return r;
}

// --- settings ----------------------------------------------------------------------------------

struct Options {
  double t_end = 1.0;
  std::vector<std::string> methods;  // empty: all
  std::vector<double> tolerances;    // rtol = atol; empty: 1e-3 .. 1e-15 in half decades
  std::vector<double> steps;         // step counts over [0, t_end]; empty: 16 .. 2^20 in half octaves
  double min_time = 0.02;            // timed repetitions add up to at least this many seconds ...
  int repeats = 3;                   // ... and are at least this many
  double max_run_time = 2.0;         // a fixed-step sweep stops once one run takes longer
  double budget_s = 3600.0;          // a run (the reference's too) stops once its pace projects it past this
  double reference_tolerance = 1e-26;
  bool reference_only = false;                   // print the reference's judged values and exit
  std::vector<std::string> judged{"x", "y", "z"};  // the columns compared at t_end
  std::optional<std::vector<Q>> reference_values;  // judge runs by their judged columns against these
  std::vector<std::string> drift_invariants;     // the invariants whose drift is measured; empty: all
};

[[noreturn]] void usage(const std::string& message) {
  std::fprintf(stderr, "bench driver: %s\n", message.c_str());
  std::exit(2);
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    if (comma > start) out.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

double number(const std::string& text, const char* option) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || !(v > 0))
    usage(std::string(option) + ": '" + text + "' is not a positive number");
  return v;
}

// V1,...,Vn in full float128 precision (as --reference-only prints them).
std::vector<Q> value_list(const std::string& text) {
  std::vector<Q> r;
  for (const std::string& item : split(text)) {
    bool ok = false;
    r.push_back(rt::float128_from_string(item, &ok));
    if (!ok || !isfinite(r.back())) usage("--reference-values: '" + item + "' is not a number");
  }
  return r;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--reference-only") {
      o.reference_only = true;
      continue;
    }
    if (i + 1 >= argc) usage("missing value after " + arg);
    const std::string value = argv[++i];
    if (arg == "--t-end") o.t_end = number(value, "--t-end");
    else if (arg == "--methods") o.methods = split(value);
    else if (arg == "--tolerances") for (const auto& v : split(value)) o.tolerances.push_back(number(v, "--tolerances"));
    else if (arg == "--steps") for (const auto& v : split(value)) o.steps.push_back(std::round(number(v, "--steps")));
    else if (arg == "--min-time") o.min_time = number(value, "--min-time");
    else if (arg == "--repeats") o.repeats = static_cast<int>(number(value, "--repeats"));
    else if (arg == "--max-run-time") o.max_run_time = number(value, "--max-run-time");
    else if (arg == "--budget-s") o.budget_s = number(value, "--budget-s");
    else if (arg == "--reference-tolerance") o.reference_tolerance = number(value, "--reference-tolerance");
    else if (arg == "--reference-values") o.reference_values = value_list(value);
    else if (arg == "--judge") o.judged = split(value);
    else if (arg == "--drift-invariants") o.drift_invariants = split(value);
    else usage("unknown option " + arg);
  }
  if (o.judged.empty()) usage("--judge: no column");
  if (o.reference_values && o.reference_values->size() != o.judged.size())
    usage("--reference-values: " + std::to_string(o.reference_values->size()) + " values for " +
          std::to_string(o.judged.size()) + " judged columns");
  if (o.tolerances.empty())
    for (int k = 6; k <= 30; ++k) o.tolerances.push_back(std::pow(10.0, -k / 2.0));
  if (o.steps.empty())
    for (int k = 8; k <= 40; ++k) o.steps.push_back(std::round(std::pow(2.0, k / 2.0)));
  return o;
}

// --- the problem -------------------------------------------------------------------------------

const P parameters{};

State initial_state() { return State(K::initial_state.begin(), K::initial_state.end()); }

// Which invariants the drift is measured on (--drift-invariants; default all).
std::array<bool, K::n_invariants> drift_measured = [] {
  std::array<bool, K::n_invariants> all{};
  all.fill(true);
  return all;
}();

// Largest change of any measured invariant along the run, relative to its initial value (absolute when
// that is 0), sampled at every point the observer sees.
class DriftMeter {
 public:
  void sample(double t, const double* x) {
    if constexpr (K::n_invariants > 0) {
      std::array<double, K::n_invariants> v{};
      K::invariants(t, x, v.data(), parameters);
      if (first_) {
        initial_ = v;
        first_ = false;
        return;
      }
      for (std::size_t k = 0; k < v.size(); ++k) {
        if (!drift_measured[k]) continue;
        const double scale = initial_[k] != 0.0 ? std::abs(initial_[k]) : 1.0;
        const double d = std::abs(v[k] - initial_[k]) / scale;
        if (!(d <= max_)) max_ = d;  // a NaN sticks
      }
    } else {
      (void)t;
      (void)x;
    }
  }
  double max() const { return max_; }

 private:
  std::array<double, K::n_invariants> initial_{};
  bool first_ = true;
  double max_ = 0.0;
};

// One run: final state and work counters.
struct Outcome {
  State x;
  double drift = 0.0;
  std::size_t evals = 0, steps = 0, rejected = 0;
};

// The time one run may take (--budget-s), judged from its pace: every 1024 right-hand sides, once
// it has run 2 s, the time so far × t_end / t. A run past it stops with the projection, so that
// `--t-end 1e300` is refused in seconds rather than computed for hours. Every system below ticks
// it; a run begins it.
class RunBudget {
 public:
  double limit_s = 3600.0;

  void begin(double t_end) {
    start_ = Clock::now();
    t_end_ = t_end;
    calls_ = 0;
  }
  void tick(double t) {
    if ((++calls_ & 1023u) != 0) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    if (elapsed < 2.0) return;
    const double projected = t > 0 ? elapsed * t_end_ / t : std::numeric_limits<double>::infinity();
    if (projected <= limit_s) return;
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "at its pace over the first %.3g s (to t = %.6g of t_end = %.6g) the run would take about %.3g s, "
                  "more than the budget of %.6g s (--budget-s)",
                  elapsed, t, t_end_, projected, limit_s);
    throw OverBudget(buf);
  }

  struct OverBudget : std::runtime_error {
    using std::runtime_error::runtime_error;
  };

 private:
  Clock::time_point start_ = Clock::now();
  double t_end_ = 1.0;
  unsigned calls_ = 0;
};
RunBudget run_budget;

// The systems, each counting its calls. (A template only so that project() can be constrained.)
template <class M = K>
struct CountedRhsT {
  std::size_t* count;
  void operator()(double t, const State& x, State& dxdt) const {
    ++*count;
    run_budget.tick(t);
    M::rhs(t, x.data(), dxdt.data(), parameters);
  }
  void project(double t, State& x) const
    requires rt::ProjectingKernel<M>
  {
    M::project(t, x.data(), parameters);
  }
};
using CountedRhs = CountedRhsT<>;

// The same with the kernel's Jacobian for the implicit methods (runtime::HasJacobian); a kernel
// generated without one leaves them to finite differences.
template <class M = K>
struct CountedJacobianRhsT : CountedRhsT<M> {
  void jacobian(double t, const State& x, Eigen::MatrixXd& J) const
    requires rt::KernelWithJacobian<M>
  {
    std::array<double, std::size_t(M::n_state) * std::size_t(M::n_state)> out{};
    M::jacobian(t, x.data(), out.data(), parameters);
    for (int i = 0; i < M::n_state; ++i)
      for (int j = 0; j < M::n_state; ++j) J(i, j) = out[std::size_t(i * M::n_state + j)];
  }
};
using CountedJacobianRhs = CountedJacobianRhsT<>;

template <class OState>
struct OdeintRhs {
  std::size_t* count;
  void operator()(const OState& x, OState& dxdt, double t) const {
    ++*count;
    run_budget.tick(t);
    K::rhs(t, x.data(), dxdt.data(), parameters);
  }
};

// --- ours ----------------------------------------------------------------------------------------

template <class Stepper>
Stepper make_adaptive() {
  if constexpr (std::is_same_v<Stepper, rt::Dop853<double>>)
    return Stepper(Stepper::default_settings(), false);  // no dense output: integrate_adaptive needs none
  else
    return Stepper();
}

template <class Stepper, class Sys = CountedRhs>
Outcome ours_adaptive(double t_end, double tol, bool observe) {
  Outcome o;
  o.x = initial_state();
  Stepper stepper = make_adaptive<Stepper>();
  Sys sys{{&o.evals}};
  DriftMeter drift;
  const rt::Tolerances tolerances{tol, tol};
  const rt::Stats s =
      observe ? rt::integrate_adaptive(stepper, sys, o.x, 0.0, t_end, 0.0, tolerances,
                                       [&](double t, const State& x) { drift.sample(t, x.data()); })
              : rt::integrate_adaptive(stepper, sys, o.x, 0.0, t_end, 0.0, tolerances, [](double, const State&) {});
  o.drift = drift.max();
  o.steps = s.accepted;
  o.rejected = s.rejected;
  return o;
}

rt::Limits fixed_limits(double steps) {
  rt::Limits limits;
  limits.max_steps = static_cast<std::size_t>(steps) + 2;
  return limits;
}

template <class Stepper>
Outcome ours_fixed(double t_end, double steps, bool observe) {
  Outcome o;
  o.x = initial_state();
  Stepper stepper;
  CountedRhs sys{&o.evals};
  DriftMeter drift;
  const double h = t_end / steps;
  const rt::Stats s =
      observe ? rt::integrate_fixed(stepper, sys, o.x, 0.0, t_end, h,
                                    [&](double t, const State& x) { drift.sample(t, x.data()); }, fixed_limits(steps))
              : rt::integrate_fixed(stepper, sys, o.x, 0.0, t_end, h, [](double, const State&) {}, fixed_limits(steps));
  o.drift = drift.max();
  o.steps = s.accepted;
  return o;
}

// Splitting methods step x = (q, q_dot) with the acceleration alone. (M is K, made a template
// parameter so that a kernel without acceleration() compiles: the branch is then discarded.)
template <class Stepper, class M = K>
Outcome ours_splitting(double t_end, double steps, bool observe) {
  Outcome o;
  o.x = initial_state();
  if constexpr (rt::SeparableKernel<M>) {
    Stepper stepper;
    std::size_t* count = &o.evals;
    auto acc = [count](double t, const State& q, State& a) {
      ++*count;
      run_budget.tick(t);
      M::acceleration(t, q.data(), a.data(), parameters);
    };
    DriftMeter drift;
    const double h = t_end / steps;
    const rt::Stats s =
        observe ? rt::integrate_fixed(stepper, acc, o.x, 0.0, t_end, h,
                                      [&](double t, const State& x) { drift.sample(t, x.data()); }, fixed_limits(steps))
                : rt::integrate_fixed(stepper, acc, o.x, 0.0, t_end, h, [](double, const State&) {}, fixed_limits(steps));
    o.drift = drift.max();
    o.steps = s.accepted;
  } else {
    (void)t_end, (void)steps, (void)observe;
    throw std::logic_error("splitting method on a kernel without acceleration()");
  }
  return o;
}

// --- Boost.Odeint --------------------------------------------------------------------------------

// odeint's state: std::vector, the container our runtime steps, so that the comparison is of the
// integrators; -DEOMC_BENCH_ODEINT_ARRAY (`eomc bench --odeint-state array`) gives odeint a
// std::array of the kernel's size instead, its fastest form for a small fixed-size system.
#ifdef EOMC_BENCH_ODEINT_ARRAY
using OState = std::array<double, n_state>;
#else
using OState = std::vector<double>;
#endif

template <class OS = OState>
OS odeint_state(const State& x) {
  OS out{};
  if constexpr (std::is_same_v<OS, State>) out.resize(x.size());
  std::copy(x.begin(), x.end(), out.begin());
  return out;
}

// Forwards try_step to a controlled stepper and counts the failed attempts, so that odeint's own
// integrate_adaptive drives it (it takes the stepper by value: this holds a pointer).
template <class Controlled>
struct CountRejections {
  using stepper_category = odeint::controlled_stepper_tag;
  Controlled* stepper;
  std::size_t* rejected;
  template <class Sys>
  odeint::controlled_step_result try_step(Sys system, OState& x, double& t, double& dt) {
    const odeint::controlled_step_result r = stepper->try_step(system, x, t, dt);
    if (r == odeint::fail) ++*rejected;
    return r;
  }
};

// The first step as our runtime chooses it (one counted system call), so that both libraries
// start alike.
double first_step(double t_end, double tol, int error_order, std::size_t& evals) {
  CountedRhs sys{&evals};
  const State x = initial_state();
  State f(n_state);
  sys(0.0, x, f);
  std::size_t probes = 0;  // the counted system already counts the probe initial_step makes
  return rt::initial_step(sys, 0.0, x, f, 1.0, error_order, rt::Tolerances{tol, tol}, t_end, probes);
}

template <class Make>
Outcome odeint_adaptive(Make make, int error_order, double t_end, double tol, bool observe) {
  Outcome o;
  auto controlled = make(tol);
  CountRejections<decltype(controlled)> counted{&controlled, &o.rejected};
  OState x = odeint_state(initial_state());
  const double dt = first_step(t_end, tol, error_order, o.evals);
  DriftMeter drift;
  OdeintRhs<OState> sys{&o.evals};
  std::size_t observed = 0;
  if (observe)
    odeint::integrate_adaptive(counted, sys, x, 0.0, t_end, dt, [&](const OState& xs, double t) {
      drift.sample(t, xs.data());
      ++observed;
    });
  else
    odeint::integrate_adaptive(counted, sys, x, 0.0, t_end, dt);
  // The observer sees the start of every step and the end: accepted steps = calls - 1. Without it,
  // the count is the same run's (the integration is deterministic).
  o.steps = observed > 0 ? observed - 1 : 0;
  o.x.assign(x.begin(), x.end());
  o.drift = drift.max();
  return o;
}

template <class M = K>
Outcome odeint_sb3a(double t_end, double steps, bool observe) {
  Outcome o;
  if constexpr (rt::SeparableKernel<M>) {
    using Coor = std::vector<double>;
    std::pair<Coor, Coor> x{Coor(K::initial_state.begin(), K::initial_state.begin() + n_q),
                            Coor(K::initial_state.begin() + n_q, K::initial_state.end())};
    std::size_t* count = &o.evals;
    // odeint's Nystroem steppers pass no time to the force: autonomous systems only (checked by
    // the caller).
    auto force = [count](const Coor& q, Coor& a) {
      ++*count;
      M::acceleration(0.0, q.data(), a.data(), parameters);
    };
    odeint::symplectic_rkn_sb3a_mclachlan<Coor> stepper;
    const auto n = static_cast<std::size_t>(steps);
    DriftMeter drift;
    State joined(n_state);
    if (observe)
      odeint::integrate_n_steps(stepper, force, x, 0.0, t_end / steps, n, [&](const std::pair<Coor, Coor>& s, double t) {
        std::copy(s.first.begin(), s.first.end(), joined.begin());
        std::copy(s.second.begin(), s.second.end(), joined.begin() + n_q);
        drift.sample(t, joined.data());
      });
    else
      odeint::integrate_n_steps(stepper, force, x, 0.0, t_end / steps, n);
    o.x = State(n_state);
    std::copy(x.first.begin(), x.first.end(), o.x.begin());
    std::copy(x.second.begin(), x.second.end(), o.x.begin() + n_q);
    o.steps = n;
    o.drift = drift.max();
  } else {
    (void)t_end, (void)steps, (void)observe;
    throw std::logic_error("sb3a on a kernel without acceleration()");
  }
  return o;
}

// --- the methods -----------------------------------------------------------------------------------

enum class Kind { adaptive, fixed };

struct Method {
  const char* name;  // a string literal (the registry's names are literals too)
  const char* library;
  Kind kind;
  bool needs_acceleration;
  std::function<Outcome(double t_end, double setting, bool observe)> run;
};

// Ours: every method of the runtime's registry (eomc/runtime/registry.hpp), in its order, so that
// a new integrator there is benchmarked without a change here.
void add_ours(std::vector<Method>& m) {
  for (const rt::IntegratorInfo& info : rt::integrator_infos)
    rt::visit_integrator<double>(info.name, [&](auto tag) {
      using Tag = decltype(tag);
      using Stepper = typename Tag::type;
      if constexpr (Tag::info.uses_jacobian)
        m.push_back({Tag::info.name.data(), "eomc", Kind::adaptive, false, ours_adaptive<Stepper, CountedJacobianRhs>});
      else if constexpr (Tag::info.kind == rt::IntegratorKind::adaptive)
        m.push_back({Tag::info.name.data(), "eomc", Kind::adaptive, false, ours_adaptive<Stepper>});
      else if constexpr (Tag::info.needs_separable)
        m.push_back({Tag::info.name.data(), "eomc", Kind::fixed, true, ours_splitting<Stepper>});
      else
        m.push_back({Tag::info.name.data(), "eomc", Kind::fixed, false, ours_fixed<Stepper>});
    });
}

std::vector<Method> all_methods() {
  std::vector<Method> m;
  add_ours(m);
  // Boost.Odeint's, under their own names.
  std::vector<Method> odeint_methods{
      {"runge_kutta_dopri5", "odeint", Kind::adaptive, false,
       [](double t_end, double tol, bool observe) {
         return odeint_adaptive([](double e) { return odeint::make_controlled(e, e, odeint::runge_kutta_dopri5<OState>()); },
                                4, t_end, tol, observe);
       }},
      {"runge_kutta_fehlberg78", "odeint", Kind::adaptive, false,
       [](double t_end, double tol, bool observe) {
         return odeint_adaptive(
             [](double e) { return odeint::make_controlled(e, e, odeint::runge_kutta_fehlberg78<OState>()); }, 7, t_end,
             tol, observe);
       }},
      {"bulirsch_stoer", "odeint", Kind::adaptive, false,
       [](double t_end, double tol, bool observe) {
         return odeint_adaptive([](double e) { return odeint::bulirsch_stoer<OState>(e, e); }, 7, t_end, tol, observe);
       }},
      {"symplectic_rkn_sb3a_mclachlan", "odeint", Kind::fixed, true, odeint_sb3a<>},
  };
  m.insert(m.end(), odeint_methods.begin(), odeint_methods.end());
  return m;
}

// --- reference --------------------------------------------------------------------------------------

struct Reference {
  std::array<Q, n_state> x{};
  std::string description;
};

// The kernel as a system of the runtime (its drivers take the system by reference: copy it into a variable).
constexpr auto float128_rhs = [](Q t, const rt::State<Q>& x, rt::State<Q>& dxdt) {
  run_budget.tick(static_cast<double>(t));
  K::rhs(t, x.data(), dxdt.data(), parameters);
};

rt::Limits float128_limits() {
  rt::Limits limits;
  limits.max_steps = 100'000'000;
  return limits;
}

std::array<Q, n_state> float128_run(double t_end, double tol) {
  run_budget.begin(t_end);
  rt::State<Q> x(K::initial_state.begin(), K::initial_state.end());
  rt::Dop853<Q> stepper(rt::Dop853<Q>::default_settings(), false);
  auto sys = float128_rhs;
  rt::integrate_adaptive(stepper, sys, x, Q(0), Q(t_end), Q(0), rt::Tolerances{tol, tol},
                         [](Q, const rt::State<Q>&) {}, float128_limits());
  std::array<Q, n_state> out{};
  std::copy(x.begin(), x.end(), out.begin());
  return out;
}

Reference make_reference(const Options& o) {
  Reference r;
  char buf[256];
  if constexpr (eomc::bench::has_reference) {
    eomc::bench::reference<Q>(Q(o.t_end), r.x.data(), parameters);
    std::snprintf(buf, sizeof buf, "closed form (%s), evaluated in float128", eomc::bench::reference_source);
  } else {
    // A float128 DOP853 run far tighter than any double run, checked against one 1000 times looser.
    r.x = float128_run(o.t_end, o.reference_tolerance);
    const auto check = float128_run(o.t_end, o.reference_tolerance * 1e3);
    Q diff = Q(0);
    for (std::size_t i = 0; i < n_state; ++i) diff = std::max(diff, abs(check[i] - r.x[i]));
    std::snprintf(buf, sizeof buf,
                  "float128 DOP853 at rtol = atol = %.0e (a run at %.0e differs by %.2g, an upper bound on its error)",
                  o.reference_tolerance, o.reference_tolerance * 1e3, static_cast<double>(diff));
  }
  r.description = buf;
  return r;
}

double error_of(const State& x, const Reference& ref) {
  double e = 0.0;
  for (std::size_t i = 0; i < n_state; ++i) {
    const double d = static_cast<double>(abs(Q(x[i]) - ref.x[i]));
    if (!(d <= e)) e = d;  // a NaN sticks
  }
  return e;
}

// --- the formulations' reference ------------------------------------------------------------------------------

// float128_run, but stopped by a terminal event (an orbit's re_entry, in its direction), which the
// runtime locates on DOP853's dense output (runtime/events.hpp): an orbit that does not last to
// t_end has no position there to compare, and runs through the Earth judge nothing.
template <class M = K>
std::array<Q, n_state> float128_run_unless_terminal(double t_end, double tol) {
  if constexpr (rt::EventKernel<M, Q>) {
    run_budget.begin(t_end);
    rt::State<Q> x(M::initial_state.begin(), M::initial_state.end());
    rt::Dop853<Q> stepper(rt::Dop853<Q>::default_settings(), true);  // the locator needs dense output
    std::vector<rt::EventSpec> specs;
    for (std::size_t i = 0; i < M::event_names.size(); ++i)
      specs.push_back({static_cast<rt::EventDirection>(M::event_directions[i]), M::event_terminal[i]});
    rt::EventLocator<Q> locator(std::move(specs));
    auto g = [](Q t, const rt::State<Q>& xs, rt::State<Q>& out) { M::events(t, xs.data(), out.data(), parameters); };
    auto sys = float128_rhs;
    Q t_step = Q(0);  // the start of the step in progress: the last accepted step's end
    const rt::EventOutcome<Q> end =
        rt::integrate_adaptive_events(stepper, sys, x, Q(0), Q(t_end), Q(0), rt::Tolerances{tol, tol}, locator,
                                      g, [&](Q t, const rt::State<Q>&) { t_step = t; },
                                      [](const rt::EventHit<Q>&) {}, float128_limits());
    if (end.stopped) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "the terminal event '%s' occurs between t = %.9g and %.9g (at t = %.9g), before t_end",
                    M::event_names[end.event], static_cast<double>(t_step), static_cast<double>(stepper.current_time()),
                    static_cast<double>(end.t));
      throw std::runtime_error(buf);
    }
    std::array<Q, n_state> out{};
    std::copy(x.begin(), x.end(), out.begin());
    return out;
  } else {
    return float128_run(t_end, tol);
  }
}

Q distance(const std::vector<Q>& a, const std::vector<Q>& b) {
  using std::sqrt;
  Q d2 = Q(0);
  for (std::size_t k = 0; k < a.size(); ++k) d2 += (a[k] - b[k]) * (a[k] - b[k]);
  return sqrt(d2);
}

std::vector<Q> run_judged(const std::array<Q, n_state>& x, double t_end, const std::vector<Column>& columns) {
  return judged_values(Q(t_end), x.data(), columns, parameters);
}

// `--reference-only` (on the reference formulation's kernel): the judged columns at t_end of a
// float128 DOP853 run from the kernel's initial state, and how far a run 1000 times looser ends
// from it (its error is below that). Printed as a note and the line reference_values,V1,...,Vn,SPREAD.
int print_reference(const Options& o, const std::vector<Column>& columns) {
  const std::vector<Q> r = run_judged(float128_run_unless_terminal(o.t_end, o.reference_tolerance), o.t_end, columns);
  const std::vector<Q> r_loose = run_judged(float128_run(o.t_end, o.reference_tolerance * 1e3), o.t_end, columns);
  const Q spread = distance(r, r_loose);
  std::string names;
  for (const std::string& n : o.judged) names += (names.empty() ? "" : ", ") + n;
  std::printf("# reference: %s in float128 (113-bit), DOP853 at rtol = atol = %.0e from the kernel's initial state; a "
              "run at %.0e ends %.2g away in (%s) (a bound on the reference's error)\n",
              K::scene_name, o.reference_tolerance, o.reference_tolerance * 1e3, static_cast<double>(spread),
              names.c_str());
  std::printf("reference_values");
  for (const Q& v : r) std::printf(",%s", rt::to_string(v).c_str());
  std::printf(",%s\n", rt::to_string(spread, 6).c_str());
  return 0;
}

double judged_error(const State& x, double t_end, const std::vector<Column>& columns, const std::vector<Q>& reference) {
  std::array<Q, n_state> xq{};
  std::copy(x.begin(), x.end(), xq.begin());
  return static_cast<double>(distance(run_judged(xq, t_end, columns), reference));
}

// --- timing and output ------------------------------------------------------------------------------

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Median time of one run over max(repeats, enough runs to fill min_time) repetitions.
std::pair<double, int> time_runs(const std::function<void()>& run, double min_time, int repeats) {
  std::vector<double> samples;
  auto start = Clock::now();
  run();
  samples.push_back(seconds_since(start));
  int wanted = repeats;
  if (samples[0] > 0.0) wanted = std::max(repeats, static_cast<int>(std::ceil(min_time / samples[0])));
  wanted = std::min(wanted, 100000);
  while (static_cast<int>(samples.size()) < wanted) {
    start = Clock::now();
    run();
    samples.push_back(seconds_since(start));
  }
  std::sort(samples.begin(), samples.end());
  const std::size_t n = samples.size();
  const double median = n % 2 ? samples[n / 2] : (samples[n / 2 - 1] + samples[n / 2]) / 2;
  return {median, static_cast<int>(n)};
}

// A one-line bar on stderr for people at a terminal; erased when done.
class Progress {
 public:
  explicit Progress(std::size_t total) : total_(total), enabled_(::isatty(STDERR_FILENO) != 0) {}
  void show(std::size_t done, const std::string& what) {
    if (!enabled_ || total_ == 0) return;
    constexpr int width = 30;
    const int filled = static_cast<int>(width * done / total_);
    std::fprintf(stderr, "\r\033[K[%s%s] %3d%%  %s", std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), static_cast<int>(100 * done / total_), what.c_str());
    std::fflush(stderr);
  }
  ~Progress() {
    if (enabled_) std::fputs("\r\033[K", stderr);
  }

 private:
  std::size_t total_;
  bool enabled_;
};

std::string format_setting(Kind kind, double setting) {
  char buf[64];
  std::snprintf(buf, sizeof buf, kind == Kind::adaptive ? "tol %.3g" : "%.0f steps", setting);
  return buf;
}

// --- the sweep ------------------------------------------------------------------------------------

// The methods asked for (all by default), less those that cannot run this kernel (each with a note).
std::vector<Method> chosen_methods(const Options& o) {
  std::vector<Method> methods;
  for (Method& m : all_methods()) {
    const bool wanted = o.methods.empty() || std::find(o.methods.begin(), o.methods.end(), m.name) != o.methods.end();
    if (!wanted) continue;
    if (m.needs_acceleration && !separable) {
      std::printf("# skipped %s: the kernel has no acceleration(t, q) (a separable system's q'' = a(q, t)), which "
                  "splitting methods step with\n", m.name);
      continue;
    }
    if (projects && std::strcmp(m.library, "odeint") == 0) {
      std::printf("# skipped %s: odeint's integrators do not call the kernel's project() after a step\n", m.name);
      continue;
    }
    if (std::strcmp(m.name, "symplectic_rkn_sb3a_mclachlan") == 0 && !eomc::bench::autonomous) {
      std::printf("# skipped %s: odeint's Nystroem steppers pass no time to the force, and the equations depend on t\n",
                  m.name);
      continue;
    }
    methods.push_back(std::move(m));
  }
  for (const std::string& name : o.methods) {
    const auto all = all_methods();
    if (std::none_of(all.begin(), all.end(), [&](const Method& m) { return name == m.name; }))
      usage("unknown method " + name);
  }
  return methods;
}

// The judged columns by name (a formulation's run), and the measured invariants (drift_measured).
std::vector<Column> judged_columns(const Options& o) {
  std::vector<Column> columns;
  if (o.reference_only || o.reference_values) {
    for (const std::string& name : o.judged) {
      const int in_state = index_of(K::state_names, name), in_outputs = output_index(name);
      if (in_state < 0 && in_outputs < 0) usage("--judge: the kernel has no state component or output '" + name + "'");
      columns.push_back(in_state >= 0 ? Column{true, in_state} : Column{false, in_outputs});
    }
  }
  if (!o.drift_invariants.empty()) {
    drift_measured.fill(false);
    for (const std::string& name : o.drift_invariants) {
      const int k = index_of(K::invariant_names, name);
      if (k < 0) usage("--drift-invariants: the kernel has no invariant '" + name + "'");
      drift_measured[static_cast<std::size_t>(k)] = true;
    }
  }
  return columns;
}

// What a method's runs are judged against: the reference solution, or a formulation's judged columns.
struct Judge {
  const Options& o;
  const std::vector<Column>& columns;
  const Reference& ref;
  double round_off_region;  // errors this small are round-off

  double error(const State& x) const {
    return o.reference_values ? judged_error(x, o.t_end, columns, *o.reference_values) : error_of(x, ref);
  }
};

// One CSV row per setting of a method that runs, a note for those that fail.
void sweep(const Method& m, const Judge& judge, Progress& bar, std::size_t& done) {
  const Options& o = judge.o;
  const std::vector<double>& settings = m.kind == Kind::adaptive ? o.tolerances : o.steps;
  std::size_t failures = 0;
  std::string first_failure;
  double best = std::numeric_limits<double>::infinity();
  int stalled = 0;
  bool stop = false;
  for (double setting : settings) {
    bar.show(done++, std::string(m.name) + " " + format_setting(m.kind, setting));
    if (stop) continue;
    Outcome out;
    double error = 0.0, observed_s = 0.0;
    try {
      const auto start = Clock::now();
      run_budget.begin(o.t_end);
      out = m.run(o.t_end, setting, true);
      observed_s = seconds_since(start);
      error = judge.error(out.x);
      if (!std::isfinite(error)) throw std::runtime_error("non-finite final state");
    } catch (const RunBudget::OverBudget& e) {
      // The settings that follow (tighter, or more steps) cost more: the method's sweep ends here.
      if (failures++ == 0) first_failure = format_setting(m.kind, setting) + ": " + e.what();
      stop = true;
      continue;
    } catch (const std::exception& e) {
      // Too large a step (a fixed-step method blowing up, an implicit stage iteration that does
      // not converge) or a controller that gives up: no row, a note.
      if (failures++ == 0) first_failure = format_setting(m.kind, setting) + ": " + e.what();
      continue;
    }
    const auto [seconds, reps] = time_runs(
        [&] {
          run_budget.begin(o.t_end);
          (void)m.run(o.t_end, setting, false);
        },
        o.min_time, o.repeats);
    std::printf("%s,%s,%s,%.10g,%.17g,", m.name, m.library, m.kind == Kind::adaptive ? "tolerance" : "steps", setting,
                error);
    if (K::n_invariants > 0) std::printf("%.17g", out.drift);
    std::printf(",%zu,%zu,%zu,%.9g,%d\n", out.evals, out.steps, out.rejected, seconds, reps);
    std::fflush(stdout);
    // A fixed-step sweep ends once the error has stopped falling in the round-off region (three
    // settings in a row without halving it), or when a run gets slow.
    if (m.kind == Kind::fixed) {
      stalled = error < 0.5 * best || error > judge.round_off_region ? 0 : stalled + 1;
      best = std::min(best, error);
      if (stalled >= 3 || observed_s > o.max_run_time) stop = true;
    }
  }
  if (failures > 0)
    std::printf("# %s: %zu setting%s failed, the first (%s)\n", m.name, failures, failures == 1 ? "" : "s",
                first_failure.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  run_budget.limit_s = o.budget_s;
  const std::vector<Method> methods = chosen_methods(o);
  const std::vector<Column> columns = judged_columns(o);

  if (o.reference_only) {
    try {
      return print_reference(o, columns);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench driver: the reference run failed: %s\n", e.what());
      return 1;
    }
  }

  std::size_t total = 1, done = 0;  // the reference counts as one unit
  for (const Method& m : methods) total += m.kind == Kind::adaptive ? o.tolerances.size() : o.steps.size();
  Progress bar(total);
  bar.show(done++, "reference solution");
  Reference ref;
  if (!o.reference_values) {
    try {
      ref = make_reference(o);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench driver: the reference run failed: %s\n", e.what());
      return 1;
    }
    std::printf("# reference: %s\n", ref.description.c_str());
  }
  std::printf("method,library,kind,setting,error,max_invariant_drift,rhs_evals,steps,rejected,wall_seconds,repetitions\n");
  std::fflush(stdout);

  // Errors this small are round-off: a fixed-step sweep that no longer improves there is done.
  double scale = 1.0;
  if (o.reference_values)
    for (const Q& v : *o.reference_values) scale = std::max(scale, static_cast<double>(abs(v)));
  else
    for (const Q& v : ref.x) scale = std::max(scale, static_cast<double>(abs(v)));
  const Judge judge{o, columns, ref, 1e-8 * scale};
  for (const Method& m : methods) sweep(m, judge, bar, done);
  return 0;
}
