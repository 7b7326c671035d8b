// Scenes as TOML text through the generator: the model, and the kernel header eomc generate
// writes (scene → model → equations → IR → header). Needs eomc_generator.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

namespace test_support {

// The model of a scene given as text; `file` is the name its diagnostics carry.
inline eomc::model::Model model_of(const std::string& toml, const std::string& file = "test.toml") {
    return eomc::model::build_model(eomc::scene::parse_scene_string(toml, file));
}

// The model of a bundled scene, scenes/<name>.toml.
inline eomc::model::Model bundled_model(const std::string& name) {
    return eomc::model::build_model(
        eomc::scene::parse_scene_file(std::string(EOMC_SOURCE_DIR) + "/scenes/" + name + ".toml"));
}

// The text of a bundled scene.
inline std::string bundled_scene(const std::string& name) {
    std::ifstream in(std::string(EOMC_SOURCE_DIR) + "/scenes/" + name + ".toml");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

struct Kernel {
    std::string header, struct_name;
};

struct KernelOptions {
    bool hamiltonian = false;  // Hamilton's equations instead of Lagrange's
    bool variational = false;  // with the variational equations (--variational)
    bool jacobian = false;     // with jacobian() (--jacobian; --variational implies it)
};

// The kernel header `eomc generate` writes for the scene.
inline Kernel kernel_of(const std::string& toml, KernelOptions options = {}) {
    const auto model = model_of(toml);
    const auto equations = eomc::mechanics::derive(model);
    const eomc::codegen::LowerOptions lowering{.jacobian = options.jacobian || options.variational};
    const auto ir =
        options.hamiltonian
            ? eomc::codegen::lower(model, eomc::mechanics::canonical_equations(model, equations).form, nullptr, lowering)
            : eomc::codegen::lower(model, equations, nullptr, lowering);
    return {eomc::codegen::emit_header(ir, {EOMC_VERSION, options.variational}), model.struct_name};
}

}  // namespace test_support
