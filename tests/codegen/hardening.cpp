// A scene is untrusted input: no string in it may reach generated code, a compiler or a plot
// script as anything but inert text, and no number the emitter cannot represent may be emitted.
// Unit tests of codegen/cpp_text, then the whole command line on hostile scenes; kernels too
// large for fixed-size matrices; and what eomc says when its output may vary between runs.
#define BOOST_TEST_MODULE codegen_hardening
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <ginac/ginac.h>

#include "command.hpp"
#include "csv.hpp"
#include "oscillator.hpp"
#include "codegen/cpp_emitter.hpp"
#include "codegen/cpp_text.hpp"

namespace fs = std::filesystem;
using eomc::codegen::comment_text;
using eomc::codegen::fill_template;
using eomc::codegen::string_literal;
using test_support::Result;
using test_support::slurp;

namespace {

fs::path scratch(const std::string& name) { return test_support::scratch("codegen-hardening", name); }

Result run(const std::string& arguments, const fs::path& dir) { return test_support::run_eomc(arguments, dir); }

using test_support::write_file;

// For sh: the paths here hold line breaks but no single quote.
std::string sh_quoted(const fs::path& p) {
    std::string out(1, '\'');
    out += p.string();
    out += '\'';
    return out;
}

using test_support::last_csv_row;

// A harmonic oscillator q̈ = −k q whose scene strings are supplied by the test.
std::string oscillator(const std::string& summary_line, const std::string& k_name = "k") {
    return test_support::oscillator_scene(
        {.name = "osc", .summary_line = summary_line, .parameter = k_name, .value = "4.0", .stiffness = k_name, .tail = ""});
}

}  // namespace

BOOST_AUTO_TEST_CASE(comment_text_cannot_end_a_line_comment) {
    BOOST_TEST(comment_text("ok\n#include <cstdlib>") == "ok\\x0A#include <cstdlib>");
    BOOST_TEST(comment_text("a\rb") == "a\\x0Db");
    BOOST_TEST(comment_text(std::string("nul\0byte", 8)) == "nul\\x00byte");
    BOOST_TEST(comment_text("tab\there") == "tab\\x09here");
    // U+2028, C1 controls and bytes that are not UTF-8 are written as their bytes.
    BOOST_TEST(comment_text("a\u2028b") == "a\\xE2\\x80\\xA8b");
    BOOST_TEST(comment_text("a\xC2\x85" "b") == "a\\xC2\\x85b");
    BOOST_TEST(comment_text("bad \xFF\xC0\xAF") == "bad \\xFF\\xC0\\xAF");
    // Well-formed UTF-8 prose stays as it is.
    BOOST_TEST(comment_text("T = T_e + T_m + T_r, μ, Ω, —") == "T = T_e + T_m + T_r, μ, Ω, —");
}

BOOST_AUTO_TEST_CASE(a_backslash_at_the_end_of_a_comment_cannot_splice_the_next_line) {
    BOOST_TEST(comment_text("path\\") == "path\\x5C");
    BOOST_TEST(comment_text("path\\  ") == "path\\x5C  ");
    BOOST_TEST(comment_text("a\\b") == "a\\b");
}

BOOST_AUTO_TEST_CASE(string_literals_escape_every_byte_outside_printable_ascii) {
    BOOST_TEST(string_literal("a\"b\\c") == "\"a\\\"b\\\\c\"");
    BOOST_TEST(string_literal("line\nnext") == "\"line\\012next\"");
    BOOST_TEST(string_literal("\x7f\xff" "1") == "\"\\177\\3771\"");
}

BOOST_AUTO_TEST_CASE(the_template_is_filled_in_one_pass) {
    // A value holding a marker stays as it is: values are never scanned again.
    BOOST_TEST(fill_template("// {{summary}}\nstruct {{name}} {};", {{"summary", "{{name}}"}, {"name", "K"}}) ==
               "// {{name}}\nstruct K {};");
    BOOST_CHECK_THROW(fill_template("{{unknown}}", {{"name", "K"}}), std::logic_error);
    BOOST_CHECK_THROW(fill_template("{{name}}", {{"name", "K"}, {"unused", ""}}), std::logic_error);
    BOOST_CHECK_THROW(fill_template("{{name", {{"name", "K"}}), std::logic_error);
}

