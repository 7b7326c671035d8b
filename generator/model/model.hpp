// Stage 2: the scene's strings turned into GiNaC objects.
//
// Every name maps to exactly one GiNaC symbol (SymbolTable is the only factory), every
// expression is parsed against that table, and everything that needs algebra to check
// (unknown symbols, masses that are not positive, positions that depend on velocities,
// carrier motion that depends on the coordinates) is checked here, with the position of
// the offending character. The model is still "what the user said": no derivation.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "scene/scene.hpp"

namespace eomc::model {

using Vec3 = std::array<GiNaC::ex, 3>;

enum class Effect { relative, translation, euler, centrifugal, coriolis };
inline constexpr std::array<Effect, 5> all_effects{Effect::relative, Effect::translation, Effect::euler,
                                                  Effect::centrifugal, Effect::coriolis};
const char* name(Effect e);

struct Parameter {
    std::string name;
    GiNaC::symbol symbol;
    double value = 0.0;  // the scene's default
};

struct Coordinate {
    std::string name;
    GiNaC::symbol q, q_dot, q_ddot;  // q, q_dot, q_ddot in the scene's expressions
    double initial = 0.0;            // at the parameters' defaults
    double rate = 0.0;
    // The scene's initial value and rate when given as expressions of the parameters ("v/r"),
    // recomputed wherever the parameters are given other values (initial_overrides); else empty.
    GiNaC::ex initial_expr, rate_expr;
};

// A carried body: a particle at r'(q, t) or, with an inertia, a rigid body with its mass
// centre there, turned by `orientation` from the carrier.
struct Particle {
    std::string name;
    GiNaC::ex mass;
    Vec3 position;  // r'(q, t) in carrier axes
    bool rigid = false;
    GiNaC::matrix inertia = GiNaC::matrix(3, 3);   // about the mass centre, body axes
    // Elementary rotations (axis 'x' | 'y' | 'z', angle(q, t)) turning the carrier's axes into
    // the body's, applied left to right; empty: parallel to the carrier.
    std::vector<std::pair<char, GiNaC::ex>> orientation;
    SourcePos inertia_pos;  // the inertia's value in the scene
};

// An unknown velocity of a free carrier: one component of v_o or of ω (seed §1.1).
struct QuasiVelocity {
    std::string name;
    GiNaC::symbol symbol, rate;  // v0 and v0_dot
    double initial = 0.0;
    bool angular = false;  // a component of ω, else of v_o
    int axis = 0;
};

// The carrier: ω and v_o in carrier axes, functions of t (prescribed) or, for a free
// carrier, each component a quasi-velocity symbol or 0 (held by the constraints).
struct Carrier {
    Vec3 angular_velocity;
    Vec3 pole_velocity;
    bool free = false;
    GiNaC::ex mass = 0;                             // the carrier's own mass (0: none given),
    GiNaC::matrix inertia = GiNaC::matrix(3, 3);    // its inertia about o (zero: none given),
    SourcePos inertia_pos;                          // the [carrier] table
    Vec3 center{0, 0, 0};                           // its mass centre (carrier axes)
    Vec3 resultant{0, 0, 0}, moment{0, 0, 0};       // given external force on the system, moment about o
};

// Equations given directly (scene [newtonian]), one per coordinate in declaration order:
// the kinematic form q̈_s = f_s(t, q, q̇), or the fundamental form Φ_s = A_sk q̈_k + B_s = 0
// (checked to be affine in q̈).
struct Newtonian {
    bool fundamental = false;
    std::vector<GiNaC::ex> expressions;  // f_s (kinematic) or Φ_s (fundamental)
    std::vector<SourcePos> positions;    // of each expression's text
    SourcePos pos;                       // the [newtonian] table
};

// An event (scene [events]): g(t, q, q̇, parameters) crossing zero. Quasi-velocities count as
// velocities.
struct Event {
    std::string name;
    GiNaC::ex when;
    int direction = 0;  // +1: upwards only, -1: downwards only, 0: both
    bool terminal = false;
    SourcePos pos;      // the key in [events]
};

// A bilateral constraint row (scene [[constraint]]; Mei, §6.6 and ch. 3): holonomic, f(t, q) = 0,
// or kinematic, φ(t, q, u) = Σ_k B_k(t, q) u_k + b(t, q) = 0 over the velocities u (checked to be
// linear in them and to hold a rate). The initial state satisfies it at the parameters' defaults.
enum class ConstraintStabilization { project, baumgarte, none };

struct Constraint {
    std::string name;
    bool holonomic = true;
    GiNaC::ex expression;  // f (holonomic) or φ (kinematic)
    ConstraintStabilization stabilization = ConstraintStabilization::project;
    double alpha = 0.0, beta = 0.0;  // Baumgarte's constants
    SourcePos pos;                   // the expression's text in the scene
};

// A unilateral constraint row (scene [[unilateral]]; Mei, ch. 6): a gap f(t, q) >= 0 (§6.2) or a
// unilateral kinematic constraint φ(t, q, u) = Σ_k B_k(t, q) u_k + b(t, q) >= 0 (§6.7), checked as
// the bilateral rows are (linear in the rates, at least one). Newton's restitution coefficient e is
// an expression of the parameters with 0 <= e <= 1 at their defaults. The initial state satisfies
// f >= 0 (or φ >= 0) at the defaults.
struct Unilateral {
    std::string name;
    bool holonomic = true;          // a gap; false: a velocity row (§6.7)
    GiNaC::ex expression;           // f (gap) or φ (velocity row)
    GiNaC::ex restitution;          // e, a function of the parameters
    double restitution_default = 0; // e at the parameters' defaults
    SourcePos pos;                  // the expression's text in the scene
    SourcePos restitution_pos;      // the restitution's text (the table when absent)
};

// A programmed motion (scene [[program]]; Mei, ch. 3): ω(t, q) = 0 (configuration space) or
// φ(t, q, q̇) = 0 (phase space, holding a rate), the law of its residual (Erugin, with
// Galiullin's gains; the open loop ω̈ = 0 or φ̇ = 0 when not closed), and the control's directions.
// moment: a rigid body's torque about a fixed body-axis direction (Mei §3.2), D's column over ω.
enum class ProgramControl { ideal, directions, actuated, moment };

struct Program {
    std::string name;
    bool configuration = true;     // ω(t, q); false: φ(t, q, q̇)
    GiNaC::ex expression;          // ω or φ
    bool closed_loop = false;
    double alpha = 0.0, beta = 0.0, kappa = 0.0;
    ProgramControl control = ProgramControl::ideal;
    std::vector<GiNaC::ex> direction;   // directions: one generalized direction per coordinate (0 where not given);
                                        // moment: the body-axis torque direction (3 entries, over p, q, r)
    std::vector<std::size_t> actuated;  // actuated: the coordinates' indices, in the scene's order
    SourcePos pos, erugin_pos, control_pos;  // the expression's text, the law and the control values
};

// How `eomc simulate` passes the unilateral rows (scene [contact]; the runtime's names).
using ContactMethod = runtime::contact::ContactMethod;
using ImpactLaw = runtime::contact::ImpactLaw;

// An orbit scene ([orbit]): a point mass about a central body in inertial Cartesian axes,
// T = |v|²/2, V = −μ/r − R with R the sum of the kept disturbing functions (acceleration =
// +∇R; Mei, ch. 2), and the non-conservative accelerations as generalized forces.
struct OrbitTerm {
    std::string effect;  // "J2", …, "custom"
    GiNaC::ex value;     // a disturbing function R(x, y, z, t)
};
struct OrbitAcceleration {
    std::string effect;  // "drag" or "custom"
    Vec3 value;          // inertial axes, functions of (t, x, y, z, x_dot, y_dot, z_dot)
};
struct Orbit {
    GiNaC::ex mu, radius;                        // the central body's μ and radius (parameters)
    double mu_default = 0;                       // μ at the parameters' defaults (initial elements)
    std::vector<OrbitTerm> disturbing;           // in library order, then custom
    std::vector<OrbitAcceleration> accelerations;
    GiNaC::ex R = 0;                             // Σ disturbing
    Vec3 acceleration{0, 0, 0};                  // Σ accelerations
    // What the kernel integrates (mechanics/orbit/formulation.hpp's registry decides by it).
    scene::OrbitFormulationKind kind = scene::OrbitFormulationKind::cowell;
    SourcePos formulation_pos;                   // the [orbit] formulation key (or the [orbit] table)
    double rectify = 1e-2;                       // encke: reset the reference when |δ| > rectify |ρ|
    GiNaC::ex r;                                 // √(x² + y² + z²)
};

// A heavy rigid body (or gyrostat) about a fixed point O ([rigid_body]; Mei, ch. 5), in body
// axes: ω = (p, q, r), γ the upward vertical (|γ| = 1), gravity −P γ at the mass centre.
// Every formulation (mechanics/rigid/formulation.hpp) writes its state through ω and γ, so
// events and integrals are stated in p, q, r, gamma1..3 whatever the kernel integrates.
struct RigidBody {
    GiNaC::matrix inertia = GiNaC::matrix(3, 3);  // about O, body axes, symmetric
    bool principal = true;                        // inertia diagonal (the body axes are principal)
    Vec3 center{0, 0, 0};                         // r_c, body axes
    GiNaC::ex weight = 0;                         // P = m g
    Vec3 gyrostat{0, 0, 0};                       // k, the rotor's constant angular momentum, body axes
    std::array<GiNaC::symbol, 3> omega;           // p, q, r
    std::array<GiNaC::symbol, 3> omega_rate;      // p_dot, q_dot, r_dot
    std::array<GiNaC::symbol, 3> gamma;           // gamma1, gamma2, gamma3
    // The quaternion formulation's attitude e0..e3 (body → space), a state that programs may hold
    // (Mei §3.2: an attitude programmed through the error quaternion); absent in the others.
    std::optional<std::array<GiNaC::symbol, 4>> attitude;
    std::array<double, 3> omega0{0, 0, 0};        // ω(0)
    std::array<double, 4> attitude0{1, 0, 0, 0};  // body → space unit quaternion at t = 0
    std::array<double, 3> vertical0{0, 0, 1};     // γ(0) = R(0)ᵀ e_Z
    std::array<double, 6> andoyer0{};              // andoyer_deprit: (l, g, h, L, G, H) at t = 0
    scene::RigidFormulationKind formulation = scene::RigidFormulationKind::euler_poisson;
    SourcePos formulation_pos, initial_pos, inertia_pos, pos;
    // The euler_angles formulation: ω and γ in the ZXZ angles and their rates (the model's
    // coordinates φ, θ, ψ); empty maps otherwise.
    GiNaC::exmap in_angles;

