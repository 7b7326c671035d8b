// Unit tests of the code generator: the C++ printer (exact strings: this is where goldens
// belong), common-subexpression elimination (same values, fewer operations), effects that
// are dropped leaving no code, and determinism.
#define BOOST_TEST_MODULE codegen
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <functional>
#include <map>
#include <random>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "mechanics/derive.hpp"
#include "model/functions.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

#include "scenes.hpp"

using namespace eomc;
using GiNaC::ex;

namespace {

struct Printer {
    GiNaC::symbol x{"x"}, y{"y"}, z{"z"};
    std::string operator()(const ex& e) {
        codegen::CppExpressionPrinter p({{x, "x"}, {y, "y"}, {z, "z"}});
        return p.print(e);
    }
};

// Double-precision value of e with the given symbol values (temporaries resolved first).
double value(const ex& e, const std::map<std::string, double>& at, const codegen::Block* block = nullptr) {
    GiNaC::exmap substitution;
    std::function<void(const ex&)> collect = [&](const ex& node) {
        if (GiNaC::is_a<GiNaC::symbol>(node)) {
            const auto name = GiNaC::ex_to<GiNaC::symbol>(node).get_name();
            if (at.count(name)) substitution[node] = at.at(name);
        }
        for (std::size_t i = 0; i < node.nops(); ++i) collect(node.op(i));
    };
    collect(e);
    ex resolved = e;
    if (block) {
        // Temporaries refer only to earlier ones: substitute from the last back to the first.
        for (auto it = block->temporaries.rbegin(); it != block->temporaries.rend(); ++it)
            resolved = resolved.subs(GiNaC::exmap{{it->symbol, it->value}});
        collect(resolved);
    }
    return GiNaC::ex_to<GiNaC::numeric>(resolved.subs(substitution).evalf()).to_double();
}

mechanics::Equations derive_scene(const std::string& toml, model::Model& model) {
    model = test_support::model_of(toml);
    return mechanics::derive(model);
}

const char* disk_tube_ball(const char* keep) {
    static std::string text;
    text = std::string(R"(
[scene]
name = "tube"
[parameters]
m = 0.5
Omega = 3.0
a = 0.2
[coordinates]
q = { initial = 0.1 }
[carrier]
angular_velocity = ["0", "Omega", "a*t"]
pole_velocity = ["a*t", "0", "0"]
[[body]]
name = "ball"
mass = "m"
position = ["q", "0", "0"]
[effects]
keep = )") + keep + "\n";
    return text.c_str();
}

}  // namespace

BOOST_AUTO_TEST_CASE(printer_integer_powers_become_multiplications) {
    Printer print;
    BOOST_TEST(print(GiNaC::pow(print.x, 2)) == "x*x");
    BOOST_TEST(print(GiNaC::pow(print.x, 3)) == "x*x*x");
    BOOST_TEST(print(GiNaC::pow(print.x, -1)) == "S(1)/x");
    BOOST_TEST(print(GiNaC::pow(print.x, -2)) == "S(1)/(x*x)");
    BOOST_TEST(print(GiNaC::sqrt(print.x)) == "sqrt(x)");
    BOOST_TEST(print(GiNaC::pow(print.x, GiNaC::numeric(3, 2))) == "x*sqrt(x)");
    // Binary powering past the cube (compilers share the repeated square), pow() past the bound.
    BOOST_TEST(print(GiNaC::pow(print.x, 4)) == "(x*x)*(x*x)");
    BOOST_TEST(print(GiNaC::pow(print.x, 12)) == "((x*x*x)*(x*x*x))*((x*x*x)*(x*x*x))");
    BOOST_TEST(print(GiNaC::pow(print.x, -5)) == "S(1)/((x*x)*(x*x)*x)");
    BOOST_TEST(print(GiNaC::pow(print.x, codegen::max_multiplied_power + 1)) == "pow(x, S(33))");
    BOOST_TEST(print(GiNaC::pow(print.y + print.z, -1)) == "S(1)/(y + z)");
}

BOOST_AUTO_TEST_CASE(printer_half_integer_powers_become_sqrt_and_multiplications) {
    Printer print;
    BOOST_TEST(print(GiNaC::pow(print.x, GiNaC::numeric(-1, 2))) == "S(1)/sqrt(x)");
    BOOST_TEST(print(GiNaC::pow(print.x, GiNaC::numeric(-3, 2))) == "S(1)/(x*sqrt(x))");
    BOOST_TEST(print(GiNaC::pow(print.x, GiNaC::numeric(5, 2))) == "x*x*sqrt(x)");
    BOOST_TEST(print(GiNaC::pow(print.x, GiNaC::numeric(-7, 2))) == "S(1)/(x*x*x*sqrt(x))");
    BOOST_TEST(print(print.y * GiNaC::pow(print.x, GiNaC::numeric(-5, 2))) == "y/(x*x*sqrt(x))");
    BOOST_TEST(print(GiNaC::pow(print.x, GiNaC::numeric(1, 3))) == "pow(x, S(1)/S(3))");
    BOOST_TEST(print(GiNaC::pow(print.x, GiNaC::numeric(67, 2))) == "pow(x, S(67)/S(2))");
}

