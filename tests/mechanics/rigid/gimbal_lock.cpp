// The run-time stop at a singular set of M, through `eomc`: a heavy top in Euler angles that
// falls through the pole θ = 0 (no spin, θ0 = 0.3, θ̇0 = −1) stops with a message naming the
// set sin(theta) = 0 before any non-finite number is written; a top that stays away from the
// pole runs to t_end with its momenta p_φ, p_ψ tracked; `eomc derive`/`generate` warn.
#define BOOST_TEST_MODULE rigid_gimbal_lock
#include <boost/test/unit_test.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "command.hpp"
#include "reduction_scenes.hpp"

using namespace test_support;

namespace {

std::vector<std::vector<double>> csv_rows(const std::string& text, std::string* header) {
    std::istringstream in(text);
    std::string line;
    std::getline(in, *header);
    std::vector<std::vector<double>> rows;
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::istringstream cells(line);
        std::string cell;
        while (std::getline(cells, cell, ',')) row.push_back(std::stod(cell));
        rows.push_back(row);
    }
    return rows;
}

const char* falling = " --set theta=0.3 --set theta_dot=-1 --set phi_dot=0 --set psi_dot=0";

}  // namespace

BOOST_AUTO_TEST_CASE(a_top_falling_through_the_pole_stops_at_the_singular_set) {
    for (const std::string method : {"dopri5", "rk4 --step 0.01"}) {
        const fs::path dir = scratch("rigid", "gimbal_lock_" + method.substr(0, method.find(' ')));
        const fs::path scene = write_scene(dir, rigid_scenes::top());
        const Result r = run_eomc("simulate " + scene.string() + falling + " --integrator " + method +
                                      " --output " + (dir / "run.csv").string(),
                                  dir);
        BOOST_TEST(r.status != 0);
        BOOST_TEST(r.err.find("the state reached the singular set sin(theta) = 0 of the mass matrix (gimbal lock") !=
                       std::string::npos,
                   r.err);
        BOOST_TEST(r.err.find(" at t = 0.3") != std::string::npos, r.err);  // θ = 0.3 − t + O(t²): near t ≈ 0.33
        // The rows up to the last accepted state are kept; every number in them is finite.
        const std::string text = slurp(dir / "run.csv");
        BOOST_TEST(text.find("nan") == std::string::npos);
        BOOST_TEST(text.find("inf") == std::string::npos);
        std::string header;
        const auto rows = csv_rows(text, &header);
        BOOST_REQUIRE(!rows.empty());
        BOOST_TEST(header.rfind("t,phi,theta,psi,phi_dot,theta_dot,psi_dot,energy,momentum_phi,momentum_psi", 0) == 0u);
        const double theta_last = rows.back()[2];
        BOOST_TEST(theta_last > 0.0);    // still on the near side of the pole
        BOOST_TEST(theta_last < 0.05);   // and close to it
        BOOST_TEST(rows.back()[0] > 0.3);
        BOOST_TEST(rows.back()[0] < 0.35);
    }
}

BOOST_AUTO_TEST_CASE(a_top_away_from_the_pole_runs_and_keeps_its_momenta) {
    const fs::path dir = scratch("rigid", "spinning_top");
    const fs::path scene = write_scene(dir, rigid_scenes::top());
    const Result r = run_eomc("simulate " + scene.string() + " --summary json", dir);
    BOOST_TEST(r.status == 0, r.err);
    BOOST_TEST(r.out.find("\"momentum_phi\": {\"initial\": ") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("\"momentum_psi\": {\"initial\": ") != std::string::npos, r.out);
    // The warning of the set is printed, the run is not refused.
    BOOST_TEST(r.err.find("warning: the mass matrix is singular where sin(theta) = 0") != std::string::npos, r.err);
}

BOOST_AUTO_TEST_CASE(derive_and_generate_warn_of_the_singular_set) {
    const fs::path dir = scratch("rigid", "warn");
    const fs::path scene = write_scene(dir, rigid_scenes::top());
    const Result d = run_eomc("derive " + scene.string(), dir);
    BOOST_TEST(d.status == 0);
    BOOST_TEST(d.err.find("scene.toml:17:") != std::string::npos, d.err);
    BOOST_TEST(d.err.find("gimbal lock") != std::string::npos, d.err);
    const Result g = run_eomc("generate " + scene.string() + " -o " + dir.string(), dir);
    BOOST_TEST(g.status == 0);
    BOOST_TEST(g.err.find("warning: the mass matrix is singular where sin(theta) = 0") != std::string::npos, g.err);
    // A scene whose M is regular everywhere warns of nothing.
    const fs::path damped = write_file(dir / "damped.toml", rigid_scenes::damped);
    const Result q = run_eomc("derive " + damped.string(), dir);
    BOOST_TEST(q.status == 0);
    BOOST_TEST(q.err.empty(), q.err);
}
