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
    double initial = 0.0;
    double rate = 0.0;
};

struct Particle {
    std::string name;
    GiNaC::ex mass;
    Vec3 position;  // r'(q, t) in carrier axes
};

// A carrier whose motion is prescribed: ω(t) and v_o(t) in carrier axes.
struct Carrier {
    Vec3 angular_velocity;
    Vec3 pole_velocity;
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
    std::vector<Particle> particles;
    std::optional<GiNaC::ex> kinetic_energy;  // [lagrangian] T

    GiNaC::ex potential = 0;                     // V(q, q_dot, t)
    std::vector<GiNaC::ex> generalized_forces;   // Q_s, one per coordinate (0 when not given)
    std::array<bool, 5> keep{true, true, true, true, true};  // indexed by Effect
    SourcePos kinetic_pos;                       // where T comes from (for errors about M)

    scene::Simulate simulate;
    std::optional<Newtonian> newtonian;  // equations instead of energies (no particles, no T)
    scene::Inverse inverse;

    bool keeps(Effect e) const { return keep[static_cast<int>(e)]; }
    // All symbols that are inputs of the equations: t, q, q_dot, parameters.
    GiNaC::lst state_symbols() const;
};

// Throws eomc::InputError naming the place in the scene.
Model build_model(const scene::Scene& scene);

}  // namespace eomc::model
