// Stage 1 of the pipeline: a scene file (TOML) parsed into plain data.
//
// Nothing here knows GiNaC. Expressions stay strings, each with the source position of
// its first character so that later stages can point at an unknown symbol inside it.
// The parser checks everything that can be checked without algebra: syntax, known keys
// (with a "did you mean" for typos), types, vector lengths, names, effect names.
#pragma once

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "eomc/runtime/contact/method.hpp"
#include "eomc/runtime/registry_info.hpp"
#include "support/diagnostic.hpp"

namespace eomc::scene {

// An expression as written in the scene. `pos` is the position of the first character
// of the expression text itself (inside the quotes), so pos.shifted(k) is character k.
struct Expr {
    std::string text;
    SourcePos pos;
};

using Vec3 = std::array<Expr, 3>;

struct Parameter {
    std::string name;
    double value = 0.0;
    SourcePos pos;
};

struct Coordinate {
    std::string name;
    double initial = 0.0;
    double rate = 0.0;
    SourcePos pos;
    // initial = "v/r": an expression of the parameters, recomputed whenever --set, --grid or --vary
    // gives them other values (`initial` and `rate` above are then filled in by the model).
    std::optional<Expr> initial_expr, rate_expr;
};

struct InitialValue {
    std::string name;
    double value = 0.0;
    SourcePos pos;  // the key
};

// The carrier body's frame o x'y'z'. Absent: the bodies move in an inertial frame.
struct Carrier {
    std::string motion = "prescribed";  // "prescribed" | "free"
    SourcePos motion_pos;
    // Prescribed: functions of t and parameters. Free: each component a new name (an unknown
    // quasi-velocity) or "0" (held at zero by the constraints).
    Vec3 angular_velocity;  // ω in carrier axes
    Vec3 pole_velocity;     // v_o in carrier axes
    // The carrier's own mass distribution (required for a free carrier, optional for a prescribed
    // one, whose holding forces it enters): mass, inertia about o (3 principal moments or
    // 9 entries, row-major; empty when not given), mass centre in carrier axes.
    std::optional<Expr> mass;
    std::vector<Expr> inertia;
    Vec3 center;
    std::vector<InitialValue> initial;  // [carrier.initial]: the quasi-velocities at t = 0
    SourcePos pos;                      // the [carrier] table
};

// An elementary rotation of a body's orientation, "z:phi": about the current z axis by phi.
struct Rotation {
    char axis = 'z';
    Expr angle;
};

// A carried body: a particle at r'(q, t) in carrier axes or, with `inertia`, a rigid body
// whose mass centre is there and whose axes are turned by `orientation` from the carrier's.
struct Body {
    std::string name;
    Expr mass;
    Vec3 position;
    std::vector<Expr> inertia;           // about the mass centre, body axes: 3 or 9 entries; empty: a particle
    std::vector<Rotation> orientation;   // applied left to right; empty: parallel to the carrier
    SourcePos pos;  // the [[body]] table
    SourcePos inertia_pos, orientation_pos;
};

// A Lagrangian given directly: L = T - V.
struct Lagrangian {
    Expr kinetic;    // T
    Expr potential;  // V (may be "0")
    SourcePos pos;
};

struct GeneralizedForce {
    std::string coordinate;  // a declared coordinate name (checked by the model)
    Expr value;
    SourcePos pos;  // the key
};

struct Forces {
    std::optional<Expr> potential;            // V(q, t)
    std::vector<GeneralizedForce> generalized;  // Q_s, in file order
    // Only with a free carrier: the external force on the whole system and its moment about
    // o, in carrier axes (the seed's V and m⁰).
    std::optional<Vec3> resultant, moment;
    SourcePos resultant_pos, moment_pos;
};

// The inertial effects of relative motion that the equations keep.
inline constexpr std::array<std::string_view, 5> effect_names{"relative", "translation", "euler",
                                                             "centrifugal", "coriolis"};

struct Effects {
    bool given = false;                  // false: keep all
    std::vector<std::string> keep;       // each one of effect_names (orbit_effect_names in an orbit scene), no duplicates
    std::vector<SourcePos> keep_pos;     // position of each entry
    // An orbit scene's [effects.custom]: a disturbing function R(x, y, z, t) (acceleration += ∇R)
    // and a non-conservative acceleration in inertial axes (may use the velocity).
    std::optional<Expr> disturbing_function;
    std::optional<Vec3> acceleration;
    SourcePos pos;                       // the [effects] table
};

// An orbit scene's perturbation library ([effects] keep in a scene with [orbit]); each names the
// parameters it reads (docs/scene-format.md).
inline constexpr std::array<std::string_view, 5> orbit_effect_names{"J2", "J3", "J4", "drag", "third_body"};
// The formulations of an orbit scene's equations (each one kernel from the same scene), read
// once here from [orbit] formulation or --orbit-formulation; what each one is and builds is
// mechanics/orbit/formulation.hpp's registry.
enum class OrbitFormulationKind { cowell, encke, lagrange, gauss, delaunay, equinoctial, mean };
// Indexed by OrbitFormulationKind.
inline constexpr std::array<std::string_view, 7> orbit_formulation_names{"cowell",   "encke",       "lagrange", "gauss",
                                                                         "delaunay", "equinoctial", "mean"};
inline constexpr std::string_view name(OrbitFormulationKind kind) {
    return orbit_formulation_names[static_cast<std::size_t>(kind)];
}

// [orbit]: a point mass about a central body. The model's coordinates are the inertial
// Cartesian x, y, z; the initial state comes from classical elements or is given directly.
struct Orbit {
    Expr mu, radius;                       // central_body: expressions of the parameters
    SourcePos central_body_pos;
    // a, e, i, raan, argp, mean_anomaly; the angles in radians (degrees in the file).
    std::optional<std::array<double, 6>> elements;
    std::optional<std::array<double, 6>> state;  // x, y, z, vx, vy, vz
    SourcePos initial_pos;                 // the elements or state value
    OrbitFormulationKind formulation = OrbitFormulationKind::cowell;
    SourcePos formulation_pos;
    // encke: the reference orbit is reset to the osculating one when |δ| > rectify |ρ| (0 < rectify < 1).
    double rectify = 1e-2;
    SourcePos pos;                         // the [orbit] table
};

// The formulations of a rigid body's equations (Mei, ch. 5), each one kernel from the same scene:
// what each one integrates is mechanics/rigid/formulation.hpp's registry.
enum class RigidFormulationKind { euler_poisson, quaternion, euler_angles, andoyer_deprit };
// Indexed by RigidFormulationKind.
inline constexpr std::array<std::string_view, 4> rigid_formulation_names{"euler_poisson", "quaternion", "euler_angles",
                                                                         "andoyer_deprit"};
inline constexpr std::string_view name(RigidFormulationKind kind) {
    return rigid_formulation_names[static_cast<std::size_t>(kind)];
}

// [rigid_body]: a heavy rigid body (or gyrostat) about a fixed point O (Mei, ch. 5). Body axes
// are principal at O when `inertia` gives three moments; γ is the upward vertical in body axes.
struct RigidBody {
    std::vector<Expr> inertia;  // 3 principal moments, or 9 entries of a symmetric matrix (row-major)
    Vec3 center;                // the mass centre in body axes
    Expr weight;                // P = m g
    std::optional<Vec3> gyrostatic_moment;  // k, body axes (a gyrostat's rotor; §5.6)
    RigidFormulationKind formulation = RigidFormulationKind::euler_poisson;
    SourcePos formulation_pos;
    std::array<double, 3> omega{0, 0, 0};          // ω(0), body axes
    std::optional<std::array<double, 3>> vertical;  // γ(0), unit (checked)
    std::optional<std::array<double, 3>> zxz;       // attitude φ, θ, ψ (radians) instead of γ(0)
    SourcePos inertia_pos, initial_pos, pos;        // the inertia value, the initial attitude value, the table
};

// [simulate]: the run's defaults. The integrators are the runtime's catalogue
// (eomc/runtime/registry_info.hpp), which says for each its kind, order and traits: fixed-step ones
// take a step, adaptive ones tolerances; the splitting methods need a separable kernel (q̈ = a(t, q)).
struct Simulate {
    double t_end = 10.0;
    std::string integrator{runtime::default_integrator};  // a name in runtime::integrator_infos
    double rtol = 1e-10;
    double atol = 1e-12;
    double step = 1e-3;                 // for the fixed-step integrators
    std::optional<bool> compensated;    // absent: the integrator's compensated_by_default
    SourcePos integrator_pos;           // the value of `integrator`, else the [simulate] table, else unknown
};

// [events]: g(t, x) crossing zero. `when` is an expression of t, the coordinates, the velocities
// and the parameters; direction "up" counts crossings from negative to positive only, "down"
// the reverse, "both" either; a terminal event stops the simulation at its time.
inline constexpr std::array<std::string_view, 3> event_directions{"both", "up", "down"};

struct Event {
    std::string name;  // the key: an identifier
    Expr when;
    std::string direction = "both";  // one of event_directions
    bool terminal = false;
    SourcePos pos;  // the key
};

// [[constraint]]: a bilateral constraint row (Mei, §6.6 and ch. 3; Lur'e, Analytical Mechanics,
// ch. 2), either holonomic, f(q, t) = 0, or kinematic, φ = B(q, t) q̇ + b(q, t) = 0 (linear in
// the rates; the model checks the algebra). The row is kept by the integration as `stabilize`
// says: "project" (the default), "none", or Baumgarte's { alpha, beta }.
inline constexpr std::array<std::string_view, 3> stabilization_names{"project", "baumgarte", "none"};

struct Constraint {
    std::string name;        // an identifier, unique among the constraints
    bool holonomic = true;   // `holonomic = "f"`; false: `kinematic = "phi"`
    Expr expression;         // f or φ
    std::string stabilize = "project";  // one of stabilization_names
    double alpha = 0.0, beta = 0.0;     // Baumgarte's constants (stabilize = { alpha, beta })
    SourcePos pos;           // the [[constraint]] table
    SourcePos name_pos;      // the name's value
    SourcePos stabilize_pos; // the stabilize value (the table when absent)
};

// [[unilateral]]: a unilateral constraint (Mei, ch. 6), either a gap f(q, t) >= 0 (§6.2) or a
// unilateral kinematic constraint φ(q, q̇, t) >= 0 linear in the rates (§6.7), with Newton's
// restitution coefficient e (an expression of the parameters, "0" when absent; the model checks
// 0 <= e <= 1 at the defaults). Names are unique among the unilateral and the bilateral rows.
struct Unilateral {
    std::string name;        // an identifier
    bool holonomic = true;   // `gap = "f"`; false: `velocity = "phi"`
    Expr expression;         // f or φ
    Expr restitution;        // e ("0" at the table when absent)
    SourcePos pos;           // the [[unilateral]] table
    SourcePos name_pos;      // the name's value
};

// [[program]]: a programmed motion realised by control forces (Mei, ch. 3; Galiullin, Inverse
// Problems of Dynamics, 1981): a relation ω(q, t) = 0 (configuration space) or φ(q, q̇, t) = 0
// (phase space; the model decides which by the symbols it holds), the law its residual is to
// follow (Erugin, PMM 16, 1952, with Galiullin's stable choice: `erugin = { alpha, beta }`,
// ω̈ + 2αω̇ + β²ω = 0, or `{ kappa }`, φ̇ + κφ = 0; absent: ω̈ = 0 or φ̇ = 0, the open loop) and
// the control's directions: "ideal" (the program's gradient; Chetaev's ∂φ/∂q̇), a table
// coordinate = "direction" (the generalized force λ·direction on it; others 0), or a list of
// actuated coordinates (one unit column, hence one control, each).
struct Program {
    std::string name;             // an identifier, unique among the programs
    Expr constraint;              // ω or φ
    bool closed_loop = false;     // erugin given
    bool phase_law = false;       // erugin = { kappa }
    double alpha = 0.0, beta = 0.0, kappa = 0.0;
    std::string control = "ideal";                        // "ideal" | "directions" | "actuated" | "moment"
    std::vector<std::pair<std::string, Expr>> directions;  // control = { coordinate = "direction" }, file order
    std::vector<std::pair<std::string, SourcePos>> actuated;  // control = ["coordinate", ...]
    Vec3 moment;                  // control = { moment = [m1, m2, m3] }: a body-axis torque direction ([rigid_body])
    SourcePos pos;                // the [[program]] table
    SourcePos name_pos, erugin_pos, control_pos;  // the values (the table when absent)
};

// [contact]: how `eomc simulate` integrates through the unilateral rows, by the runtime's names
// (eomc/runtime/contact/method.hpp): event-driven (free flight, impacts located as events, contact
// phases) or Moreau–Jean's time stepping with its θ (Acary & Brogliato 2008), and the impact law.
struct Contact {
    runtime::contact::ContactMethod method = runtime::contact::ContactMethod::event_driven;
    double theta = 0.5;                   // moreau_jean's θ (runtime::contact::valid_theta)
    runtime::contact::ImpactLaw impact_law = runtime::contact::ImpactLaw::simultaneous;  // event_driven only
    SourcePos pos;                        // the [contact] table (unknown when absent)
    SourcePos method_pos, theta_pos, impact_law_pos;  // the values (the table when absent)
};

// Which equations the kernel integrates: Lagrange's (state q, q̇) or Hamilton's (state q, p).
inline constexpr std::array<std::string_view, 2> formulation_names{"lagrangian", "hamiltonian"};
// A closed-form solution, for judging integrators (`eomc bench`): the exact state at time t as
// expressions of t and the parameters, one per state variable (q and q_dot for every coordinate).
struct ReferenceValue {
    std::string state;  // a coordinate "q" or its rate "q_dot"
    Expr value;
    SourcePos pos;      // the key
};

struct Reference {
    std::vector<ReferenceValue> values;  // file order; every state variable exactly once
    SourcePos pos;                       // the [reference] table
};

// A system given by its equations instead of its energies (Mei ch. 4, the inverse problem):
// either the kinematic form, one acceleration q̈_s = f_s(t, q, q̇) per coordinate (keys
// `<coordinate>_ddot`), or the fundamental form A(t,q,q̇) q̈ + B(t,q,q̇) = 0, one expression
// per coordinate (keys `<coordinate>` in [newtonian.fundamental]). Coordinate names are
// checked by the model.
struct NewtonianEquation {
    std::string coordinate;  // the coordinate the key names (the `_ddot` stripped)
    Expr value;
    SourcePos pos;           // the key
};

struct Newtonian {
    bool fundamental = false;
    std::vector<NewtonianEquation> equations;  // file order
    SourcePos pos;                             // the [newtonian] (or [newtonian.fundamental]) table
};

// Settings of `eomc inverse`.
struct Inverse {
    bool construct = true;          // build a Lagrangian when the equations allow one
    bool multiplier_search = true;  // look for an integrating factor when they are not self-adjoint
};

struct Scene {
    std::string path;     // the file it came from ("" for a string)
    std::string name;     // [a-z][a-z0-9_]*
    std::string summary;
    SourcePos name_pos;
    std::vector<Parameter> parameters;    // file order
    std::vector<Coordinate> coordinates;  // file order
    std::optional<Carrier> carrier;
    std::vector<Body> bodies;
    std::optional<Lagrangian> lagrangian;
    Forces forces;
    Effects effects;
    Simulate simulate;
    std::vector<Event> events;  // [events], file order
    std::vector<Constraint> constraints;  // [[constraint]], file order
    std::vector<Unilateral> unilateral;   // [[unilateral]], file order
    Contact contact;                      // [contact] (defaults when absent)
    std::vector<Program> programs;        // [[program]], file order
    std::string formulation = "lagrangian";  // one of formulation_names ([formulation] kind)
    SourcePos formulation_pos;
    bool kernel_jacobian = false;  // [kernel] jacobian: the generated kernel always has jacobian()
    std::optional<Reference> reference;
    std::optional<Newtonian> newtonian;  // instead of [[body]] or [lagrangian]
    std::optional<Orbit> orbit;          // instead of [coordinates] and [[body]] / [lagrangian]
    std::optional<RigidBody> rigid_body; // instead of [coordinates] and [[body]] / [lagrangian]
    Inverse inverse;
};

// Throws eomc::InputError (file:line:column) on anything malformed.
Scene parse_scene_file(const std::string& path);
Scene parse_scene_string(std::string_view toml_text, const std::string& path = "<string>");

// The orbit formulation called `name`; an unknown name throws InputError at `where` (with a
// did-you-mean).
OrbitFormulationKind parse_orbit_formulation(std::string_view name, const SourcePos& where);
// Checks an orbit formulation's name as parse_orbit_formulation does.
void check_orbit_formulation(const std::string& name, const SourcePos& where);

// `--orbit-formulation NAME`: the same scene in another formulation. The scene's name gains
// "_NAME" (even when NAME is the scene's own), so that each kernel has its own header and
// struct, and the header's name follows from the flag alone. A scene without [orbit] is
// refused at `where`.
void set_orbit_formulation(Scene& scene, const std::string& name, const SourcePos& where);

// The rigid-body formulation called `name`, as parse_orbit_formulation does for orbits.
RigidFormulationKind parse_rigid_formulation(std::string_view name, const SourcePos& where);
// parse_rigid_formulation, for a name that is only checked (--formulations).
void check_rigid_formulation(const std::string& name, const SourcePos& where);
// `--rigid-formulation NAME`, as set_orbit_formulation: the scene's name gains "_NAME". A scene
// without [rigid_body] is refused at `where`.
void set_rigid_formulation(Scene& scene, const std::string& name, const SourcePos& where);

// "disk_tube_ball" -> "DiskTubeBall"
std::string struct_name(const std::string& scene_name);

}  // namespace eomc::scene
