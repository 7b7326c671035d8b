#include "scene/scene.hpp"

#include <cctype>

namespace eomc::scene {

std::string struct_name(const std::string& scene_name) {
    std::string out;
    bool upper = true;
    for (char c : scene_name) {
        if (c == '_') {
            upper = true;
            continue;
        }
        out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
        upper = false;
    }
    return out;
}

}  // namespace eomc::scene
