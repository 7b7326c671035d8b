// libFuzzer target: any bytes as a scene, taken through the front end past build_model — the
// equations derived (mechanics::derive: the [[program]] rows' count and rank, the degenerate
// [[unilateral]] and [[constraint]] rows, the [rigid_body] formulations), Hamilton's form when the
// scene asks for it, then lowered and emitted as a kernel header — the way `eomc generate` does —
// and the start checked as `eomc simulate` checks it (mechanics::check_start).
// A refusal must be an InputError or an EmitError (both exit 2 in cli/main.cpp); anything else is a
// finding. The symbolic work grows with the model, so only small ones go past build_model: at most
// three velocities and four rows, and expressions of a bounded size (a scene beyond these is
// the scene target's, which reads and builds every size); -timeout bounds the rest.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "codegen/cpp_emitter.hpp"
#include "codegen/cpp_text.hpp"
#include "codegen/kernel_ir.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/start.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

namespace {

// The number of nodes of e's expression tree, counting up to `limit`.
std::size_t nodes(const GiNaC::ex& e, std::size_t limit) {
    std::size_t n = 1;
    for (std::size_t i = 0; i < e.nops() && n <= limit; ++i) n += nodes(e.op(i), limit - n);
    return n;
}

bool small(const eomc::model::Model& m) {
    constexpr std::size_t max_nodes = 400;
    if (m.velocity_names().size() > 3 || m.particles.size() > 3) return false;
    if (m.constraints.size() + m.unilateral.size() + m.programs.size() + m.events.size() > 4) return false;
    std::size_t total = nodes(m.potential, max_nodes);
    if (m.kinetic_energy) total += nodes(*m.kinetic_energy, max_nodes);
    for (const auto& q : m.generalized_forces) total += nodes(q, max_nodes);
    for (const auto& c : m.constraints) total += nodes(c.expression, max_nodes);
    for (const auto& u : m.unilateral) total += nodes(u.expression, max_nodes);
    for (const auto& p : m.programs) total += nodes(p.expression, max_nodes);
    for (const auto& b : m.particles) {
        total += nodes(b.mass, max_nodes) + nodes(b.inertia, max_nodes);
        for (const auto& r : b.position) total += nodes(r, max_nodes);
        for (const auto& [axis, angle] : b.orientation) total += nodes(angle, max_nodes);
    }
    if (m.newtonian)
        for (const auto& f : m.newtonian->expressions) total += nodes(f, max_nodes);
    return total <= max_nodes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const eomc::scene::Scene scene = eomc::scene::parse_scene_string(text, "fuzz.toml");
        const eomc::model::Model model = eomc::model::build_model(scene);
        if (!small(model)) return 0;
        const eomc::mechanics::Equations equations = eomc::mechanics::derive(model);
        const eomc::codegen::KernelIR ir =
            model.hamiltonian
                ? eomc::codegen::lower(model, eomc::mechanics::canonical_equations(model, equations).form)
                : eomc::codegen::lower(model, equations);
        (void)eomc::codegen::emit_header(ir, {"fuzz", false});
        eomc::mechanics::check_start(model, equations, eomc::mechanics::start_values(model, {}),
                                     "with the scene's initial values and default parameters");
    } catch (const eomc::InputError&) {
        // a refusal with its place
    } catch (const eomc::codegen::EmitError&) {
        // what a kernel cannot hold (a constant beyond double's range, …)
    }
    return 0;
}
