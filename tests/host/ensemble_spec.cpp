// The ensemble specifications: --grid, --vary, --samples and --seed parsed and checked, each
// error at its flag; the grid's points, and the draws of each member from its own seed.
#define BOOST_TEST_MODULE ensemble_spec
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "host/ensemble_spec.hpp"
#include "support/diagnostic.hpp"

using namespace eomc::host;
using eomc::InputError;

namespace {

// The call throws InputError at a place starting with `flag`, its message holding `words`.
void expect_error(const std::function<void()>& call, const std::string& flag, const std::string& words) {
    try {
        call();
    } catch (const InputError& e) {
        BOOST_TEST_INFO("error: " << e.what());
        BOOST_TEST(e.where().file.rfind(flag, 0) == 0u);
        BOOST_TEST(e.message().find(words) != std::string::npos);
        return;
    }
    BOOST_FAIL("no InputError for " + flag + " (" + words + ")");
}

}  // namespace

BOOST_AUTO_TEST_CASE(grid_points_are_evenly_spaced_and_end_exactly) {
    const GridAxis a = parse_grid("k=0:12:121");
    BOOST_TEST(a.name == "k");
    BOOST_TEST(a.count == 121u);
    // (b − a)·i/(n − 1) = 12 i / 120: 12 i is exact, one division rounds, so i/10 correctly rounded.
    for (std::size_t i = 0; i < a.count; ++i) BOOST_TEST(a.value(i) == static_cast<double>(i) / 10.0);
    const GridAxis b = parse_grid(" g = 9.81 ");
    BOOST_TEST(b.count == 1u);
    BOOST_TEST(b.value(0) == 9.81);
    const GridAxis c = parse_grid("x=-1:2:2");
    BOOST_TEST(c.value(0) == -1.0);
    BOOST_TEST(c.value(1) == 2.0);
    BOOST_TEST(parse_grid("x=2:2:1").value(0) == 2.0);
}

// Found by fuzz_ensemble_flags: (b − a)·i overflowed for a range near double's limit, so the
// points of -1e308:1e3:83 from i = 2 on were inf (a member run with k = inf).
BOOST_AUTO_TEST_CASE(grid_points_near_doubles_limit_stay_between_the_ends) {
    for (const char* text : {"k=-1e308:1e03:83", "k=-8e307:8e307:1000", "k=0:1.7e308:100000000"}) {
        BOOST_TEST_INFO(text);
        const GridAxis a = parse_grid(text);
        double previous = a.first;
        for (std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{2}, a.count / 2, a.count - 2, a.count - 1}) {
            const double v = a.value(i);
            BOOST_TEST(std::isfinite(v));
            BOOST_TEST(v >= previous);
            BOOST_TEST(v <= a.last);
            previous = v;
        }
        BOOST_TEST(a.value(a.count - 1) == a.last);
    }
    const GridAxis a = parse_grid("k=-1e308:1e03:83");  // (b − a)·(i/82): near 1e308·i/82
    BOOST_TEST(a.value(41) == -1e308 + 1e308 * (41.0 / 82.0));
}

BOOST_AUTO_TEST_CASE(bad_grids_are_refused_at_the_flag) {
    expect_error([] { parse_grid("k=1:0:5"); }, "--grid k=1:0:5", "reversed");
    expect_error([] { parse_grid("k=1:1:5"); }, "--grid", "empty");
    expect_error([] { parse_grid("k=0:1:0"); }, "--grid", "at least 1");
    expect_error([] { parse_grid("k=0:1:-3"); }, "--grid", "positive");
    expect_error([] { parse_grid("k=0:1:2.5"); }, "--grid", "whole number");
    expect_error([] { parse_grid("k=0:1:1"); }, "--grid", "one point");
    expect_error([] { parse_grid("k=nan:1:3"); }, "--grid", "not a number");
    expect_error([] { parse_grid("k=0:inf:3"); }, "--grid", "not a number");
    expect_error([] { parse_grid("k=0:1e309:3"); }, "--grid", "range of a double");
    expect_error([] { parse_grid("k=-1e308:1e308:3"); }, "--grid", "wider");
    expect_error([] { parse_grid("k=0:1"); }, "--grid", "expected NAME=a:b:n");
    expect_error([] { parse_grid("=1"); }, "--grid", "expected NAME");
    expect_error([] { parse_grid("k;rm=1"); }, "--grid", "not a name");
    expect_error([] { parse_grid("k=0:1:1000000000"); }, "--grid", "limit");
}

BOOST_AUTO_TEST_CASE(variations_parse_and_bad_arguments_are_refused) {
    const Variation v = parse_variation("Cd=normal(2.2, 0.1)");
    BOOST_TEST(v.name == "Cd");
    BOOST_TEST((v.kind == Distribution::normal));
    BOOST_TEST(v.a == 2.2);
    BOOST_TEST(v.b == 0.1);
    BOOST_TEST((parse_variation("a=uniform(-1,1)").kind == Distribution::uniform));
    BOOST_TEST((parse_variation("a=lognormal(0,0.5)").kind == Distribution::lognormal));
    expect_error([] { parse_variation("Cd=normal(2.2,0)"); }, "--vary Cd=normal(2.2,0)", "sigma > 0");
    expect_error([] { parse_variation("Cd=lognormal(1,-0.1)"); }, "--vary", "sigma > 0");
    expect_error([] { parse_variation("a=uniform(1,1)"); }, "--vary", "a < b");
    expect_error([] { parse_variation("a=uniform(2,1)"); }, "--vary", "a < b");
    expect_error([] { parse_variation("a=gaussian(1,2)"); }, "--vary", "unknown distribution");
    expect_error([] { parse_variation("a=normal(1)"); }, "--vary", "two numbers");
    expect_error([] { parse_variation("a=normal(1,2,3)"); }, "--vary", "two numbers");
    expect_error([] { parse_variation("a=normal(1,nan)"); }, "--vary", "not a number");
    expect_error([] { parse_variation("a=normal 1 2"); }, "--vary", "expected");
}

