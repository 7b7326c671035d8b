#include "host/pipeline.hpp"

#include <iostream>
#include <string_view>

#include <fmt/format.h>

#include "codegen/cpp_emitter.hpp"
#include "eomc/runtime/registry.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/orbit/formulation.hpp"
#include "mechanics/rigid/formulation.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::host {

void StageClock::lap(const char* stage) {
    const auto now = std::chrono::steady_clock::now();
    stages_.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
    last_ = now;
}

void StageClock::print(std::ostream& out) const {
    double total = 0;
    for (const auto& [stage, seconds] : stages_) {
        out << fmt::format("timing {} {:.6f}\n", stage, seconds);
        if (std::string_view(stage) != "lower") total += seconds;  // lower is the sum of its parts
    }
    out << fmt::format("timing total {:.6f}\n", total);
}

namespace {

// The state-transition matrix Φ follows the flow of ẋ = F(t, x); a projection after every step
// moves the state off that flow, and Φ does not follow it.
void check_variational(const mechanics::Equations& eqs, const FrontEndOptions& options) {
    if (!options.variational) return;
    for (const auto& row : eqs.constraints)
        if (row.stabilization == mechanics::Stabilization::project)
            throw InputError(row.pos, fmt::format("--variational cannot follow the projection onto [[constraint]] '{}' "
                                                  "after every step; give it stabilize = \"none\" or Baumgarte's "
                                                  "{{ alpha = …, beta = … }} for the state-transition matrix",
                                                  row.name));
}

// What a rigid-body formulation cannot be combined with (its registry entry's traits).
void check_rigid_formulation_options(const model::Model& model, const FrontEndOptions& options) {
    const mechanics::rigid::RigidFormulation& f = mechanics::rigid::rigid_formulation(model.rigid->formulation);
    if ((options.hamiltonian || model.hamiltonian) && !f.hamiltonian)
        throw InputError(model.rigid->formulation_pos,
                         fmt::format("the {} formulation integrates its own equations ({}), not Hamilton's in (q, p); "
                                     "use formulation = \"euler_angles\" (or andoyer_deprit, canonical already)",
                                     f.name, f.summary));
    if (options.variational && !f.variational)
        throw InputError(model.rigid->formulation_pos,
                         fmt::format("--variational cannot follow the {} formulation's projection onto |γ| = 1 or |e| = "
                                     "1 after every step; use formulation = \"euler_angles\" or \"andoyer_deprit\" for "
                                     "the state-transition matrix",
                                     f.name));
}

// What an orbit formulation cannot be combined with (its registry entry's traits).
void check_formulation_options(const model::Model& model, const FrontEndOptions& options) {
    if (model.rigid) return check_rigid_formulation_options(model, options);
    if (!model.orbit) return;
    const mechanics::OrbitFormulation& f = mechanics::orbit_formulation(model.orbit->kind);
    if ((options.hamiltonian || model.hamiltonian) && !f.hamiltonian)
        throw InputError(model.orbit->formulation_pos,
                         fmt::format("the {} formulation integrates its own equations ({}), not Hamilton's; use "
                                     "formulation = \"cowell\" with the Hamiltonian formulation",
                                     f.name, f.summary));
    // Φ would have to follow each change of the state's variables (encke's rectifications).
    if (options.variational && !f.variational)
        throw InputError(model.orbit->formulation_pos,
                         fmt::format("--variational cannot follow the {} formulation's rectifications (each one changes "
                                     "the state's variables); use formulation = \"cowell\" for the state-transition "
                                     "matrix",
                                     f.name));
}

}  // namespace

Pipeline front_end(const std::string& scene_path, const FrontEndOptions& options, StageClock* clock) {
    scene::Scene scene = scene::parse_scene_file(scene_path);
    if (!options.orbit_formulation.empty())
        scene::set_orbit_formulation(scene, options.orbit_formulation,
                                     SourcePos{std::string(options.flag ? options.flag : "--orbit-formulation") + " " +
                                               options.orbit_formulation});
    if (!options.rigid_formulation.empty())
        scene::set_rigid_formulation(scene, options.rigid_formulation,
                                     SourcePos{std::string(options.flag ? options.flag : "--rigid-formulation") + " " +
                                               options.rigid_formulation});
    Pipeline p{model::build_model(scene), {}, std::nullopt, options.variational,
               options.jacobian || options.variational || scene.kernel_jacobian};
    for (const auto& w : p.model.warnings) std::cerr << format_warning(w) << "\n";
    if (clock) clock->lap("parse");
    p.equations = mechanics::derive(p.model);
    for (const auto& set : p.equations.singular_sets)
        std::cerr << format_warning({p.model.kinetic_pos,
                                     fmt::format("the mass matrix is singular where {} (det M has the factor ({})^{}): "
                                                 "the coordinates fail there ({}), and a simulation stops when the "
                                                 "state comes close",
                                                 set.condition, symbolic::text(set.indicator), set.order,
                                                 set.indicator.has(GiNaC::sin(GiNaC::wild())) ||
                                                         set.indicator.has(GiNaC::cos(GiNaC::wild()))
                                                     ? "gimbal lock"
                                                     : "a coordinate singularity")})
                  << "\n";
    check_formulation_options(p.model, options);
    check_variational(p.equations, options);
    if (options.hamiltonian || p.model.hamiltonian) p.canonical = mechanics::canonical_equations(p.model, p.equations);
    if (clock) clock->lap("derive");
    return p;
}

std::string kernel_header(const Pipeline& p, StageClock* clock, codegen::KernelIR* ir_out, bool jacobian) {
    codegen::LoweringTimes lowering;
    const codegen::LowerOptions options{.jacobian = p.jacobian || jacobian};
    const codegen::KernelIR ir = p.canonical ? codegen::lower(p.model, p.canonical->form, &lowering, options)
                                             : codegen::lower(p.model, p.equations, &lowering, options);
    if (ir_out) *ir_out = ir;
    if (clock) {
        clock->lap("lower");
        clock->add("cse_mass_forcing", lowering.mass_and_forcing);
        clock->add("jacobian", lowering.jacobian);
        clock->add("invariants", lowering.invariants);
    }
    std::string header = codegen::emit_header(ir, {EOMC_VERSION, p.variational});
    if (clock) clock->lap("emit");
    return header;
}

bool method_needs_jacobian(std::string_view integrator) {
    const runtime::IntegratorInfo* info = runtime::find_integrator(integrator);
    return info != nullptr && info->uses_jacobian;
}

bool depends_on_time(const Pipeline& p) {
    for (const auto& f : p.equations.forcing)
        if (f.has(p.model.t)) return true;
    for (unsigned i = 0; i < p.equations.mass_matrix.rows(); ++i)
        for (unsigned j = 0; j < p.equations.mass_matrix.cols(); ++j)
            if (p.equations.mass_matrix(i, j).has(p.model.t)) return true;
    return false;
}

}  // namespace eomc::host
