// [rigid_body] scenes: what the scene and model stages refuse, at its place, and what the
// derivation keeps (the classical integrals proven, the searched ones tracked only where they hold).
#define BOOST_TEST_MODULE rigid_scene
#include <boost/test/unit_test.hpp>

#include <string>

#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "scenes.hpp"
#include "support/diagnostic.hpp"

using eomc::InputError;
using test_support::model_of;

namespace {

std::string scene(const std::string& body, const std::string& initial, const std::string& extra = "") {
    return "[scene]\nname = \"top\"\n[parameters]\nA = 1.0\nC = 0.5\nP = 1.0\nx0 = 1.0\n" + extra +
           "[rigid_body]\n" + body + "\n[rigid_body.initial]\n" + initial + "\n";
}

const std::string kovalevskaya = "inertia = [\"A\", \"A\", \"C\"]\ncenter = [\"x0\", \"0\", \"0\"]\nweight = \"P\"";

// Building the model must fail at (line, column) with a message containing `fragment`.
void expect_refused(const std::string& toml, int line, int column, const std::string& fragment) {
    try {
        (void)eomc::mechanics::first_order_form(model_of(toml, "t.toml"),
                                                eomc::mechanics::derive(model_of(toml, "t.toml")));
    } catch (const InputError& e) {
        BOOST_TEST_INFO("message: " << e.what());
        BOOST_TEST(e.where().line == line);
        BOOST_TEST(e.where().column == column);
        BOOST_TEST(e.message().find(fragment) != std::string::npos);
        return;
    }
    BOOST_ERROR("accepted a scene that should fail with '" << fragment << "'");
}

std::vector<std::string> invariant_names(const std::string& toml) {
    std::vector<std::string> names;
    for (const auto& inv : eomc::mechanics::derive(model_of(toml)).invariants) names.push_back(inv.name);
    return names;
}

}  // namespace

BOOST_AUTO_TEST_CASE(refused_at_their_place) {
    // Lines 1–7 are [scene] and [parameters], 8 is [rigid_body], 9–11 its keys, 12 [rigid_body.initial].
    expect_refused(scene(kovalevskaya, "omega = [1, 0, 0]\nvertical = [0.6, 0.48, 0.65]"), 14, 12, "not 1");
    expect_refused(scene(kovalevskaya, "omega = [1, 0, 0]\nvertical = [0, 0, 1]\nattitude = { zxz = [0, 1, 0] }"), 15,
                   12, "both");
    expect_refused(scene(kovalevskaya, "omega = [1, 0, 0]"), 12, 1, "missing required key 'vertical'");
    expect_refused(scene(kovalevskaya + "\nformulation = \"euler_poison\"", "omega = [1, 0, 0]\nvertical = [0, 0, 1]"),
                   12, 15, "did you mean 'euler_poisson'");
    expect_refused(scene(kovalevskaya, "omega = [1, 0, 0]\nvertical = [0, 0, 1]", "p = 2.0\n"), 8, 1,
                   "name of a state variable");
    expect_refused(scene("inertia = [\"A\", \"-A\", \"C\"]", "omega = [1, 0, 0]\nvertical = [0, 0, 1]"), 9, 11,
                   "not positive definite");
    // Euler angles at θ = 0 (gimbal lock at the start); Andoyer–Deprit with K along body axis 3.
    expect_refused(scene(kovalevskaya + "\nformulation = \"euler_angles\"", "omega = [1, 0, 0]\nvertical = [0, 0, 1]"),
                   15, 12, "gimbal lock");
    expect_refused(scene(kovalevskaya + "\nformulation = \"andoyer_deprit\"", "omega = [0, 0, 2]\nvertical = [0.6, 0, 0.8]"),
                   12, 15, "L = ±G");
    expect_refused("[scene]\nname = \"x\"\n[coordinates]\nq = {}\n" + scene(kovalevskaya, "omega = [1, 0, 0]\nvertical = [0, 0, 1]").substr(20),
                   3, 1, "[coordinates] cannot be combined with [rigid_body]");
}

BOOST_AUTO_TEST_CASE(classical_integrals_proven_and_searched_ones_tracked) {
    // Kovalevskaya (A = B = 2C, r_c in the equatorial plane): the quartic is found and tracked.
    const auto kov = invariant_names(scene(kovalevskaya, "omega = [0.8, -0.4, 1.5]\nvertical = [0.6, 0.48, 0.64]"));
    BOOST_TEST(kov == (std::vector<std::string>{"energy", "area", "geometric", "integral_4_1"}),
               boost::test_tools::per_element());
    // A generic heavy body: the three classical integrals only.
    const auto generic = invariant_names(scene("inertia = [\"1\", \"2\", \"3\"]\ncenter = [\"1\", \"1\", \"1\"]\nweight = \"P\"",
                                               "omega = [0.8, -0.4, 1.5]\nvertical = [0.6, 0.48, 0.64]"));
    BOOST_TEST(generic == (std::vector<std::string>{"energy", "area", "geometric"}), boost::test_tools::per_element());
    // Goryachev–Chaplygin (A = B = 4C): its cubic holds on the zero level of the area integral only,
    // so it is tracked from γ0 with K·γ = 0 (ω0 = (0.4, 0.2, 1), γ0 ∝ (0.5, 0, −0.8)) and not otherwise.
    const std::string gc = "inertia = [\"2\", \"2\", \"0.5\"]\ncenter = [\"1\", \"0\", \"0\"]\nweight = \"1\"";
    const auto on = invariant_names(scene(gc, "omega = [0.4, 0.2, 1]\nvertical = [0.5299989400031799, 0, -0.8479983040050879]"));
    BOOST_TEST(on.back() == "conditional_3_1");
    const auto off = invariant_names(scene(gc, "omega = [0.4, 0.2, 1]\nvertical = [0.6, 0.48, 0.64]"));
    BOOST_TEST(off.back() == "geometric");
}

BOOST_AUTO_TEST_CASE(every_formulation_starts_from_the_same_body_state) {
    // The outputs p, q, r, gamma1..3 of each formulation at t = 0 are ω0 and γ0.
    const double omega0[3] = {0.8, -0.4, 1.5}, gamma0[3] = {0.6, 0.48, 0.64};
    for (const char* f : {"quaternion", "euler_angles", "andoyer_deprit"}) {
        const auto model = model_of(scene(kovalevskaya + "\nformulation = \"" + f + "\"",
                                          "omega = [0.8, -0.4, 1.5]\nvertical = [0.6, 0.48, 0.64]"));
        const auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
        GiNaC::exmap at = model.parameter_defaults();
        for (const auto& s : form.state) at[s.symbol] = s.initial;
        BOOST_TEST_CONTEXT(f) {
            BOOST_REQUIRE(form.outputs.size() >= 3);
            for (const auto& out : form.outputs) {
                const double v = GiNaC::ex_to<GiNaC::numeric>(out.value.subs(at).evalf()).to_double();
                const int i = out.name == "p" ? 0 : out.name == "q" ? 1 : out.name == "r" ? 2 : -1;
                const int g = out.name.rfind("gamma", 0) == 0 ? out.name.back() - '1' : -1;
                // Round-off of the conversions (a few operations on O(1) numbers).
                if (i >= 0) BOOST_TEST(std::abs(v - omega0[i]) < 1e-14);
                if (g >= 0) BOOST_TEST(std::abs(v - gamma0[g]) < 1e-14);
            }
        }
    }
}
