// build_model's steps, one per scene table or model kind (one file each: carried_bodies.cpp,
// newtonian.cpp, orbit.cpp, rigid_body.cpp, rows.cpp, programs.cpp), and the parsing helpers they
// share (model.cpp). Private to model/: the stage's interface is model.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "model/expression_parser.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

namespace eomc::model {

// The symbols an expression may hold, by what it describes.
inline constexpr unsigned time_and_parameters = SymbolKind::time | SymbolKind::parameter;
inline constexpr unsigned configuration = time_and_parameters | SymbolKind::coordinate;
inline constexpr unsigned phase = configuration | SymbolKind::velocity;

Vec3 parse_vector(const SymbolTable& symbols, const scene::Vec3& v, unsigned allowed, const std::string& what);

// e at `values` as a real float, or nothing where it is undefined there: GiNaC throws when the
// values reach a pole (log(0), 1/0) and leaves a non-numeric or complex value otherwise.
std::optional<GiNaC::numeric> real_value(const GiNaC::ex& e, const GiNaC::exmap& values);

// A mass must be a positive constant: evaluate it at the parameters' defaults.
GiNaC::ex parse_mass(const SymbolTable& symbols, const scene::Body& body, const Model& model);

// 3 principal moments or 9 entries → a symmetric 3×3 matrix of constants.
GiNaC::matrix parse_inertia(const SymbolTable& symbols, const std::vector<scene::Expr>& entries, const SourcePos& pos,
                            const std::string& what);

// The value of an expression of the parameters at their defaults (for the initial state).
double at_defaults(const GiNaC::ex& e, const Model& model, const scene::Expr& where, const std::string& what);

// The model kinds (model.hpp, ModelKind), each from its tables.
void build_carried_bodies(const scene::Scene& scene, SymbolTable& symbols, Model& model);  // [carrier], [[body]]
Newtonian build_newtonian(const SymbolTable& symbols, const scene::Newtonian& given, const Model& model);
void build_orbit(const scene::Scene& scene, SymbolTable& symbols, Model& model);
void build_rigid_body(const scene::Scene& scene, SymbolTable& symbols, Model& model);

// The rows, after the coordinates: [[constraint]], [[unilateral]] with [contact], [[program]], and
// the constraint rows turned into ideal programs where programs are given.
void build_constraints(const scene::Scene& scene, const SymbolTable& symbols, Model& model);
void build_unilateral(const scene::Scene& scene, const SymbolTable& symbols, Model& model);
void build_programs(const scene::Scene& scene, const SymbolTable& symbols, Model& model);
void constraints_as_programs(const scene::Scene& scene, Model& model);

}  // namespace eomc::model