BOOST_AUTO_TEST_CASE(sample_counts_and_seeds) {
    BOOST_TEST(parse_samples("10000") == 10000u);
    expect_error([] { parse_samples("0"); }, "--samples", "at least 1");
    expect_error([] { parse_samples("-5"); }, "--samples", "positive");
    expect_error([] { parse_samples("1e3"); }, "--samples", "whole number");
    expect_error([] { parse_samples("999999999999"); }, "--samples", "limit");
    BOOST_TEST(parse_seed("18446744073709551615") == 18446744073709551615ULL);
    expect_error([] { parse_seed("18446744073709551616"); }, "--seed", "above");
    expect_error([] { parse_seed("-1"); }, "--seed", "whole number");
}

BOOST_AUTO_TEST_CASE(a_sweep_runs_the_grid_last_axis_fastest) {
    EnsembleSpec spec;
    spec.grid = {parse_grid("a=0:2:3"), parse_grid("b=10:20:2")};
    BOOST_TEST(spec.members() == 6u);
    BOOST_TEST((spec.input_names() == std::vector<std::string>{"a", "b"}));
    BOOST_TEST((spec.inputs(0) == std::vector<double>{0, 10}));
    BOOST_TEST((spec.inputs(1) == std::vector<double>{0, 20}));
    BOOST_TEST((spec.inputs(4) == std::vector<double>{2, 10}));
    BOOST_TEST((spec.inputs(5) == std::vector<double>{2, 20}));
}

BOOST_AUTO_TEST_CASE(each_member_draws_from_its_own_seed) {
    EnsembleSpec spec;
    spec.vary = {parse_variation("a=uniform(1,3)"), parse_variation("b=lognormal(0,1)")};
    spec.samples = 1000;
    spec.seed = 42;
    // The same member in any order, and after any other: its draws depend on (seed, index) alone.
    const std::vector<double> late = spec.inputs(999), early = spec.inputs(3);
    BOOST_TEST(spec.inputs(999) == late);
    BOOST_TEST(spec.inputs(3) == early);
    BOOST_TEST(late != early);
    for (std::size_t i = 0; i < spec.samples; ++i) {
        const auto x = spec.inputs(i);
        BOOST_TEST((x[0] >= 1.0 && x[0] < 3.0));
        BOOST_TEST(x[1] > 0.0);
    }
    EnsembleSpec other = spec;
    other.seed = 43;
    BOOST_TEST(other.inputs(3) != early);
}

// The sample mean and standard deviation of N draws of normal(μ, σ): the mean's standard error
// is σ/√N, the sample standard deviation's ≈ σ/√(2(N − 1)); each must lie within 5 of them (a
// correct sampler fails with probability ~6e-7 per check; the seed is fixed, so it does not flake).
BOOST_AUTO_TEST_CASE(normal_draws_have_their_mean_and_spread) {
    EnsembleSpec spec;
    spec.vary = {parse_variation("x=normal(3,0.5)")};
    spec.samples = 20000;
    spec.seed = 2024;
    double sum = 0, sum2 = 0;
    for (std::size_t i = 0; i < spec.samples; ++i) sum += spec.inputs(i)[0];
    const double n = static_cast<double>(spec.samples), mean = sum / n;
    for (std::size_t i = 0; i < spec.samples; ++i) sum2 += std::pow(spec.inputs(i)[0] - mean, 2);
    const double sd = std::sqrt(sum2 / (n - 1));
    BOOST_TEST(std::abs(mean - 3.0) < 5 * 0.5 / std::sqrt(n));
    BOOST_TEST(std::abs(sd - 0.5) < 5 * 0.5 / std::sqrt(2 * (n - 1)));
}

BOOST_AUTO_TEST_CASE(names_are_checked_against_the_kernel) {
    const std::vector<std::string> parameters{"gamma", "w"}, states{"x", "x_dot"};
    EnsembleSpec spec;
    spec.grid = {parse_grid("w=1:2:3"), parse_grid("x=0.5")};
    check_names(spec, parameters, states, {});
    spec.grid.push_back(parse_grid("gama=0:1:2"));
    expect_error([&] { check_names(spec, parameters, states, {}); }, "--grid gama=0:1:2", "did you mean 'gamma'");
    spec.grid.back() = parse_grid("w=3");
    expect_error([&] { check_names(spec, parameters, states, {}); }, "--grid w=3", "twice");
    spec.grid.pop_back();
    expect_error([&] { check_names(spec, parameters, states, {{"w", 2.0}}); }, "--grid w=1:2:3", "--set");
    spec.vary = {parse_variation("gamma=normal(0.1,0.01)")};
    expect_error([&] { check_names(spec, parameters, states, {}); }, "--vary", "not both");
}
