// libFuzzer target: any bytes as a scene file, read and built into a model. A scene that is
// refused must be refused with an InputError (its place and reason); anything else — a crash,
// undefined behaviour, another exception, a hang, unbounded memory — is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const eomc::scene::Scene scene = eomc::scene::parse_scene_string(text, "fuzz.toml");
        eomc::model::build_model(scene);
    } catch (const eomc::InputError&) {
        // a refusal with its place: the expected outcome for most inputs
    }
    return 0;
}
