#include "mechanics/numeric_probe.hpp"

#include <random>
#include <stdexcept>

namespace eomc::mechanics {

namespace {

std::vector<ProbePoint> make_points(const model::Model& model, std::size_t count, std::uint64_t seed,
                                    bool perturb_parameters) {
    std::mt19937_64 rng(seed);
    // Drawn by hand from the raw generator: std::uniform_real_distribution's output is not
    // specified bit-for-bit across standard libraries.
    auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 11) * 0x1.0p-53; };
    std::vector<ProbePoint> points(count);
    for (auto& point : points) {
        auto& v = point.values;
        v[model.t] = uniform(-1, 1);
        for (const auto& c : model.coordinates) {
            v[c.q] = uniform(-1, 1);
            v[c.q_dot] = uniform(-1, 1);
            v[c.q_ddot] = uniform(-1, 1);
        }
        for (const auto& p : model.parameters) {
            if (!perturb_parameters) v[p.symbol] = p.value;
            else if (p.value == 0.0) v[p.symbol] = uniform(0.3, 1.3);
            else v[p.symbol] = p.value * uniform(0.8, 1.25);
        }
    }
    return points;
}

}  // namespace

std::vector<ProbePoint> probe_points(const model::Model& model, std::size_t count, std::uint64_t seed) {
    return make_points(model, count, seed, true);
}

std::vector<ProbePoint> probe_points_at_defaults(const model::Model& model, std::size_t count, std::uint64_t seed) {
    return make_points(model, count, seed, false);
}

double evaluate(const GiNaC::ex& e, const ProbePoint& at) {
    const GiNaC::ex value = e.subs(at.values).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(value) || !GiNaC::ex_to<GiNaC::numeric>(value).is_real())
        throw std::runtime_error("expression does not evaluate to a real number at a probe point");
    return GiNaC::ex_to<GiNaC::numeric>(value).to_double();
}

}  // namespace eomc::mechanics
