// The scene reader (parse_scene_string): one scene text read table by table, each table's reader in
// its file (read_*.cpp), the tools they share in reader.cpp, the order and the checks across tables
// in scene.cpp. Private to scene/: the stage's interface is scene.hpp.
#pragma once

#include <array>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "scene/scene.hpp"

namespace eomc::scene {

bool is_scene_name(std::string_view s);
std::string lower_first(std::string s);
std::string join(std::initializer_list<const char*> names);
// "a string", "an integer", ...: the TOML type of a node, for "expected X, got Y".
std::string type_name(const toml::node& n);
// A literal number written as an expression ("2", "-0.5", "1e-3"), if the text is one.
std::optional<double> literal_number(std::string_view text);
bool before(const SourcePos& a, const SourcePos& b);
using Entry = std::pair<const toml::key*, const toml::node*>;

class Reader {
public:
    Reader(std::string_view text, std::string file);
    Scene read();

private:
    // The tools (reader.cpp): positions, errors, tables and keys, values, names, rows.
    void split_lines(std::string_view text);
    SourcePos at(const toml::source_region& r) const;
    SourcePos at(const toml::node& n) const { return at(n.source()); }
    SourcePos at(const toml::key& k) const { return at(k.source()); }
    SourcePos top() const { return SourcePos{file_, 1, 1}; }

    // The source text from (line, column) to the end of that line; toml++ counts columns
    // in code points, so step over UTF-8 continuation bytes.
    std::string_view text_from(const SourcePos& p) const;

    // Where the text of a string value starts: after the opening quote(s); a multi-line
    // string that opens with a newline starts on the next line.
    SourcePos string_text_pos(const toml::node& n) const;

    // The literal of a number value as written, without digit separators or a leading '+'.
    std::string number_text(const toml::node& n) const;

    [[noreturn]] static void fail(const SourcePos& pos, const std::string& message);
    static std::string syntax_message(std::string description);

    // A table's entries in file order (toml++ keeps them sorted by name).
    static std::vector<Entry> entries(const toml::table& t);

    void check_keys(const toml::table& t, std::initializer_list<const char*> allowed, const std::string& where) const;
    const toml::table& as_table(const toml::node& n, const std::string& path) const;
    const toml::node& require(const toml::table& t, const char* key, const std::string& where) const;
    std::string read_string(const toml::node& n, const std::string& path) const;
    double read_number(const toml::node& n, const std::string& path) const;
    bool read_bool(const toml::node& n, const std::string& path) const;
    double read_positive(const toml::node& n, const std::string& path) const;
    Expr read_expr(const toml::node& n, const std::string& path) const;
    Vec3 read_vec3(const toml::node& n, const std::string& path) const;
    static Vec3 zero_vec3(const SourcePos& pos) { return Vec3{Expr{"0", pos}, Expr{"0", pos}, Expr{"0", pos}}; }

    // Parameters and coordinates become symbols: they must not shadow the time, the
    // built-in functions and constants, or the derived names q_dot / q_ddot.
    void check_symbol_name(const std::string& name, const SourcePos& pos, const char* kind) const;

    // Three principal moments, or a 3×3 matrix as 9 entries or 3 rows of 3.
    std::vector<Expr> read_inertia(const toml::node& n, const std::string& path) const;

    std::array<double, 3> read_numbers3(const toml::node& n, const std::string& path) const;

    // An array of tables [[key]] (`title`): its elements, each checked to be a table. Absent: none.
    std::vector<const toml::table*> table_array(const char* key, const char* title, const char* noun) const;

    // A row's `name`: an identifier not yet in `seen` (which it joins). `noun` names the row's
    // kind in the messages; `duplicate` says what an earlier row of that name was.
    std::string read_row_name(const toml::table& t, const std::string& path, const char* title, const char* noun,
                              std::map<std::string, std::pair<SourcePos, std::string>>& seen, SourcePos& name_pos) const;

    // Exactly one of the keys `a` and `b` of a row's table: the node and whether it is `a`. Both are
    // refused at the later one with `both`, neither at the table with `neither`.
    std::pair<const toml::node*, bool> exactly_one(const toml::table& t, const char* a, const char* b,
                                                   const std::string& both, const std::string& neither) const;

    // read_declarations.cpp
    void read_scene(Scene& s) const;
    void read_parameters(Scene& s) const;
    void read_coordinates(Scene& s) const;
    void check_name_clashes(const Scene& s) const;

    // read_carried_bodies.cpp
    void read_carrier(Scene& s) const;
    void read_bodies(Scene& s) const;
    std::vector<Rotation> read_orientation(const toml::node& n, const std::string& path) const;

    // read_energies.cpp
    void read_lagrangian(Scene& s) const;
    void read_forces(Scene& s) const;
    void read_effects(Scene& s) const;
    void read_custom_effects(Scene& s, const toml::table& t) const;

    // read_orbit.cpp
    void read_orbit(Scene& s) const;
    std::array<double, 6> read_elements(const toml::table& t) const;
    void check_orbit_structure() const;

    // read_rigid_body.cpp
    void read_rigid_body(Scene& s) const;
    void check_rigid_structure() const;

    // read_run.cpp
    void read_formulation(Scene& s) const;
    void read_kernel(Scene& s) const;
    void read_simulate(Scene& s) const;
    void read_events(Scene& s) const;
    void read_reference(Scene& s) const;

    // read_constraints.cpp
    void read_constraints(Scene& s) const;

    // read_unilateral.cpp
    void read_unilateral(Scene& s) const;
    void read_contact(Scene& s) const;

    // read_programs.cpp
    void read_programs(Scene& s) const;
    void refuse_programs(const Scene& s, const SourcePos& first) const;
    void read_erugin(const toml::table& t, const std::string& path, Program& p) const;
    void read_program_control(const toml::table& t, const std::string& path, const Scene& s, Program& p) const;

    // read_newtonian.cpp
    void read_newtonian(Scene& s) const;
    void read_inverse(Scene& s) const;
    void check_newtonian_structure() const;

    // scene.cpp
    void check_structure() const;

    std::string file_;
    std::vector<std::string> lines_;
    toml::table root_;
};

}  // namespace eomc::scene
