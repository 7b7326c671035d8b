// The rigid-body formulations (Mei, ch. 5), one registry entry each: what the kernel of a
// [rigid_body] scene integrates. Every one is the Euler–Poisson system (euler_poisson.hpp) in its
// own variables; each writes ω and γ as functions of its state, so that events, integrals and the
// outputs p, q, r, gamma1..3 mean the same whatever the kernel integrates. Adding a formulation:
// an enumerator and its name in scene/scene.hpp, its reserved names in model/rigid_body.cpp, its entry and
// builder here.
#pragma once

#include <span>
#include <string_view>

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

namespace eomc::mechanics::rigid {

using RigidFormulationKind = scene::RigidFormulationKind;

struct RigidFormulation {
    RigidFormulationKind kind;
    std::string_view name;     // as [rigid_body] formulation and --rigid-formulation spell it
    std::string_view summary;  // one line: the state and the equations
    FirstOrderForm (*build)(const model::Model& model, const Equations& equations);
    bool hamiltonian;  // Hamilton's equations in (q, p) apply (a Lagrangian in coordinates)
    bool variational;  // --variational applies: the state keeps its meaning along a run
};

const RigidFormulation& rigid_formulation(RigidFormulationKind kind);
std::span<const RigidFormulation> rigid_formulations();

FirstOrderForm euler_poisson_form(const model::Model& model, const Equations& equations);
FirstOrderForm quaternion_form(const model::Model& model, const Equations& equations);
FirstOrderForm euler_angles_form(const model::Model& model, const Equations& equations);
FirstOrderForm andoyer_deprit_form(const model::Model& model, const Equations& equations);

}  // namespace eomc::mechanics::rigid
