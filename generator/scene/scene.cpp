// Stage 1 entry points: a scene file or text read (the Reader, reader.hpp, in the order of its
// tables and with the checks across them), formulations chosen, names for the kernel's struct.
#include "scene/scene.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "scene/reader.hpp"
#include "support/identifier.hpp"

namespace eomc::scene {

Scene Reader::read() {
    Scene s;
    check_keys(root_, {"scene", "parameters", "coordinates", "carrier", "body", "lagrangian", "forces",
                       "effects", "simulate", "events", "formulation", "reference", "newtonian", "inverse", "orbit",
                       "constraint", "rigid_body", "unilateral", "contact", "program", "kernel"},
               "at the top level");
    read_scene(s);
    read_parameters(s);
    read_orbit(s);
    read_rigid_body(s);
    read_coordinates(s);
    check_name_clashes(s);
    read_carrier(s);
    read_bodies(s);
    read_lagrangian(s);
    read_forces(s);
    read_effects(s);
    read_simulate(s);
    read_events(s);
    read_constraints(s);
    read_formulation(s);
    read_kernel(s);
    read_reference(s);
    read_newtonian(s);
    read_inverse(s);
    read_unilateral(s);
    read_contact(s);
    read_programs(s);
    check_orbit_structure();
    check_rigid_structure();
    check_newtonian_structure();
    check_structure();
    return s;
}

// Bodies (with an optional carrier and effects) or a Lagrangian: one or the other.
void Reader::check_structure() const {
    const toml::node* lagrangian = root_.get("lagrangian");
    const toml::node* body = root_.get("body");
    const toml::node* carrier = root_.get("carrier");
    const toml::node* effects = root_.get("effects");
    if (lagrangian) {
        const std::pair<const toml::node*, const char*> others[] = {
            {body, "[[body]]"}, {carrier, "[carrier]"}, {effects, "[effects]"}};
        for (const auto& [other, title] : others) {
            if (!other) continue;
            const bool lagrangian_later = before(at(*other), at(*lagrangian));
            const toml::node& later = lagrangian_later ? *lagrangian : *other;
            const toml::node& earlier = lagrangian_later ? *other : *lagrangian;
            fail(at(later),
                 fmt::format("{} cannot be combined with {} (line {}); a scene gives either carried bodies "
                             "([[body]], with an optional [carrier] and [effects]) or a [lagrangian]",
                             lagrangian_later ? "[lagrangian]" : title, lagrangian_later ? title : "[lagrangian]",
                             at(earlier).line));
        }
    } else if (!body && !root_.get("newtonian") && !root_.get("orbit") && !root_.get("rigid_body")) {
        fail(top(), "the scene has neither [[body]] nor [lagrangian] nor [newtonian] nor [orbit] nor [rigid_body]; "
                    "give carried bodies, a lagrangian L = T - V, the equations of motion, an orbit or a rigid body "
                    "about a fixed point");
    }
    if (effects && !carrier && !root_.get("orbit"))
        fail(at(*effects), "[effects] requires a [carrier] (inertial effects of a moving frame) or an [orbit] "
                           "(perturbations of an orbit)");
}

OrbitFormulationKind parse_orbit_formulation(std::string_view name, const SourcePos& where) {
    for (std::size_t k = 0; k < orbit_formulation_names.size(); ++k)
        if (orbit_formulation_names[k] == name) return static_cast<OrbitFormulationKind>(k);
    const std::vector<std::string> names(orbit_formulation_names.begin(), orbit_formulation_names.end());
    const std::string near = nearest_name(std::string(name), names);
    throw InputError(where, fmt::format("unknown orbit formulation '{}'; {}", name,
                                        near.empty() ? fmt::format("expected one of {}", fmt::join(names, ", "))
                                                     : fmt::format("did you mean '{}'?", near)));
}

void check_orbit_formulation(const std::string& name, const SourcePos& where) { parse_orbit_formulation(name, where); }

void set_orbit_formulation(Scene& scene, const std::string& name, const SourcePos& where) {
    if (!scene.orbit)
        throw InputError(where, fmt::format("{} has no [orbit]; only an orbit scene has a formulation to choose",
                                            scene.path.empty() ? "the scene" : scene.path));
    const OrbitFormulationKind kind = parse_orbit_formulation(name, where);
    scene.name += "_" + name;
    scene.orbit->formulation = kind;
    scene.orbit->formulation_pos = where;
}

RigidFormulationKind parse_rigid_formulation(std::string_view name, const SourcePos& where) {
    for (std::size_t k = 0; k < rigid_formulation_names.size(); ++k)
        if (rigid_formulation_names[k] == name) return static_cast<RigidFormulationKind>(k);
    const std::vector<std::string> names(rigid_formulation_names.begin(), rigid_formulation_names.end());
    const std::string near = nearest_name(std::string(name), names);
    throw InputError(where, fmt::format("unknown rigid-body formulation '{}'; {}", name,
                                        near.empty() ? fmt::format("expected one of {}", fmt::join(names, ", "))
                                                     : fmt::format("did you mean '{}'?", near)));
}

void check_rigid_formulation(const std::string& name, const SourcePos& where) { parse_rigid_formulation(name, where); }

void set_rigid_formulation(Scene& scene, const std::string& name, const SourcePos& where) {
    if (!scene.rigid_body)
        throw InputError(where, fmt::format("{} has no [rigid_body]; only a rigid-body scene has a formulation to "
                                            "choose",
                                            scene.path.empty() ? "the scene" : scene.path));
    const RigidFormulationKind kind = parse_rigid_formulation(name, where);
    scene.name += "_" + name;
    scene.rigid_body->formulation = kind;
    scene.rigid_body->formulation_pos = where;
}

Scene parse_scene_string(std::string_view toml_text, const std::string& path) {
    return Reader(toml_text, path).read();
}

Scene parse_scene_file(const std::string& path) {
    const SourcePos where{path, 0, 0};
    // A scene is a regular file of bounded size: /dev/zero, a FIFO or a huge file would never
    // finish reading (or fill memory) before the first line is checked. O_NONBLOCK keeps the
    // open of a FIFO from waiting for a writer; the type is checked on what was opened.
    constexpr std::size_t max_scene_bytes = 4u << 20;
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        throw InputError(where, fmt::format("cannot open scene file '{}': {}", path, lower_first(std::strerror(err))));
    }
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0)
        throw InputError(where, fmt::format("cannot read scene file '{}': {}", path, lower_first(std::strerror(errno))));
    if (S_ISDIR(info.st_mode))
        throw InputError(where, fmt::format("cannot read scene file '{}': it is a directory", path));
    if (!S_ISREG(info.st_mode))
        throw InputError(where, fmt::format("cannot read scene file '{}': it is not a regular file", path));
    std::string text;
    char buffer[65536];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw InputError(where, fmt::format("cannot read scene file '{}': read error", path));
        if (n == 0) break;
        text.append(buffer, std::size_t(n));
        if (text.size() > max_scene_bytes)
            throw InputError(where, fmt::format("cannot read scene file '{}': it is larger than {} MiB", path,
                                                max_scene_bytes >> 20));
    }
    Scene s = parse_scene_string(text, path);
    s.path = path;
    return s;
}

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
