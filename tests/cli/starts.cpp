// Issue 28, every start checked: the scene's own initial values, --set and each ensemble member
// pass the same checks (the rows hold and their Jacobian has full rank, M is positive definite,
// the inertias are a body's), refused at exit 2 naming the row or the flag, and valid starts run.
#define BOOST_TEST_MODULE cli_starts
#include <boost/test/unit_test.hpp>

#include <string>

#include "command.hpp"

namespace fs = std::filesystem;
using test_support::run_eomc;
using test_support::scratch;
using test_support::slurp;
using test_support::write_scene;

namespace {

const std::string scenes = EOMC_SOURCE_DIR "/scenes/";
const std::string pendulum = scenes + "pendulum_cartesian.toml";
// Each test's kernels cached in the build tree, never the user's ~/.cache.
const std::string cache = " --cache-dir " EOMC_BINARY_DIR "/test-cache";

// A bundled scene with `from` replaced by `to` (which must be there: else the test would test nothing).
std::string edited(const std::string& scene, const std::string& from, const std::string& to) {
    std::string text = slurp(scenes + scene);
    const auto at = text.find(from);
    BOOST_TEST_REQUIRE(at != std::string::npos, scene << " has no '" << from << "'");
    return text.replace(at, from.size(), to);
}

// The pendulum hanging straight down, x = 0, y = −l: every row below is exactly 0 there.
std::string hanging(const std::string& rod) {
    std::string text = edited("pendulum_cartesian.toml", "x = { initial = 0.5753106463250436", "x = { initial = 0.0");
    const std::string y = "y = { initial = -1.0530990742684472", row = "holonomic = \"x^2 + y^2 - l^2\"";
    text.replace(text.find(y), y.size(), "y = { initial = -1.2");
    return text.replace(text.find(row), row.size(), "holonomic = \"" + rod + "\"");
}

// Exit 2, the diagnostic at `where` (its start: a member's value follows "--vary x="), `words` in it.
void expect_refused(const std::string& arguments, const fs::path& dir, const std::string& where,
                    const std::string& words) {
    BOOST_TEST_INFO(arguments);
    const bool compiles = arguments.rfind("derive", 0) != 0;
    const auto r = run_eomc(arguments + (compiles ? cache : ""), dir);
    BOOST_TEST(r.status == 2, r.err);
    BOOST_TEST(r.err.rfind(where, 0) == 0u, r.err);
    BOOST_TEST(r.err.find(": error: ") != std::string::npos, r.err);
    BOOST_TEST(r.err.find(words) != std::string::npos, r.err);
}

}  // namespace

// 1. --set of a coordinate or a rate, and --vary of one, get the rows' check the scene's own values get.
BOOST_AUTO_TEST_CASE(a_set_or_varied_start_off_the_rod_is_refused) {
    const fs::path dir = scratch("cli-starts", "rows");
    expect_refused("simulate " + pendulum + " --set x=5", dir, "--set x=5",
                   "violates the constraint 'rod': f(q0, 0) = 24.669");
    expect_refused("simulate " + pendulum + " --set x_dot=1", dir, "--set x_dot=1",
                   "violates the constraint 'rod': df/dt(q0, q0_dot, 0)");
    expect_refused("ensemble " + pendulum + " --vary 'x=normal(0.5,0.1)' --samples 3 --t-end 0.1", dir, "--vary x=",
                   "every member was refused; member 0: the initial state violates the constraint 'rod'");
    expect_refused("sweep " + pendulum + " --grid x=0.1:0.3:3 --t-end 0.1", dir, "--grid x=0.1",
                   "violates the constraint 'rod'");
}

BOOST_AUTO_TEST_CASE(a_set_start_on_the_rod_runs) {
    const fs::path dir = scratch("cli-starts", "valid");
    // (0.6, −√(1.2² − 0.6²)) lies on the rod to round-off, at rest: the rod's residual stays there.
    const auto r = run_eomc("simulate " + pendulum + " --set x=0.6 --set y=-1.0392304845413263 --t-end 0.5" + cache, dir);
    BOOST_TEST(r.status == 0, r.err);
    BOOST_TEST(r.out.find("rod ") != std::string::npos, r.out);
}

// 2. M positive definite: a [lagrangian] mass in the file or by --set, a [[body]] mass by --vary.
BOOST_AUTO_TEST_CASE(a_negative_mass_is_refused_on_every_path) {
    const fs::path dir = scratch("cli-starts", "mass");
    const fs::path scene = write_scene(dir, edited("bouncing_ball.toml", "m = 1.0", "m = -1.0"));
    // T = "m*y_dot^2/2" is line 14, its text at column 6: M = m = −1.
    expect_refused("simulate " + scene.string(), dir, scene.string() + ":14:6",
                   "the mass matrix is not positive definite at the initial state with the scene's initial values and "
                   "default parameters (its smallest eigenvalue is -1,");
    expect_refused("simulate " + scenes + "bouncing_ball.toml --set m=-1", dir, "--set m=-1",
                   "the mass matrix is not positive definite");
    expect_refused("ensemble " + scenes + "falling_particle.toml --vary 'm=normal(-1,0.1)' --samples 3 --t-end 0.1", dir,
                   "--vary m=", "every member was refused; member 0: the mass matrix is not positive definite");
}