    Vec3 omega_vector() const { return {omega[0], omega[1], omega[2]}; }
    Vec3 gamma_vector() const { return {gamma[0], gamma[1], gamma[2]}; }
    // The symbols of the attitude, each with its rate along the motion, linear in ω: γ̇ = γ × ω and,
    // in the quaternion formulation, ė = ½ e ⊗ (0, ω).
    std::vector<std::pair<GiNaC::symbol, GiNaC::ex>> attitude_rates() const;
};

// What a scene describes, which decides the chapter that derives its equations (mechanics/derive).
enum class ModelKind {
    energies,         // T and V: a [lagrangian] T, or carried particles and bodies (Mei, ch. 1)
    given_equations,  // [newtonian]: the equations themselves (the inverse problem, Mei, ch. 4)
    orbit,            // [orbit]: a perturbed Kepler motion (Mei, ch. 2)
    rigid,            // [rigid_body]: a heavy rigid body about a fixed point (Mei, ch. 5)
};

struct Model {
    std::string name;         // scene name, e.g. disk_tube_ball
    std::string struct_name;  // DiskTubeBall
    std::string summary;
    std::string source;       // scene path as given
    GiNaC::symbol t;
    std::vector<Parameter> parameters;
    std::vector<Coordinate> coordinates;

    // Either particles (with an optional carrier: absent = inertial frame) or a kinetic energy.
    std::optional<Carrier> carrier;
    std::vector<QuasiVelocity> quasi_velocities;  // a free carrier's unknowns, in axis order (v_o, then ω)
    std::vector<Particle> particles;
    std::optional<GiNaC::ex> kinetic_energy;  // [lagrangian] T

