#include "host/formulation_bench.hpp"

#include <fmt/format.h>

#include "scene/scene.hpp"

namespace eomc::host {

Pipeline add_formulations(BenchRequest& r, const std::string& scene_path, const FormulationFamily& family,
                          const std::vector<std::string>& asked, const std::string& single) {
    std::vector<std::string> names = asked;
    if (names.empty() && !single.empty()) names = {single};
    if (names.empty()) names.assign(family.names.begin(), family.names.end());
    for (const auto& name : names) family.check(name, SourcePos{"--formulations"});
    const auto formulation = [&](const std::string& name) {
        FrontEndOptions options;
        options.*family.option = name;
        options.flag = "--formulations";
        return front_end(scene_path, options);
    };
    const std::string& reference = r.axis.reference;
    const Pipeline ref = formulation(reference);
    r.header_text = kernel_header(ref);
    r.struct_name = ref.model.struct_name;
    r.scene_name = scene::parse_scene_file(scene_path).name;  // not a formulation's kernel name
    r.reference_body.clear();
    const bool all_built = asked.empty() && single.empty();
    for (const auto& name : names) {
        try {
            const Pipeline f = name == reference ? ref : formulation(name);
            r.formulations.push_back({name, name == reference ? r.header_text : kernel_header(f), f.model.struct_name,
                                      f.model.name, !depends_on_time(f)});
        } catch (const InputError& e) {
            // Asked for by name: bad input. Among "all built": a formulation that does not take
            // this scene (mean with drag, Euler angles at gimbal lock) is left out, and the table
            // says why.
            if (!all_built) throw;
            r.skipped.push_back(fmt::format("{}: left out: {}", name, e.message()));
        }
    }
    if (r.formulations.empty())
        throw InputError(SourcePos{"--formulations"},
                         "no formulation takes this scene: " + fmt::format("{}", fmt::join(r.skipped, "; ")));
    return ref;
}

}  // namespace eomc::host