BOOST_AUTO_TEST_CASE(names_that_are_macros_of_the_kernel_headers_are_known) {
    for (const char* macro : {"M_PI", "NULL", "EOF", "INFINITY", "errno", "assert", "linux", "unix", "EIGEN_WORLD_VERSION"})
        BOOST_TEST(eomc::codegen::is_kernel_macro(macro), macro);
    for (const char* name : {"m", "k", "Omega", "q", "J2", "M"}) BOOST_TEST(!eomc::codegen::is_kernel_macro(name), name);
}

// The scene summary and the scene's file name reach the header's first lines. A line break in
// either used to end the comment: the next line was compiled, and a static initialiser ran
// when `simulate` loaded the kernel.
BOOST_AUTO_TEST_CASE(a_summary_with_line_breaks_runs_no_code_at_simulate) {
    const fs::path dir = scratch("summary");
    const fs::path marker = dir / "ran";
    const std::string payload = "ok\\n#include <cstdlib>\\nstatic int x_ = (std::system(\\\"touch " +
                                marker.string() + "\\\"), 0);\\n// {{struct_name}}\\r\\u2028 \\\\";
    const fs::path scene = write_file(dir / "scene.toml", oscillator("summary = \"" + payload + "\""));
    const Result r = run("simulate " + sh_quoted(scene) + " --t-end 1 --output " + sh_quoted(dir / "o.csv") + " --cache-dir " +
                             sh_quoted(dir / "cache"),
                         dir);
    BOOST_TEST_INFO(r.err);
    BOOST_TEST(r.status == 0);
    BOOST_TEST(!fs::exists(marker));

    const Result g = run("generate " + sh_quoted(scene) + " -o " + sh_quoted(dir), dir);
    BOOST_TEST(g.status == 0);
    const std::string header = slurp(dir / "osc.hpp");
    std::istringstream lines(header);
    std::string first, second;
    std::getline(lines, first);
    std::getline(lines, second);
    BOOST_TEST(second == "// ok\\x0A#include <cstdlib>\\x0Astatic int x_ = (std::system(\"touch " + marker.string() +
                             "\"), 0);\\x0A// {{struct_name}}\\x0D\\xE2\\x80\\xA8 \\x5C");
    BOOST_TEST(header.find("\nstatic int x_") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(a_scene_file_name_with_a_line_break_stays_in_the_comment) {
    const fs::path dir = scratch("file_name");
    const fs::path marker = dir / "ran";
    const fs::path scene =
        write_file(dir / ("x.toml\nstatic int y_ = (__builtin_trap(), 0);\n#define Z"), oscillator("summary = \"plain\""));
    const Result r = run("simulate " + sh_quoted(scene) + " --t-end 1 --output " + sh_quoted(dir / "o.csv") + " --cache-dir " +
                             sh_quoted(dir / "cache"),
                         dir);
    BOOST_TEST_INFO(r.err);
    BOOST_TEST(r.status == 0);
    const Result g = run("generate " + sh_quoted(scene) + " -o " + sh_quoted(dir), dir);
    BOOST_TEST(g.status == 0);
    const std::string header = slurp(dir / "osc.hpp");
    BOOST_TEST(header.find("x.toml\\x0Astatic int y_") != std::string::npos);
    BOOST_TEST(header.find("\nstatic int y_") == std::string::npos);
}

// Parameters named like macros of <cmath>, <cstdio> and the GNU dialect: the kernel binds them
// under other C++ names, and they are still set by their scene names, so the physics is right.
BOOST_AUTO_TEST_CASE(parameters_named_like_libc_macros_compile_and_keep_their_values) {
    const fs::path dir = scratch("macros");
    for (const std::string name : {"M_PI", "NULL", "EOF", "INFINITY", "linux", "errno"}) {
        const fs::path scene = write_file(dir / (name + ".toml"), oscillator("summary = \"macro\"", name));
        const fs::path csv = dir / (name + ".csv");
        const Result r = run("simulate " + sh_quoted(scene) + " --t-end 1 --rtol 1e-12 --atol 1e-12 --output " + sh_quoted(csv) +
                                 " --cache-dir " + sh_quoted(dir / "cache"),
                             dir);
        BOOST_TEST_INFO(name << ": " << r.err);
        BOOST_TEST_REQUIRE(r.status == 0);
        // q = cos 2t with k = 4, q̇ = −2 sin 2t: to the tolerance of the run.
        const std::vector<double> row = last_csv_row(csv);
        BOOST_TEST_REQUIRE(row.size() >= 3u);
        BOOST_TEST(std::abs(row[1] - std::cos(2.0)) < 1e-9);
        BOOST_TEST(std::abs(row[2] + 2 * std::sin(2.0)) < 1e-9);
        // --set reaches the renamed member by the scene name: k = 1 gives q = cos t.
        const Result s = run("simulate " + sh_quoted(scene) + " --t-end 1 --rtol 1e-12 --atol 1e-12 --set " + name +
                                 "=1 --output " + sh_quoted(csv) + " --cache-dir " + sh_quoted(dir / "cache"),
                             dir);
        BOOST_TEST_REQUIRE(s.status == 0);
        BOOST_TEST(std::abs(last_csv_row(csv)[1] - std::cos(1.0)) < 1e-9);
    }
}

// A constant outside double's range printed as S(inf) or S(0.0…) (1e-400*q^3 became 0·∞).
BOOST_AUTO_TEST_CASE(a_constant_double_cannot_hold_is_refused_at_generate) {
    const fs::path dir = scratch("range");
    const fs::path scene = write_file(dir / "tiny.toml",
                                 "[scene]\nname = \"tiny\"\n[coordinates]\nq = { initial = 1.0 }\n[lagrangian]\n"
                                 "T = \"q_dot^2/2\"\nV = \"1e-200*1e-200*q^4\"\n");
    const Result r = run("generate " + sh_quoted(scene) + " -o " + sh_quoted(dir / "out"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("tiny.toml: error: ") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("outside the range of double") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "out" / "tiny.hpp"));
}

// A coordinate named like a constraint's multiplier would be a second CSV column of that name.
BOOST_AUTO_TEST_CASE(a_name_that_would_be_written_twice_is_refused_at_generate) {
    const fs::path dir = scratch("columns");
    const fs::path scene = write_file(dir / "clash.toml",
                                 "[scene]\nname = \"clash\"\n[parameters]\nl = 1.0\n[coordinates]\n"
                                 "lambda_rod = { initial = 1.0 }\ny = { initial = 0.0 }\n[lagrangian]\n"
                                 "T = \"(lambda_rod_dot^2 + y_dot^2)/2\"\n[[constraint]]\nname = \"rod\"\n"
                                 "holonomic = \"lambda_rod^2 + y^2 - l^2\"\n");
    const Result r = run("generate " + sh_quoted(scene) + " -o " + sh_quoted(dir / "out"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("clash.toml: error: ") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("two columns named 'lambda_rod'") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "out" / "clash.hpp"));
}

// The plot script quotes the output directory in gnuplot's single quotes, which only a line
// break can leave; the next line ran as a gnuplot command (`system`).
BOOST_AUTO_TEST_CASE(a_bench_output_directory_with_a_line_break_is_refused) {
    const fs::path dir = scratch("gnuplot");
    const fs::path scene = write_file(dir / "osc.toml", oscillator("summary = \"plain\""));
    const fs::path marker = dir / "ran";
    const std::string out = (dir / "o\nsystem \"touch ").string() + marker.string() + "\"\n#";
    const Result r = run("bench " + sh_quoted(scene) + " -o " + sh_quoted(out) + " --methods rk4 --steps 10", dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("-o: error: the output directory") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(marker));
}

BOOST_AUTO_TEST_CASE(the_printer_refuses_constants_and_exponents_it_cannot_represent) {
    const GiNaC::symbol q("q");
    eomc::codegen::CppExpressionPrinter printer({{q, "q"}});
    BOOST_CHECK_THROW(printer.print(GiNaC::numeric(1, 10) * GiNaC::pow(GiNaC::numeric(10), -400) * q),
                      eomc::codegen::EmitError);
    BOOST_CHECK_THROW(printer.print(GiNaC::pow(GiNaC::numeric(10), 400) * q), eomc::codegen::EmitError);
    // 2^64 + 2 used to be cut by to_long() and printed as q*q.
    BOOST_CHECK_THROW(printer.print(GiNaC::pow(q, GiNaC::pow(GiNaC::numeric(2), 64) + 2)), eomc::codegen::EmitError);
    BOOST_TEST(printer.print(GiNaC::pow(q, 9)) == "((q*q)*(q*q))*((q*q)*(q*q))*q");
    BOOST_TEST(printer.print(GiNaC::pow(q, 40)) == "pow(q, S(40))");  // past max_multiplied_power
    BOOST_TEST(printer.print(GiNaC::numeric(1, 3) * q) == "S(1)/S(3)*q");
}

// 130 coordinates: a large kernel generates, compiles and runs (M = I here, so there is no solve;
// a large coupled M, Eigen's LLT with dynamic sizes, is tests/codegen/scenes/chain46.toml's). The
// chain's first normal mode, q_i = sin(π(i+1)/(n+1)) cos ωt with
// ω = 2 sin(π/(2(n+1))), is the known answer.
BOOST_AUTO_TEST_CASE(a_scene_with_130_coordinates_generates_compiles_and_moves_in_its_normal_mode) {
    constexpr int n = 130;
    const double pi = std::acos(-1.0), omega = 2 * std::sin(pi / (2 * (n + 1)));
    std::string coordinates, T, V = "q0^2 + q" + std::to_string(n - 1) + "^2";
    for (int i = 0; i < n; ++i) {
        coordinates += fmt::format("q{} = {{ initial = {:.17g}, rate = 0.0 }}\n", i, std::sin(pi * (i + 1) / (n + 1)));
        T += fmt::format("{}q{}_dot^2", i ? " + " : "", i);
        if (i) V += fmt::format(" + (q{}-q{})^2", i, i - 1);
    }
    const fs::path dir = scratch("large");
    const fs::path scene = write_file(dir / "chain.toml", "[scene]\nname = \"chain\"\n[coordinates]\n" + coordinates +
                                                         "[lagrangian]\nT = \"(" + T + ")/2\"\nV = \"(" + V + ")/2\"\n");
    const fs::path csv = dir / "chain.csv";
    const double t_end = 20.0;
    const Result r = run("simulate " + sh_quoted(scene) + " --t-end 20 --rtol 1e-11 --atol 1e-11 --output " + sh_quoted(csv) +
                             " --cache-dir " + sh_quoted(dir / "cache"),
                         dir);
    BOOST_TEST_INFO(r.err);
    BOOST_TEST_REQUIRE(r.status == 0);
    const std::vector<double> row = last_csv_row(csv);
    BOOST_TEST_REQUIRE(row.size() >= std::size_t(2 * n + 1));
    BOOST_TEST(row[0] == t_end);
    // The local error per step is held to 1e-11 of |q| ≤ 1; over ~10² steps it adds up to < 1e-8.
    double worst = 0;
    for (int i = 0; i < n; ++i)
        worst = std::max(worst, std::abs(row[1 + i] - std::sin(pi * (i + 1) / (n + 1)) * std::cos(omega * t_end)));
    BOOST_TEST(worst < 1e-8);
}

// GiNaC orders terms by hash values seeded with addresses; eomc turns address-space
// randomisation off for itself, and says so when it stays on (here: asked for by the test).
BOOST_AUTO_TEST_CASE(eomc_says_when_its_output_may_differ_between_runs) {
    const fs::path dir = scratch("aslr");
    const fs::path scene = write_file(dir / "osc.toml", oscillator("summary = \"plain\""));
    const Result quiet = run("derive " + sh_quoted(scene), dir);
    BOOST_TEST(quiet.status == 0);
    BOOST_TEST(quiet.err.empty(), quiet.err);
    const Result r = test_support::run_command(std::string(EOMC_EXECUTABLE) + " derive " + sh_quoted(scene), dir,
                                               "EOMC_TEST_ASLR=1");
    BOOST_TEST(r.status == 0);
    BOOST_TEST(r.err.find("eomc: warning: address-space randomisation stays on (EOMC_TEST_ASLR is set)") !=
                   std::string::npos,
               r.err);
}
