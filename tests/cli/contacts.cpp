// Contacts and constraint rows as a user meets them on the command line (impacts never missed,
// motion never faked): the scenes of the report, each against a closed form, through `eomc
// simulate` with its CSV and JSON summary. Mei, Special Topics in Analytical Mechanics, ch. 6
// (Newton's law, §6.5); the rows of a constrained run in the CSV are the projected state.
#define BOOST_TEST_MODULE cli_contacts
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "command.hpp"
#include "csv.hpp"

namespace fs = std::filesystem;
using test_support::Result;

namespace {

const double eps = std::numeric_limits<double>::epsilon();
constexpr double grav = 9.81;

Result simulate(const fs::path& dir, const std::string& scene, const std::string& extra = "") {
  const fs::path file = test_support::write_scene(dir, scene);
  return test_support::run_eomc("simulate '" + file.string() + "' --summary json --output '" + (dir / "run.csv").string() +
                                    "' --cache-dir '" + (dir / "cache").string() + "' " + extra,
                                dir);
}

// The times of the JSON summary's entries of one list ("impacts" or "zeno"), in order.
std::vector<double> summary_times(const std::string& json, const std::string& list) {
  const std::size_t at = json.find("\"" + list + "\": [");
  BOOST_REQUIRE(at != std::string::npos);
  const std::string rest = json.substr(at, json.find(']', at) - at);
  std::vector<double> out;
  const std::regex t_re("\"t\": ([-0-9.eE+]+)");
  for (auto it = std::sregex_iterator(rest.begin(), rest.end(), t_re); it != std::sregex_iterator(); ++it)
    out.push_back(std::stod((*it)[1]));
  return out;
}

// The times of the CSV rows labelled `label` (the last column).
std::vector<double> csv_times(const fs::path& csv, const std::string& label) {
  std::vector<double> out;
  for (const std::string& line : test_support::read_lines(csv))
    if (line.size() > label.size() && line.compare(line.size() - label.size(), label.size(), label) == 0)
      out.push_back(std::stod(line.substr(0, line.find(','))));
  return out;
}

const std::string ceiling_scene = R"([scene]
name = "u_ceiling"
summary = "ball thrown up at a ceiling y <= 10 that it just reaches"
[parameters]
m = 1.0
g = 9.81
e = 0.5
[coordinates]
y = { initial = 0.0, rate = 14.013850256086064 }
[lagrangian]
T = "m*y_dot^2/2"
V = "m*g*y"
[[unilateral]]
name = "ceiling"
gap = "10 - y"
restitution = "e"
[simulate]
t_end = 3.0
)";

std::string floor_scene(const std::string& gap, double e, double t_end) {
  return "[scene]\nname = \"drop\"\nsummary = \"a ball dropped from 1 m\"\n[parameters]\nm = 1.0\ng = 9.81\n"
         "[coordinates]\ny = { initial = 1.0, rate = 0.0 }\n[lagrangian]\nT = \"m*y_dot^2/2\"\nV = \"m*g*y\"\n"
         "[[unilateral]]\nname = \"floor\"\ngap = \"" + gap + "\"\nrestitution = \"" + std::to_string(e) +
         "\"\n[simulate]\nt_end = " + std::to_string(t_end) + "\nrtol = 1e-10\natol = 1e-12\n";
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_ceiling_just_reached_is_hit) {
  const fs::path dir = test_support::scratch("cli-contacts", "ceiling");
  const Result r = simulate(dir, ceiling_scene, "--rtol 1e-14 --atol 1e-14 --integrator dop853");
  BOOST_TEST_MESSAGE(r.err);
  BOOST_REQUIRE_EQUAL(r.status, 0);
  const double v0 = 14.013850256086064, v_minus = std::sqrt(v0 * v0 - 20.0 * grav);
  const double t_hit = (v0 - v_minus) / grav, s = 3.0 - t_hit;
  const double y_end = 10.0 - 0.5 * v_minus * s - 0.5 * grav * s * s;  // −3.1542542
  const auto impacts = summary_times(r.out, "impacts");
  BOOST_REQUIRE_EQUAL(impacts.size(), 1u);
  // Free flight is a quadratic that dop853 reproduces to round-off: the impact time carries the
  // locator's bracket and the tolerance over |ẏ⁻| = 0.434 m/s; y(3) that error times (1 + e) g s.
  const double dt = 8 * eps * t_hit + (1e-14 * 10 + 1e-14) / v_minus, dy = 1.5 * grav * dt * s + 1e-12;
  BOOST_TEST(std::abs(impacts[0] - t_hit) <= dt);
  BOOST_TEST(std::abs(test_support::last_csv_row(dir / "run.csv")[1] - y_end) <= dy);
  BOOST_TEST(csv_times(dir / "run.csv", "impact:ceiling") == impacts);
}

