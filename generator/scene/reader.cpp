// The reader's tools: positions in the scene text, errors, tables and keys, values, names, and the
// row tables' shared steps ([[constraint]], [[unilateral]], [[program]]).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "scene/reader.hpp"
#include "support/identifier.hpp"

namespace eomc::scene {

bool is_scene_name(std::string_view s) {
    if (s.empty() || !(s[0] >= 'a' && s[0] <= 'z')) return false;
    return std::all_of(s.begin() + 1, s.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
}

std::string lower_first(std::string s) {
    if (!s.empty()) s[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
    return s;
}

std::string join(std::initializer_list<const char*> names) {
    std::string out;
    for (const char* n : names) {
        if (!out.empty()) out += ", ";
        out += n;
    }
    return out;
}

std::string type_name(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array";
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a float";
        case toml::node_type::boolean: return "a boolean";
        case toml::node_type::date: return "a date";
        case toml::node_type::time: return "a time";
        case toml::node_type::date_time: return "a date-time";
        default: return "nothing";
    }
}

std::optional<double> literal_number(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    if (text.empty()) return std::nullopt;
    double v = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

bool before(const SourcePos& a, const SourcePos& b) {
    return std::pair(a.line, a.column) < std::pair(b.line, b.column);
}

namespace {

const char* const reserved_functions[] = {"sin", "cos", "tan", "exp", "log", "sqrt", "asin", "acos", "atan"};

}  // namespace

Reader::Reader(std::string_view text, std::string file) : file_(std::move(file)) {
    // A UTF-8 byte order mark is not part of the first line's columns.
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    split_lines(text);
    try {
        root_ = toml::parse(text, std::string_view(file_));
    } catch (const toml::parse_error& e) {
        fail(at(e.source()), syntax_message(std::string(e.description())));
    }
}

void Reader::split_lines(std::string_view text) {
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t nl = text.find('\n', start);
        if (nl == std::string_view::npos) nl = text.size();
        std::string line(text.substr(start, nl - start));
        if (!line.empty() && line.back() == '\r') line.pop_back();
        lines_.push_back(std::move(line));
        start = nl + 1;
    }
}

SourcePos Reader::at(const toml::source_region& r) const {
    return SourcePos{file_, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
}

std::string_view Reader::text_from(const SourcePos& p) const {
    if (p.line < 1 || static_cast<std::size_t>(p.line) > lines_.size()) return {};
    std::string_view line = lines_[static_cast<std::size_t>(p.line - 1)];
    std::size_t i = 0;
    for (int col = 1; col < p.column && i < line.size(); ++col) {
        ++i;
        while (i < line.size() && (static_cast<unsigned char>(line[i]) & 0xC0) == 0x80) ++i;
    }
    return line.substr(i);
}

SourcePos Reader::string_text_pos(const toml::node& n) const {
    SourcePos p = at(n);
    const std::string_view src = text_from(p);
    if (src.substr(0, 3) == "\"\"\"" || src.substr(0, 3) == "'''") {
        if (src.size() == 3) return SourcePos{file_, p.line + 1, 1};
        return p.shifted(3);
    }
    if (!src.empty() && (src[0] == '"' || src[0] == '\'')) return p.shifted(1);
    return p;
}

std::string Reader::number_text(const toml::node& n) const {
    const std::string_view src = text_from(at(n));
    std::string out;
    for (char c : src) {
        if (std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.') {
            out += c == 'E' ? 'e' : c;
        } else if (c != '_') {
            break;
        }
    }
    if (!out.empty() && out[0] == '+') out.erase(0, 1);
    return out;
}

void Reader::fail(const SourcePos& pos, const std::string& message) {
    throw InputError(pos, message);
}

std::string Reader::syntax_message(std::string description) {
    static constexpr std::string_view prefix = "Error while parsing ";
    if (description.rfind(prefix, 0) == 0) {
        const std::string rest = description.substr(prefix.size());
        const std::size_t colon = rest.find(": ");
        if (colon != std::string::npos)
            return fmt::format("invalid TOML in {}: {}", rest.substr(0, colon), rest.substr(colon + 2));
        return "invalid TOML in " + rest;
    }
    return "invalid TOML: " + lower_first(std::move(description));
}

std::vector<Entry> Reader::entries(const toml::table& t) {
    std::vector<Entry> out;
    for (const auto& [k, v] : t) out.emplace_back(&k, &v);
    std::stable_sort(out.begin(), out.end(), [](const Entry& a, const Entry& b) {
        const auto& pa = a.first->source().begin;
        const auto& pb = b.first->source().begin;
        return std::pair(pa.line, pa.column) < std::pair(pb.line, pb.column);
    });
    return out;
}

void Reader::check_keys(const toml::table& t, std::initializer_list<const char*> allowed, const std::string& where) const {
    for (const auto& [key, node] : entries(t)) {
        const std::string name(key->str());
        if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return name == a; })) continue;
        const std::string near = nearest_name(name, allowed);
        if (!near.empty())
            fail(at(*key), fmt::format("unknown key '{}' {}; did you mean '{}'?", name, where, near));
        fail(at(*key), fmt::format("unknown key '{}' {}; expected one of: {}", name, where, join(allowed)));
    }
}