// A member refused among members that run: its row says why, the others run, exit 0.
BOOST_AUTO_TEST_CASE(a_refused_member_is_a_row_with_its_reason) {
    const fs::path dir = scratch("cli-starts", "member");
    const fs::path csv = dir / "members.csv";
    const auto r = run_eomc("ensemble " + scenes + "falling_particle.toml --vary 'm=uniform(-1,1)' --samples 8 --seed 1 "
                            "--t-end 0.1 -o " + csv.string() + cache,
                            dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const std::string rows = slurp(csv);
    std::size_t refused = 0, ok = 0;
    for (std::size_t at = 0; (at = rows.find('\n', at)) != std::string::npos; ++at) {
        const std::string row = rows.substr(at + 1, rows.find('\n', at + 1) - at - 1);
        if (row.empty()) continue;
        const bool negative = row.find(",-") == row.find(',');  // the mass m, the first input
        const bool failed = row.find(",failed,") != std::string::npos;
        BOOST_TEST(negative == failed, row);
        if (failed) BOOST_TEST(row.find("the mass matrix is not positive definite") != std::string::npos, row);
        (failed ? refused : ok) += 1;
    }
    BOOST_TEST(refused > 0u);
    BOOST_TEST(ok > 0u);
}

// Principal moments: positive and A + B >= C; a lamina's equality (2 + 3 = 5) is a body's.
BOOST_AUTO_TEST_CASE(moments_that_violate_the_triangle_inequality_are_refused) {
    const fs::path dir = scratch("cli-starts", "inertia");
    const fs::path rigid = write_scene(dir, edited("dzhanibekov.toml", "inertia = [\"2\", \"3\", \"5\"]",
                                                   "inertia = [\"2\", \"3\", \"6\"]"));
    expect_refused("derive " + rigid.string(), dir, rigid.string() + ":10:11",
                   "violate the triangle inequality A + B >= C (2 + 3 < 6)");
    const fs::path body = write_scene(dir, edited("ball_on_turntable.toml", "\"2*m*r^2/5\", \"2*m*r^2/5\", \"2*m*r^2/5\"",
                                                  "\"2*m*r^2/5\", \"2*m*r^2/5\", \"-2*m*r^2/5\""));
    expect_refused("derive " + body.string(), dir, body.string() + ":35:11", "must be positive");
    expect_refused("simulate " + scenes + "hess_top.toml --set C=100", dir, "--set C=100",
                   "violate the triangle inequality");
    expect_refused("ensemble " + scenes + "hess_top.toml --vary 'C=normal(100,1)' --samples 2 --t-end 0.1", dir,
                   "--vary C=", "violate the triangle inequality");
    const auto lamina = run_eomc("derive " + scenes + "dzhanibekov.toml", dir);
    BOOST_TEST(lamina.status == 0, lamina.err);
}

// 3. The constraint qualification: a row whose Jacobian vanishes on the manifold, or rows dependent
// at the start, refused at exit 2 naming the row (they used to fail at exit 1, "non-finite
// derivative").
BOOST_AUTO_TEST_CASE(a_degenerate_or_dependent_row_is_refused_naming_it) {
    const fs::path dir = scratch("cli-starts", "rank");
    // Line 25, column 14: the row's text.
    const fs::path squared = write_scene(dir, hanging("(x^2 + y^2 - l^2)^2"));
    expect_refused("simulate " + squared.string(), dir, squared.string() + ":25:14",
                   "the Jacobian of the constraint 'rod' vanishes at the initial state");
    // Off x = 0 the start is on the rod to round-off only; the square is as small, not a violation.
    const fs::path rounded = write_scene(dir, edited("pendulum_cartesian.toml", "holonomic = \"x^2 + y^2 - l^2\"",
                                                     "holonomic = \"(x^2 + y^2 - l^2)^2\""));
    expect_refused("simulate " + rounded.string(), dir, rounded.string() + ":25:14",
                   "the Jacobian of the constraint 'rod' vanishes at the initial state");
    // y + l = 0 beside the rod: independent rows in general, dependent at the bottom, x = 0.
    const fs::path floor = write_scene(dir, hanging("x^2 + y^2 - l^2") + "\n[[constraint]]\nname = \"floor\"\n"
                                                                          "holonomic = \"y + l\"\n");
    expect_refused("simulate " + floor.string(), dir, floor.string() + ":35:14",
                   "the constraint 'floor' is linearly dependent on 'rod' at the initial state");
    // The same row twice: dependent everywhere.
    const fs::path twice = write_scene(dir, slurp(pendulum) + "\n[[constraint]]\nname = \"rod2\"\n"
                                                              "holonomic = \"x^2 + y^2 - l^2\"\n");
    expect_refused("simulate " + twice.string(), dir, twice.string() + ":25:14", "'rod' and 'rod2' are dependent");
}