BOOST_AUTO_TEST_CASE(every_resolvable_bounce_is_reported_in_the_summary_and_the_csv) {
  // e = 0.8 from 1 m: t_k = t1 (1 + 2 e (1 − e^(k−1))/(1 − e)); the tenth impact at its time,
  // the summary's impacts and the CSV's impact rows the same list, the Zeno row after them.
  const fs::path dir = test_support::scratch("cli-contacts", "bounces");
  const Result r = simulate(dir, floor_scene("y", 0.8, 12.0));
  BOOST_REQUIRE_EQUAL(r.status, 0);
  const auto impacts = summary_times(r.out, "impacts");
  BOOST_REQUIRE(impacts.size() >= 10u);
  const double e = 0.8, t1 = std::sqrt(2.0 / grav);
  const double t10 = t1 * (1.0 + 2.0 * e * (1.0 - std::pow(e, 9)) / (1.0 - e));
  double bound = 0.0;  // the per-impact error grown by (1 + 2e) an impact (event_driven.cpp)
  for (int j = 1; j <= 10; ++j)
    bound = bound * (1 + 2 * e) + 8 * eps * t10 + (1e-10 * 2 + 1e-12) / (std::pow(e, j - 1) * std::sqrt(2 * grav));
  BOOST_TEST(std::abs(impacts[9] - t10) <= bound);
  BOOST_TEST(csv_times(dir / "run.csv", "impact:floor") == impacts);
  const auto zeno = summary_times(r.out, "zeno");
  BOOST_REQUIRE_EQUAL(zeno.size(), 1u);
  BOOST_TEST(zeno[0] > impacts.back());
  BOOST_TEST(csv_times(dir / "run.csv", "zeno:floor") == zeno);
}

BOOST_AUTO_TEST_CASE(a_gap_without_gradient_on_its_boundary_is_refused_naming_the_row) {
  const fs::path dir = test_support::scratch("cli-contacts", "cubed");
  const Result r = simulate(dir, floor_scene("y^3", 0.5, 2.0));
  BOOST_TEST_MESSAGE(r.err);
  BOOST_TEST(r.status != 0);
  BOOST_TEST(r.err.find("gradient of the constraint vanishes") != std::string::npos);
  BOOST_TEST(r.err.find("is floor") != std::string::npos);
  BOOST_TEST(r.err.find("t = 0.4515") != std::string::npos);  // √(2/g), where y³ closes
}

BOOST_AUTO_TEST_CASE(walls_that_pinch_with_restitution_are_refused) {
  // x ≥ 0 and −x ≥ 0 at the same place, e = 1, arriving at 1 m/s: no impulse keeps both.
  const fs::path dir = test_support::scratch("cli-contacts", "pinch");
  const Result r = simulate(dir, R"([scene]
name = "pinch"
summary = "a particle between two walls at the same place"
[parameters]
m = 1.0
[coordinates]
x = { initial = 0.0, rate = -1.0 }
[lagrangian]
T = "m*x_dot^2/2"
V = "0"
[[unilateral]]
name = "left"
gap = "x"
restitution = "1"
[[unilateral]]
name = "right"
gap = "-x"
restitution = "1"
[simulate]
t_end = 2.0
)");
  BOOST_TEST_MESSAGE(r.err);
  BOOST_TEST(r.status != 0);
  BOOST_TEST(r.err.find("no impulse satisfies Newton's law") != std::string::npos);
  BOOST_TEST(r.err.find("is left") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(the_csv_of_a_constrained_run_holds_the_projected_state) {
  // scenes/pendulum_cartesian.toml, l = 1.2: every row on x² + y² = l² and x ẋ + y ẏ = 0 to the
  // round-off of the projection (a few ulps of l², of l |u|), not to the step's tolerance (1e-12).
  const fs::path dir = test_support::scratch("cli-contacts", "rod");
  const Result r = test_support::run_eomc(std::string("simulate '") + EOMC_SOURCE_DIR + "/scenes/pendulum_cartesian.toml' "
                                          "--output '" + (dir / "run.csv").string() + "' --cache-dir '" +
                                          (dir / "cache").string() + "'",
                                          dir);
  BOOST_REQUIRE_EQUAL(r.status, 0);
  const auto lines = test_support::read_lines(dir / "run.csv");
  BOOST_REQUIRE(lines.size() > 10u);
  const double l = 1.2;
  double rod = 0.0, rate = 0.0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto v = test_support::csv_numbers(lines[i]);  // t, x, y, x_dot, y_dot, ...
    rod = std::max(rod, std::abs(v[1] * v[1] + v[2] * v[2] - l * l));
    rate = std::max(rate, std::abs(v[1] * v[3] + v[2] * v[4]) / (l * (std::abs(v[3]) + std::abs(v[4]) + 1e-300)));
  }
  BOOST_TEST_MESSAGE("rows: |x² + y² − l²| ≤ " << rod << ", |x ẋ + y ẏ| / (l |u|) ≤ " << rate);
  BOOST_TEST(rod <= 8 * eps * l * l);
  BOOST_TEST(rate <= 8 * eps);
}

BOOST_AUTO_TEST_CASE(a_splitting_method_is_refused_on_a_constrained_scene) {
  // verlet steps q̈ = a(q) and never projects: on the Cartesian pendulum it left the rod by 20 with
  // exit 0. The rows make the kernel non-separable: refused at the flag, exit 2.
  const fs::path dir = test_support::scratch("cli-contacts", "verlet");
  const Result r = test_support::run_eomc(std::string("simulate '") + EOMC_SOURCE_DIR + "/scenes/pendulum_cartesian.toml' "
                                          "--integrator verlet --step 0.001 --cache-dir '" + (dir / "cache").string() + "'",
                                          dir);
  BOOST_TEST(r.status == 2);
  BOOST_TEST(r.err.find("no constraint rows") != std::string::npos);
}
