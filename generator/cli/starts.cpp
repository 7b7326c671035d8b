// Every start checked alike: the scene's own initial values, --set, each ensemble member.
#include <algorithm>
#include <memory>
#include <mutex>

#include <fmt/format.h>

#include "cli/options.hpp"
#include "mechanics/start.hpp"

namespace eomc::cli {

namespace {

// The check at the overrides' values, refused at `given` with the scene's place it was made as
// (as check_overrides_against_scene names its --set).
void check_overrides(const host::Pipeline& p, const std::vector<std::pair<std::string, double>>& overrides,
                     const std::string& given) {
    try {
        mechanics::check_start(p.model, p.equations, mechanics::start_values(p.model, overrides),
                               "with the values given");
    } catch (const InputError& e) {
        throw InputError(SourcePos{given}, fmt::format("{} (checked as in {})", e.message(), to_string(e.where())));
    }
}

}  // namespace

void check_start(const host::Pipeline& p, const std::vector<std::pair<std::string, double>>& overrides,
                 const std::string& given) {
    mechanics::check_start(p.model, p.equations, mechanics::start_values(p.model, {}),
                           "with the scene's initial values and default parameters");
    if (!overrides.empty()) check_overrides(p, overrides, given);
}

std::function<void(const std::vector<std::pair<std::string, double>>&)> member_start_check(
    const host::Pipeline& p, const host::EnsembleSpec& spec) {
    std::vector<std::string> grid, vary;  // the inputs' names by the flag that gives them
    for (const auto& axis : spec.grid) grid.push_back(axis.name);
    for (const auto& v : spec.vary) vary.push_back(v.name);
    auto lock = std::make_shared<std::mutex>();
    return [&p, grid, vary, lock](const std::vector<std::pair<std::string, double>>& overrides) {
        const auto has = [](const std::vector<std::string>& names, const std::string& name) {
            return std::find(names.begin(), names.end(), name) != names.end();
        };
        std::string given;
        for (const auto& [name, value] : overrides)
            given += fmt::format("{}{} {}={}", given.empty() ? "" : " ",
                                 has(grid, name) ? "--grid" : has(vary, name) ? "--vary" : "--set", name, value);
        const std::lock_guard<std::mutex> one_at_a_time(*lock);
        check_overrides(p, overrides, given);
    };
}

std::function<std::vector<std::pair<std::string, double>>(const std::vector<std::pair<std::string, double>>&)>
derived_start(const host::Pipeline& p) {
    const bool any = std::any_of(p.model.coordinates.begin(), p.model.coordinates.end(), [](const auto& c) {
        return !GiNaC::is_a<GiNaC::numeric>(c.initial_expr) || !GiNaC::is_a<GiNaC::numeric>(c.rate_expr);
    });
    if (!any) return nullptr;
    auto lock = std::make_shared<std::mutex>();  // GiNaC is not thread-safe
    return [&p, lock](const std::vector<std::pair<std::string, double>>& overrides) {
        const std::lock_guard<std::mutex> one_at_a_time(*lock);
        return model::initial_overrides(p.model, overrides);
    };
}

}  // namespace eomc::cli
