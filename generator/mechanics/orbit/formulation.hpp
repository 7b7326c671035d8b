// The orbit formulations (Mei, ch. 2), one registry entry each: what the kernel of an orbit
// scene integrates. The scene stage reads the name into scene::OrbitFormulationKind; everything
// that depends on the choice asks here. Adding a formulation: an enumerator and its name in
// scene/scene.hpp, its entry in formulation.cpp, and its builder (plus, when the initial orbit
// can lie outside its domain, a case in model::build_model's check_formulation_domain).
#pragma once

#include <span>
#include <string_view>

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

namespace eomc::mechanics {

using OrbitFormulationKind = scene::OrbitFormulationKind;

struct OrbitFormulation {
    OrbitFormulationKind kind;
    std::string_view name;     // as [orbit] formulation and --orbit-formulation spell it
    std::string_view summary;  // one line: the state and the equations
    // The kernel's state, in order; a parameter may not take one of these names when
    // `reserves_state_names` (the others' clashes the emitter resolves by renaming).
    std::span<const std::string_view> state_names;
    bool reserves_state_names;
    // The first-order form the kernel integrates, from the model and its Cowell equations.
    FirstOrderForm (*build)(const model::Model& model, const Equations& cowell);
    bool hamiltonian;  // Hamilton's equations in (q, p) apply: the state is Cowell's (x, ẋ)
    bool variational;  // --variational applies: the state keeps its meaning along a run
};

const OrbitFormulation& orbit_formulation(OrbitFormulationKind kind);
// Every formulation, in OrbitFormulationKind order.
std::span<const OrbitFormulation> orbit_formulations();

bool hamiltonian_applies(OrbitFormulationKind kind);
bool variational_applies(OrbitFormulationKind kind);

// An orbit model whose parameters leave its formulation's reserved state names free; InputError
// at the formulation otherwise.
void check_state_names_free(const model::Model& model);

}  // namespace eomc::mechanics