    GiNaC::ex potential = 0;                     // V(q, q_dot, t)
    std::vector<GiNaC::ex> generalized_forces;   // Q_s, one per coordinate (0 when not given)
    std::array<bool, 5> keep{true, true, true, true, true};  // indexed by Effect
    SourcePos kinetic_pos;                       // where T comes from (for errors about M)

    scene::Simulate simulate;
    bool hamiltonian = false;                    // [formulation] kind = "hamiltonian"
    // [reference]: the exact state at time t (functions of t and the parameters), one expression
    // per state variable in state order (q_1..q_n, q_1_dot..q_n_dot); empty when the scene gives none.
    std::vector<GiNaC::ex> reference;
    std::optional<Newtonian> newtonian;  // equations instead of energies (no particles, no T)
    std::vector<Event> events;           // [events], in file order
    std::vector<Constraint> constraints; // [[constraint]], in file order
    std::vector<Unilateral> unilateral;  // [[unilateral]], in file order
    std::vector<Program> programs;       // [[program]], in file order
    ContactMethod contact_method = ContactMethod::event_driven;  // [contact] method
    double theta = 0.5;                  // [contact] theta (Moreau–Jean's θ-method)
    ImpactLaw impact_law = ImpactLaw::simultaneous;  // [contact] impact_law
    SourcePos impact_law_pos;            // its value (the table, or unknown, when absent)
    SourcePos contact_method_pos;        // [contact] method's value (the table, or unknown, when absent)
    std::optional<Orbit> orbit;          // an orbit scene: coordinates x, y, z, T and V built from [orbit]
    // A rigid-body scene; in the euler_angles formulation the model also has the coordinates φ, θ,
    // ψ and T, V in them (the Lagrangian chapter derives its equations).
    std::optional<RigidBody> rigid;
    scene::Inverse inverse;
    std::vector<Warning> warnings;       // accepted but doubtful input, printed by the CLI

