// Stage 4: the kernel as straight-line code, ready to print.
//
// A Block is what one emitted function computes: temporaries w_k = expr in dependency
// order (after common-subexpression elimination), then the outputs written in terms of
// them. Expressions are still GiNaC objects, but only over the symbols listed in
// KernelIR (time, state, parameters, accelerations, temporaries); the emitter prints
// them and knows nothing of mechanics.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"

namespace eomc::codegen {

struct Temporary {
    GiNaC::symbol symbol;
    GiNaC::ex value;
};

struct Block {
    std::vector<Temporary> temporaries;
    std::vector<GiNaC::ex> outputs;
    std::size_t ops_before = 0;  // operations in the outputs as derived (shared subtrees counted every time)
    std::size_t ops_after = 0;   // operations left after CSE
};

struct NamedSymbol {
    std::string name;
    GiNaC::ex symbol;
};

// The encke formulation's rectification (mechanics::Rectification), lowered: the reference
// orbit's ρ, ρ̇ and μ as one block, read by the emitted project().
struct RectificationIR {
    double ratio = 0.0;
    std::size_t deviation = 0, elements = 0, count = 0;
    Block reference;  // 7 outputs: ρ (3), ρ̇ (3), μ
};

// How rhs() and jacobian() solve M u̇ = f, decided at generation time from M's structure
// (codegen/solve_plan.hpp).
struct SolvePlan {
    enum class Method {
        none,            // nothing to solve here: no velocity block, closed form, or the runtime's solvers
        identity,        // M = I: u̇ = f
        diagonal,        // u̇_k = f_k / M_kk
        block_diagonal,  // M decouples into blocks, each an unrolled LDLᵀ (or a division)
        unrolled_ldlt,   // one dense block: LDLᵀ unrolled into straight-line code
        eigen_llt,       // past unrolled_limit velocities: Eigen's LLT at run time
    };
    Method method = Method::none;
    bool constant = false;  // M depends on numbers and parameters only (not on t or the state)
    bool numeric = false;   // M's entries are numbers: the factors are computed at generation time
    std::vector<std::vector<std::size_t>> blocks;  // the velocities each block couples, ascending
};

struct KernelIR {
    std::string scene_name, struct_name, summary, source;
    std::string description;                 // what the state and the equations are (banner)
    std::size_t n_coordinates = 0;
    std::size_t velocity_offset = 0, n_velocities = 0;  // the block solved from M u̇ = f
    GiNaC::ex t;
    std::vector<NamedSymbol> state;          // in kernel order
    std::vector<NamedSymbol> accelerations;  // u̇: inputs of the Jacobian terms and of the outputs
    std::vector<NamedSymbol> parameters;
    std::vector<double> parameter_defaults;
    std::vector<double> initial_state;
    std::vector<std::string> invariant_names;
    std::vector<std::string> output_names;
    bool separable = false;                  // q̈ = a(t, q): emit acceleration() for the splitting methods
    std::vector<std::size_t> unit_quaternions;  // first state index of each: emit project()
    std::vector<std::size_t> unit_vectors;      // likewise for unit 3-vectors
    std::optional<RectificationIR> rectification;  // encke: emit project() that rectifies

    Block mass_matrix;       // n_velocities² outputs, row-major
    Block forcing;           // n_velocities outputs
    bool has_jacobian = false;       // jacobian() is emitted (LowerOptions::jacobian); the blocks below are filled
    bool explicit_solution = false;  // n_velocities ≤ 2: u̇ = M⁻¹f solved symbolically
    Block rhs_explicit;              // when explicit_solution: every rate, in state order
    Block jacobian_explicit;         // when explicit_solution: n_state² outputs
    Block mass_and_forcing;          // otherwise: M and f CSE'd together (what rhs evaluates)
    std::vector<std::size_t> explicit_index;  // otherwise: the state index of each explicit rate
    Block explicit_rates;            // otherwise: those rates
    Block explicit_rates_jacobian;   // otherwise: their rows of ∂ẋ/∂x, |explicit_index| × n_state
    Block mass_and_jacobian_terms;   // otherwise: M, then G = ∂f/∂x − (∂M/∂x)·u̇, n_velocities × n_state
    SolvePlan solve_plan;            // otherwise: how M u̇ = f is solved
    Block solved_rates;              // straight-line plans: mass_and_forcing, then u̇ = M⁻¹f (n_velocities outputs)
    Block solved_jacobian_terms;     // straight-line plans: mass_and_jacobian_terms, then M⁻¹G (n_velocities × n_state)
    Block invariants;                // one output per invariant
    Block outputs;                   // one per output, functions of (t, x, u̇)

    // Scene events (empty: nothing is emitted): g_i(t, x), one output each.
    std::vector<std::string> event_names;
    std::vector<int> event_directions;  // +1 up, -1 down, 0 both
    std::vector<bool> event_terminal;
    Block events;

    // Where the mass matrix is singular (empty: nothing is emitted and the kernel keeps its bytes):
    // indicators s_k(t, x) whose zero set it is, each with its power in det M.
    std::vector<std::string> singular_set_names;  // "sin(theta) = 0"
    std::vector<int> singular_set_orders;
    Block singular_sets;

    // Newtonian scenes only (empty otherwise, and then nothing is emitted): Santilli's
    // conditions S1–S5 of the fundamental form as residuals, one output per name.
    std::vector<std::string> santilli_residual_names;
    Block santilli_residuals;