const toml::table& Reader::as_table(const toml::node& n, const std::string& path) const {
    if (const toml::table* t = n.as_table()) return *t;
    fail(at(n), fmt::format("'{}': expected a table, got {}", path, type_name(n)));
}

const toml::node& Reader::require(const toml::table& t, const char* key, const std::string& where) const {
    if (const toml::node* n = t.get(key)) return *n;
    fail(at(t), fmt::format("missing required key '{}' in {}", key, where));
}

std::string Reader::read_string(const toml::node& n, const std::string& path) const {
    if (const auto* s = n.as_string()) return s->get();
    fail(at(n), fmt::format("'{}': expected a string, got {}", path, type_name(n)));
}

double Reader::read_number(const toml::node& n, const std::string& path) const {
    double v = 0.0;
    if (const auto* i = n.as_integer()) {
        v = static_cast<double>(i->get());
    } else if (const auto* f = n.as_floating_point()) {
        v = f->get();
    } else {
        fail(at(n), fmt::format("'{}': expected a number, got {}", path, type_name(n)));
    }
    if (!std::isfinite(v)) fail(at(n), fmt::format("'{}': expected a finite number, got {}", path, number_text(n)));
    return v;
}

bool Reader::read_bool(const toml::node& n, const std::string& path) const {
    if (const auto* b = n.as_boolean()) return b->get();
    fail(at(n), fmt::format("'{}': expected true or false, got {}", path, type_name(n)));
}

double Reader::read_positive(const toml::node& n, const std::string& path) const {
    const double v = read_number(n, path);
    if (!(v > 0.0)) fail(at(n), fmt::format("'{}' must be positive, got {}", path, number_text(n)));
    return v;
}

Expr Reader::read_expr(const toml::node& n, const std::string& path) const {
    if (const auto* s = n.as_string()) {
        const std::string& text = s->get();
        if (std::all_of(text.begin(), text.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); }))
            fail(at(n), fmt::format("'{}': empty expression", path));
        return Expr{text, string_text_pos(n)};
    }
    if (const auto* i = n.as_integer()) return Expr{std::to_string(i->get()), at(n)};
    if (n.is_floating_point()) {
        if (!std::isfinite(n.as_floating_point()->get()))
            fail(at(n), fmt::format("'{}': expected a finite number, got {}", path, number_text(n)));
        return Expr{number_text(n), at(n)};
    }
    fail(at(n), fmt::format("'{}': expected an expression (a string or a number), got {}", path, type_name(n)));
}

Vec3 Reader::read_vec3(const toml::node& n, const std::string& path) const {
    const toml::array* a = n.as_array();
    if (!a) fail(at(n), fmt::format("'{}': expected an array of 3 expressions, got {}", path, type_name(n)));
    if (a->size() != 3) fail(at(n), fmt::format("'{}': expected 3 components, got {}", path, a->size()));
    Vec3 v;
    for (std::size_t i = 0; i < 3; ++i) v[i] = read_expr(*a->get(i), fmt::format("{}[{}]", path, i));
    return v;
}