    ModelKind kind() const {
        return newtonian ? ModelKind::given_equations
               : orbit   ? ModelKind::orbit
               : rigid   ? ModelKind::rigid
                         : ModelKind::energies;
    }
    bool keeps(Effect e) const { return keep[static_cast<int>(e)]; }
    // Lagrange's equations of a T and V in the coordinates: a scene given by its energies, or a
    // rigid body in Euler angles (whose T and V the model writes in φ, θ, ψ).
    bool lagrangian_in_coordinates() const {
        return kind() == ModelKind::energies ||
               (rigid && rigid->formulation == scene::RigidFormulationKind::euler_angles);
    }
    bool free_carrier() const { return carrier && carrier->free; }
    // The velocities u in the order of M's rows: the coordinates', then the quasi-velocities.
    std::vector<std::string> velocity_names() const;
    // All symbols that are inputs of the equations: t, q, q_dot, quasi-velocities, parameters.
    GiNaC::lst state_symbols() const;
    // Each parameter's symbol mapped to its scene default.
    GiNaC::exmap parameter_defaults() const;
};

// The initial values and rates given as expressions of the parameters, at the parameter values
// `overrides` gives (the rest at their defaults): ("q", value) and ("q_dot", value) for each one the
// overrides do not set themselves. Overrides naming no parameter are passed over. Throws InputError
// at the expression when it is not real at those values.
std::vector<std::pair<std::string, double>> initial_overrides(const Model& model,
                                                              const std::vector<std::pair<std::string, double>>& overrides);

// Throws eomc::InputError naming the place in the scene.
Model build_model(const scene::Scene& scene);

// The checks of a start that the model alone can make, shared by the scene's own initial values
// (build_model) and a run's (--set, an ensemble member: mechanics/start.hpp). `values` maps every
// symbol of the model to a number; `at` says whose values they are in the message ("with the
// default parameters"). Each throws InputError at the scene's place of what it refuses.
//
// t = 0, the parameters' defaults, the coordinates' initial values and rates, the quasi-velocities'
// and a rigid body's ω(0), γ(0) and attitude: the scene's own start.
GiNaC::exmap initial_values(const Model& model);
// e at `values`, with the magnitude of what cancels in it (Σ|term| through sums, products and
// powers): a residual is zero to round-off when |value| <= tolerance × magnitude. NaN where e is
// undefined. The terms as written, not expanded (a power of a sum could expand past any memory).
std::pair<double, double> value_and_magnitude(const GiNaC::ex& e, const GiNaC::exmap& values);
// A [[constraint]] row holds at the start: f and ḟ (holonomic) or φ (kinematic) vanish to 1e-9 of
// their magnitude.
void check_constraint_start(const Model& model, const Constraint& row, const GiNaC::exmap& values,
                            const std::string& at);
// Every body's inertia ([[body]], [rigid_body], a free carrier's) has positive principal moments A,
// B, C that satisfy the triangle inequalities A + B >= C, B + C >= A, C + A >= B.
void check_inertias(const Model& model, const GiNaC::exmap& values, const std::string& at);

}  // namespace eomc::model