// Gravity with J2: r⁻³, r⁻⁵ and r⁻⁷ of one r² = x² + y² + z² cost one sqrt and one division.
BOOST_AUTO_TEST_CASE(cse_shares_one_sqrt_and_one_division_among_half_powers) {
    GiNaC::symbol x("x"), y("y"), z("z");
    const ex r2 = x * x + y * y + z * z;
    const std::vector<ex> outputs{x * GiNaC::pow(r2, GiNaC::numeric(-3, 2)),
                                  z * z * GiNaC::pow(r2, GiNaC::numeric(-5, 2)) + GiNaC::pow(r2, GiNaC::numeric(-7, 2)),
                                  GiNaC::pow(r2, GiNaC::numeric(3, 2)) + GiNaC::pow(r2, GiNaC::numeric(1, 2))};
    const codegen::Block block = codegen::eliminate_common_subexpressions(outputs, "w");
    std::map<ex, std::string, GiNaC::ex_is_less> names{{x, "x"}, {y, "y"}, {z, "z"}};
    for (const auto& t : block.temporaries) names.emplace(t.symbol, t.symbol.get_name());
    std::string text;
    for (const auto& t : block.temporaries) text += codegen::CppExpressionPrinter(names).print(t.value) + ";";
    for (const ex& e : block.outputs) text += codegen::CppExpressionPrinter(names).print(e) + ";";
    const auto occurrences = [&](const std::string& what) {
        std::size_t n = 0;
        for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
        return n;
    };
    BOOST_TEST(occurrences("sqrt(") == 1u, text);
    BOOST_TEST(occurrences("/") == 1u, text);
    BOOST_TEST(occurrences("pow(") == 0u, text);
    const std::map<std::string, double> at{{"x", 0.3}, {"y", -1.1}, {"z", 0.7}};
    for (std::size_t k = 0; k < outputs.size(); ++k) {
        const double expected = value(outputs[k], at), got = value(block.outputs[k], at, &block);
        BOOST_TEST(std::abs(got - expected) <= 16 * 2.2e-16 * std::abs(expected));
    }
}

BOOST_AUTO_TEST_CASE(printer_signs_coefficients_and_quotients) {
    Printer print;
    BOOST_TEST(print(print.x - print.y) == "x - y");
    BOOST_TEST(print(-print.x * print.y) == "-x*y");
    BOOST_TEST(print(print.x / 2) == "S(1)/S(2)*x");
    BOOST_TEST(print(3 * print.x / print.y) == "S(3)*x/y");
    BOOST_TEST(print(print.x / (print.y * print.z)) == "x/(y*z)");
    BOOST_TEST(print(print.x * (print.y + print.z)) == "x*(y + z)");
    BOOST_TEST(print(GiNaC::sin(print.x - print.y)) == "sin(x - y)");
    BOOST_TEST(print(GiNaC::Pi * print.x) == "S(3.141592653589793238462643383279502884L)*x");
}

BOOST_AUTO_TEST_CASE(printer_refuses_what_it_cannot_emit) {
    Printer print;
    GiNaC::symbol unknown("unknown");
    BOOST_CHECK_THROW(print(GiNaC::abs(print.x)), std::runtime_error);
    BOOST_CHECK_THROW(print(unknown + 1), std::runtime_error);
}

BOOST_AUTO_TEST_CASE(cse_keeps_values_and_removes_repeats) {
    GiNaC::symbol x("x"), y("y");
    const ex shared = GiNaC::sin(x) * GiNaC::cos(y) + x * y;
    const std::vector<ex> outputs{shared * shared + 1, 2 * GiNaC::sin(x) * GiNaC::cos(y) - GiNaC::exp(shared),
                                  -x * y * GiNaC::sin(x) * GiNaC::cos(y)};
    const codegen::Block block = codegen::eliminate_common_subexpressions(outputs, "w");
    BOOST_TEST(block.ops_after < block.ops_before);
    BOOST_TEST(!block.temporaries.empty());
    const std::map<std::string, double> at{{"x", 0.3}, {"y", -1.1}};
    for (std::size_t k = 0; k < outputs.size(); ++k) {
        const double expected = value(outputs[k], at), got = value(block.outputs[k], at, &block);
        // Only the order of floating-point operations changes: a few ulp of the terms' size.
        BOOST_TEST(std::abs(got - expected) <= 8 * 2.2e-16 * (1 + std::abs(expected)));
    }
}