    // Bilateral constraint rows (mechanics/constraints/rows.hpp; empty: nothing is emitted and
    // the kernel keeps its bytes). M u̇ − Wᵀλ = f, W u̇ = r with r = −bias − stabilisation.
    std::vector<std::string> constraint_names;
    std::vector<bool> constraint_holonomic, constraint_projected;
    std::size_t n_user_outputs = 0;   // output_names then has lambda_<row> …, reaction_<coordinate> …
    Block mass_forcing_and_constraints;  // M (n_velocities², row-major), f, W (m × n_velocities), r (m)
    Block constraint_residuals;          // 2m: f_α (holonomic) or φ_α (kinematic), then φ_α
    Block constraint_jacobian;           // W alone, m × n_velocities row-major (the projection)
    // How M u̇ − Wᵀλ = f, W u̇ = r is solved (codegen/solve_plan.hpp, plan_saddle_point): in
    // straight-line code up to unrolled_limit coupled unknowns, else (eigen_llt) by the runtime's
    // Schur complement on Eigen.
    SolvePlan constraint_plan;
    Block solved_constraints;   // straight-line: u̇ (n_velocities), λ (m), Wᵀλ (n_velocities)
    Block position_correction;  // straight-line, projected holonomic rows: M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹, n_velocities × p
    Block velocity_correction;  // straight-line, every projected row: the same, n_velocities × v (empty
                                // when those are the holonomic ones: position_correction serves)

    // Unilateral rows (mechanics/unilateral/rows.hpp; empty: nothing is emitted and the kernel keeps
    // its bytes): a gap f_α(q, t) ≥ 0 or a kinematic row φ_α(q, q̇, t) ≥ 0 (Mei §6.7), with
    // f̈_α (φ̇_α) = W_α u̇ + bias_α and Newton's restitution e_α.
    std::vector<std::string> contact_names;
    std::vector<bool> contact_kinematic;
    Block restitutions;      // m outputs, functions of the parameters alone
    Block contact_gaps;      // m: f_α (gap) or φ_α (kinematic)
    Block contact_jacobian;  // W, m × n_velocities row-major
    Block contact_bias;      // m
    // m: w_α = ∂f_α/∂t of a moving gap (ḟ_α = W_α u + w_α; 0 for a kinematic row). Empty when every
    // w_α vanishes (fixed walls): nothing is emitted, the kernel keeps its bytes, and the runtime
    // takes w = 0.
    Block contact_time_rates;

    // Programs realised by controls (mechanics/control/rows.hpp; empty: nothing is emitted and the
    // kernel keeps its bytes): M u̇ = f + D λ, Ā u̇ = c, reduced in straight-line code (reduced_programs
    // below) or solved at run time on Eigen (runtime/program/control.hpp).
    // output_names then has program_<name> …, lambda_<column> …, Qc_<coordinate> … after the user's.
    std::vector<std::string> program_names;
    std::vector<double> program_laws;     // 4 per program: configuration (1 or 0), α, β, κ
    std::vector<std::string> program_columns;  // lambda_<…>, one per column of D
    bool program_redundant = false;       // dependent ideal programs: Udwadia–Kalaba
    Block mass_forcing_and_programs;      // M (n_velocities², row-major), f, Ā (m × n_velocities), c (m), D (n_velocities × k)
    Block program_residuals;              // 2m: ω and ω̇, or φ and 0
    // Where M's solve fits straight-line code and the programs are not redundant: z, Y = M⁻¹D,
    // G = Ā Y, h = c − Ā z and D (codegen/solve_plan.hpp, reduce_programs), G λ = h left to the
    // runtime's pivoted LU (runtime/program/reduced_control.hpp). Empty: the Eigen path.
    SolvePlan program_plan;
    Block reduced_programs;
};

// Common-subexpression elimination over all outputs of one function.
Block eliminate_common_subexpressions(const std::vector<GiNaC::ex>& outputs, const std::string& temp_prefix);

// Operations of an expression tree, shared subtrees counted each time they occur:
// + − × ÷ one each, a power as the printer writes it (multiplied_power: its multiplications,
// a sqrt, and a division when the exponent is negative), any other power and every function call
// one each.
std::size_t count_operations(const GiNaC::ex& e);

// The printer writes x^k with k an integer or a half-integer j/2, |k| ≤ max_multiplied_power,
// without pow(): x^m by binary powering (x^5 = (x*x)*(x*x)*x, compilers share the repeated
// square), x^(j/2) = x^((|j|−1)/2)*sqrt(x), and a negative exponent as one division 1/(…). libm's
// pow costs tens of nanoseconds where these cost a few; the bound keeps the text short.
inline constexpr long max_multiplied_power = 32;
bool multiplied_power(const GiNaC::numeric& k);
// Multiplications that x^m costs by binary powering (m ≥ 1): the squarings and one per further bit.
std::size_t powering_multiplications(unsigned long m);

// Seconds spent per lowering step, for `eomc generate --timings` and the benchmarks.
struct LoweringTimes {
    double mass_and_forcing = 0;  // CSE of M, f, M+f and the explicit rates
    double jacobian = 0;          // the Jacobian's derivatives and their CSE
    double invariants = 0;
};

// What lower() builds beyond the blocks every kernel needs.
struct LowerOptions {
    // ∂ẋ/∂x and jacobian(): for --jacobian, the variational equations and the implicit methods
    // that take it. It costs most of the lowering, so it is left out unless asked for.
    bool jacobian = false;
};

// A first-order form → kernel IR. Deterministic: the same scene gives the same IR.
KernelIR lower(const model::Model& model, const mechanics::FirstOrderForm& form, LoweringTimes* times = nullptr,
               LowerOptions options = {});
// Lagrange's equations of the model, through mechanics::first_order_form (an orbit scene with
// formulation = "equinoctial": through mechanics::equinoctial_form).
KernelIR lower(const model::Model& model, const mechanics::Equations& equations, LoweringTimes* times = nullptr,
               LowerOptions options = {});

}  // namespace eomc::codegen