std::vector<Expr> Reader::read_inertia(const toml::node& n, const std::string& path) const {
    const toml::array* a = n.as_array();
    if (!a) fail(at(n), fmt::format("'{}': expected 3 principal moments or a 3×3 array, got {}", path, type_name(n)));
    std::vector<Expr> out;
    if (a->size() == 3 && a->get(0)->is_array()) {
        for (std::size_t i = 0; i < 3; ++i) {
            const Vec3 row = read_vec3(*a->get(i), fmt::format("{}[{}]", path, i));
            out.insert(out.end(), row.begin(), row.end());
        }
    } else if (a->size() == 3 || a->size() == 9) {
        for (std::size_t i = 0; i < a->size(); ++i) out.push_back(read_expr(*a->get(i), fmt::format("{}[{}]", path, i)));
    } else {
        fail(at(n), fmt::format("'{}': expected 3 principal moments or a 3×3 array, got {} entries", path, a->size()));
    }
    return out;
}

std::array<double, 3> Reader::read_numbers3(const toml::node& n, const std::string& path) const {
    const toml::array* a = n.as_array();
    if (!a) fail(at(n), fmt::format("'{}': expected an array of 3 numbers, got {}", path, type_name(n)));
    if (a->size() != 3) fail(at(n), fmt::format("'{}': expected 3 numbers, got {}", path, a->size()));
    std::array<double, 3> v{};
    for (std::size_t i = 0; i < 3; ++i) v[i] = read_number(*a->get(i), fmt::format("{}[{}]", path, i));
    return v;
}

void Reader::check_symbol_name(const std::string& name, const SourcePos& pos, const char* kind) const {
    if (!is_scene_identifier(name))
        fail(pos, fmt::format("invalid {} name '{}': expected a letter followed by letters, digits or underscores",
                              kind, name));
    if (name == "t") fail(pos, fmt::format("'t' is reserved for the time and cannot name a {}", kind));
    if (name == "Pi") fail(pos, fmt::format("'Pi' is reserved for the constant pi and cannot name a {}", kind));
    for (const char* f : reserved_functions)
        if (name == f)
            fail(pos, fmt::format("'{}' is reserved for a built-in function and cannot name a {}", name, kind));
    const auto ends_with = [&](std::string_view suffix) {
        return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    if (ends_with("_ddot"))
        fail(pos, fmt::format("{} name '{}' ends in '_ddot', which is reserved for generalized accelerations",
                              kind, name));
    if (ends_with("_dot"))
        fail(pos, fmt::format("{} name '{}' ends in '_dot', which is reserved for generalized velocities", kind,
                              name));
}

std::vector<const toml::table*> Reader::table_array(const char* key, const char* title, const char* noun) const {
    std::vector<const toml::table*> out;
    const toml::node* node = root_.get(key);
    if (!node) return out;
    const toml::array* rows = node->as_array();
    if (!rows)
        fail(at(*node), fmt::format("'{}': expected an array of tables ({}), got {}", key, title, type_name(*node)));
    if (rows->empty())
        fail(at(*node), fmt::format("'{}': expected at least one {}; an empty array declares no {}", key, title, noun));
    for (std::size_t i = 0; i < rows->size(); ++i) {
        const toml::node& element = *rows->get(i);
        if (!element.is_table())
            fail(at(element), fmt::format("'{}[{}]': expected a table, got {}", key, i, type_name(element)));
        out.push_back(element.as_table());
    }
    return out;
}

std::string Reader::read_row_name(const toml::table& t, const std::string& path, const char* title, const char* noun,
                                  std::map<std::string, std::pair<SourcePos, std::string>>& seen, SourcePos& name_pos) const {
    const toml::node& name = require(t, "name", title);
    std::string value = read_string(name, path + ".name");
    name_pos = at(name);
    if (!is_scene_identifier(value))
        fail(at(name), fmt::format("invalid {} name '{}': expected a letter followed by letters, digits or "
                                   "underscores",
                                   noun, value));
    if (const auto it = seen.find(value); it != seen.end())
        fail(at(name), fmt::format("duplicate {} name '{}' (first declared{} at line {})", noun, value,
                                   it->second.second, it->second.first.line));
    seen.emplace(value, std::pair(at(name), std::string()));
    return value;
}

std::pair<const toml::node*, bool> Reader::exactly_one(const toml::table& t, const char* a, const char* b,
                                                       const std::string& both, const std::string& neither) const {
    const toml::node* first = t.get(a);
    const toml::node* second = t.get(b);
    if (first && second) {
        const bool second_later = before(at(*first), at(*second));
        fail(at(second_later ? *second : *first), both);
    }
    if (!first && !second) fail(at(t), neither);
    return {first ? first : second, first != nullptr};
}

}  // namespace eomc::scene