BOOST_AUTO_TEST_CASE(operation_counts_follow_the_documented_rules) {
    GiNaC::symbol x("x"), y("y");
    BOOST_TEST(codegen::count_operations(x + y) == 1u);
    BOOST_TEST(codegen::count_operations(x - y) == 1u);         // the −1 is a sign
    BOOST_TEST(codegen::count_operations(2 * x * y) == 2u);
    BOOST_TEST(codegen::count_operations(GiNaC::pow(x, 3)) == 2u);
    BOOST_TEST(codegen::count_operations(GiNaC::pow(x, -2)) == 2u);  // x*x, then 1/(…)
    BOOST_TEST(codegen::count_operations(GiNaC::pow(x, 8)) == 3u);   // three squarings
    BOOST_TEST(codegen::count_operations(GiNaC::pow(x, GiNaC::numeric(-5, 2))) == 4u);  // x*x*sqrt(x), 1/(…)
    BOOST_TEST(codegen::count_operations(GiNaC::sin(x + y)) == 2u);
}

BOOST_AUTO_TEST_CASE(dropped_effects_leave_no_code) {
    // The carrier spins up (ω_z = a t) and accelerates (v_x = a t): every effect is present.
    model::Model all_model, relative_model, no_centrifugal_model;
    const auto all = derive_scene(disk_tube_ball(R"(["relative", "translation", "euler", "centrifugal", "coriolis"])"), all_model);
    const auto relative = derive_scene(disk_tube_ball(R"(["relative"])"), relative_model);
    // (Coriolis forces act across a radial tube, never along it: it is centrifugal that matters here.)
    const auto no_centrifugal = derive_scene(disk_tube_ball(R"(["relative", "translation", "euler", "coriolis"])"), no_centrifugal_model);

    const auto ir_all = codegen::lower(all_model, all);
    const auto ir_relative = codegen::lower(relative_model, relative);
    const auto ir_no_centrifugal = codegen::lower(no_centrifugal_model, no_centrifugal);
    // Only the relative effect: the ball moves as if the tube stood still, q̈ = 0.
    BOOST_TEST(ir_relative.forcing.ops_after == 0u);
    BOOST_TEST(ir_relative.forcing.outputs.at(0).is_zero());
    BOOST_TEST(ir_all.forcing.ops_after > ir_no_centrifugal.forcing.ops_after);
    BOOST_TEST(ir_no_centrifugal.forcing.ops_after > ir_relative.forcing.ops_after);

    const std::string header_relative = codegen::emit_header(ir_relative, {"test"});
    const std::string header_all = codegen::emit_header(ir_all, {"test"});
    // Ω and a enter only through the carrier effects: with them dropped no code reads them.
    BOOST_TEST(header_relative.find("S(p.Omega)") == std::string::npos);
    BOOST_TEST(header_relative.find("S(p.a)") == std::string::npos);
    BOOST_TEST(header_all.find("S(p.Omega)") != std::string::npos);
    BOOST_TEST(header_all.find("S(p.a)") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(same_scene_same_bytes_within_a_process) {
    // (Across processes: tests/codegen/check_generated.cmake runs eomc twice per scene.)
    model::Model m1, m2;
    const auto e1 = derive_scene(disk_tube_ball(R"(["relative", "centrifugal", "coriolis"])"), m1);
    const auto e2 = derive_scene(disk_tube_ball(R"(["relative", "centrifugal", "coriolis"])"), m2);
    BOOST_TEST(codegen::emit_header(codegen::lower(m1, e1), {"test"}) ==
               codegen::emit_header(codegen::lower(m2, e2), {"test"}));
}

BOOST_AUTO_TEST_CASE(every_scene_function_is_differentiated_probed_and_emitted) {
    // model/functions.hpp is the one list; each later stage must cover all of it. The
    // derivative and the dual-number rate are compared with GiNaC's own derivative in
    // arbitrary precision: both are exact formulas evaluated in double, so they agree to a
    // few ulp of the values involved (|f'| ≤ ~2 at this point).
    GiNaC::symbol x("x");
    GiNaC::parser reader(GiNaC::symtab{{"x", x}});
    symbolic::ProbePoint at;
    at.values[x] = 0.4;
    at.rates[x] = 1.0;
    for (std::string_view name : model::elementary_functions) {
        const ex f = reader(std::string(name) + "(x/3 + 1/5)");  // argument 1/3 at x = 0.4: inside every domain
        BOOST_REQUIRE(GiNaC::is_a<GiNaC::function>(f));
        const double expected = GiNaC::ex_to<GiNaC::numeric>(f.diff(x).subs(x == GiNaC::numeric(2, 5)).evalf()).to_double();
        const ex mine = symbolic::derivative(f, x);
        const double got = GiNaC::ex_to<GiNaC::numeric>(mine.subs(x == GiNaC::numeric(2, 5)).evalf()).to_double();
        BOOST_TEST(std::abs(got - expected) <= 1e-14 * (1 + std::abs(expected)), name);
        BOOST_TEST(std::abs(symbolic::evaluate_rate(f, at) - expected) <= 1e-14 * (1 + std::abs(expected)), name);
        codegen::CppExpressionPrinter printer({{x, "x"}});
        BOOST_TEST(printer.print(f).find(std::string(name) + "(") == 0u, name);
    }
}
