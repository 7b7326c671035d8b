// Issue 29, hardening round 2: work that has a bound, refusals that come before anything is
// written, plots published like every other output, and constants that a double cannot carry.
// Each case failed before the change it tests.
#define BOOST_TEST_MODULE cli_bounded_work
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "command.hpp"

namespace fs = std::filesystem;
using test_support::Result;
using test_support::run_command;
using test_support::slurp;
using test_support::write_file;

namespace {

fs::path scratch(const std::string& name) { return test_support::scratch("cli-bounded-work", name); }

Result run(const std::string& arguments, const fs::path& dir, const std::string& env = "") {
    return run_command("timeout 300 " + std::string(EOMC_EXECUTABLE) + " " + arguments, dir, env);
}

std::size_t count_entries(const fs::path& dir) {
    std::size_t n = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) n += e.path().filename() != "stdout" && e.path().filename() != "stderr";
    return n;
}

const std::string hoop = EOMC_SOURCE_DIR "/scenes/bead_on_hoop_damped.toml";

// A gnuplot that records where it was told to draw and the mode of that directory, writes a PNG
// signature there, and (with FAKE_SLOW set) waits to be killed.
fs::path fake_gnuplot(const fs::path& dir) {
    const fs::path script = write_file(
        dir / "fake-gnuplot.sh",
        "#!/bin/sh\n"
        "out=$(sed -n \"s/^set output '\\(.*\\)'$/\\1/p\" \"$1\" | head -n 1)\n"
        "printf '%s\\n' \"$out\" > '" + (dir / "record-output").string() + "'\n"
        "stat -c %a \"$(dirname \"$out\")\" > '" + (dir / "record-mode").string() + "'\n"
        "printf '\\211PNG\\r\\n\\032\\nfake' > \"$out\"\n"
        "if [ -n \"$FAKE_SLOW\" ]; then touch '" + (dir / "drawn").string() + "'; sleep 60; fi\n");
    fs::permissions(script, fs::perms::owner_all);
    return script;
}

}  // namespace

// ---- the plot: drawn in a private directory, published whole ----------------------------------

// gnuplot opened `.<png>.<pid>.tmp` beside the target by name: a link planted there made eomc
// overwrite the link's target. It now draws in this process's own 0700 directory, and the PNG
// reaches its name by the atomic path every CSV takes.
BOOST_AUTO_TEST_CASE(gnuplot_draws_in_a_private_directory_not_beside_the_target) {
    const fs::path dir = scratch("plot-private");
    const fs::path gnuplot = fake_gnuplot(dir), out = dir / "out", tmp = dir / "tmp";
    fs::create_directories(out);
    fs::create_directories(tmp);
    const Result r = run("sweep " + hoop + " --grid omega=4:5:2 --equilibria --plot " + (out / "h.png").string(), dir,
                         "EOMC_GNUPLOT=" + gnuplot.string() + " TMPDIR=" + tmp.string());
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const fs::path drawn = slurp(dir / "record-output").substr(0, slurp(dir / "record-output").size() - 1);
    BOOST_TEST(drawn.parent_path() != out, drawn);
    BOOST_TEST(drawn.parent_path().parent_path() == tmp, drawn);
    BOOST_TEST(slurp(dir / "record-mode") == "700\n");
    BOOST_TEST(slurp(out / "h.png") == std::string("\x89PNG\r\n\x1a\nfake"));
    BOOST_TEST(count_entries(out) == 1u);  // the PNG, no temporary
    BOOST_TEST(count_entries(tmp) == 0u);  // the private directory removed
}

// SIGTERM while gnuplot draws: nothing left beside the target, nor in TMPDIR.
BOOST_AUTO_TEST_CASE(a_signal_while_gnuplot_draws_leaves_nothing_behind) {
    const fs::path dir = scratch("plot-signal");
    const fs::path gnuplot = fake_gnuplot(dir), out = dir / "out", tmp = dir / "tmp";
    fs::create_directories(out);
    fs::create_directories(tmp);
    const fs::path driver = write_file(
        dir / "driver.sh",
        "FAKE_SLOW=1 EOMC_GNUPLOT='" + gnuplot.string() + "' TMPDIR='" + tmp.string() + "' '" + EOMC_EXECUTABLE +
            "' sweep '" + hoop + "' --grid omega=4:5:2 --equilibria --plot '" + (out / "h.png").string() +
            "' > /dev/null 2>&1 &\npid=$!\ni=0\nwhile [ ! -e '" + (dir / "drawn").string() +
            "' ] && [ $i -lt 1200 ]; do sleep 0.1; i=$((i + 1)); done\nkill -TERM $pid\nwait $pid\necho status=$?\n");
    const Result r = run_command("sh '" + driver.string() + "'", dir);
    BOOST_TEST(fs::exists(dir / "drawn"), "gnuplot never ran");
    BOOST_TEST(r.out == "status=143\n", r.out << r.err);  // killed by SIGTERM (128 + 15)
    BOOST_TEST(count_entries(out) == 0u);
    BOOST_TEST(count_entries(tmp) == 0u);
}

// ---- run -d: every refusal before the header is written or anything compiled -------------------

BOOST_AUTO_TEST_CASE(run_refuses_before_it_writes_the_header_or_compiles) {
    const fs::path dir = scratch("run-refuses-first");
    std::string ball = slurp(EOMC_SOURCE_DIR "/scenes/bouncing_ball.toml");
    ball.replace(ball.find("[simulate]"), 10, "[events]\napex = \"y_dot\"\n\n[simulate]");
    const fs::path scene = write_file(dir / "ball.toml", ball);
    const std::string cache = " --cache-dir " + (dir / "cache").string();

    // The CSV's name is a symbolic link: refused, and the link's target untouched.
    fs::create_directories(dir / "linked");
    write_file(dir / "victim", "keep");
    fs::create_symlink(dir / "victim", dir / "linked" / "bouncing_ball.csv");
    Result r = run("run " + scene.string() + " -d " + (dir / "linked").string() + cache, dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("bouncing_ball.csv: error: the output exists and is a symbolic link") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "linked" / "bouncing_ball.hpp"));
    BOOST_TEST(slurp(dir / "victim") == "keep");

    // Scene events with Moreau–Jean: refused at --contact-method, before the header and the compile.
    r = run("run " + scene.string() + " -d " + (dir / "mj").string() + " --contact-method moreau_jean" + cache, dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--contact-method: error: bouncing_ball: scene events (apex) together with unilateral rows") !=
                   std::string::npos,
               r.err);
    BOOST_TEST(r.out.empty(), r.out);  // not even the derivation
    BOOST_TEST(!fs::exists(dir / "mj" / "bouncing_ball.hpp"));
    BOOST_TEST(!fs::exists(dir / "cache"));

    // The sequential impact law with Moreau–Jean, and a Moreau–Jean run past its step budget.
    r = run("simulate " + std::string(EOMC_SOURCE_DIR "/scenes/bouncing_ball.toml") +
                " --contact-method moreau_jean --impact-law sequential" + cache,
            dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--impact-law: error:") != std::string::npos, r.err);
    r = run("simulate " + std::string(EOMC_SOURCE_DIR "/scenes/bouncing_ball.toml") +
                " --contact-method moreau_jean --step 1e-9 --t-end 5" + cache,
            dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("moreau_jean with step 1e-09 to t_end = 5 takes 5e+09 steps") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "cache"));
}

// ---- simulate: a run that its own pace projects past --budget-s stops, with the projection ------

// Moreau–Jean at step 1e-7 to t = 5 is 5·10^7 steps: within the step budget, but about half a
// minute of work. With --budget-s 5 it stops once it has run 2 s, says how long it would take,
// and --progress drew its line on stderr (not a terminal here) from the start.
BOOST_AUTO_TEST_CASE(a_run_projected_past_its_budget_stops_with_the_projection) {
    const fs::path dir = scratch("simulate-budget");
    const Result r = run("simulate " + std::string(EOMC_SOURCE_DIR "/scenes/bouncing_ball.toml") +
                             " --contact-method moreau_jean --step 1e-7 --t-end 5 --budget-s 5 --progress --cache-dir " +
                             (dir / "cache").string(),
                         dir);
    BOOST_TEST(r.status == 2);
    // "the first 2 s", or a little more on a loaded machine: the pace is checked every 64 steps.
    BOOST_TEST(r.err.find("--budget-s: error: bouncing_ball: at its pace over the first ") != std::string::npos, r.err);
    BOOST_TEST(r.err.find(" s (to t = ") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("more than the budget of 5 s") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("%  t = ") != std::string::npos, r.err);  // the progress line
}

// ---- integrals: a work budget and an "undecided at degree N" verdict --------------------------

// The exact elimination grows steeply with the degree (the heavy gyrostat: 1 s at degree 5,
// 35 s at 6, past 900 s at 7). With a budget too small for degree 5, Kovalevskaya's quartic,
// decided at degree 4, is still reported, and degree 5 is undecided rather than "none".
BOOST_AUTO_TEST_CASE(the_integral_search_stops_undecided_at_its_budget) {
    const fs::path dir = scratch("integrals-budget");
    const std::string top = EOMC_SOURCE_DIR "/scenes/kovalevskaya_top.toml";
    Result r = run("integrals " + top + " --degree 5 --search-budget 20000", dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("undecided at degree 5: the search stopped after its budget of 20000 entry operations "
                          "(--search-budget); the integrals of degree ≤ 4 are decided") != std::string::npos,
               r.out);
    BOOST_TEST(r.out.find("integral_4_1 (degree 4)") != std::string::npos, r.out);
    r = run("integrals " + top + " --degree 5 --format json", dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("\"undecided\": \"\"") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("\"name\": \"integral_4_1\"") != std::string::npos, r.out);
    r = run("integrals " + top + " --search-budget 0", dir);
    BOOST_TEST(r.status != 0);
}

// ---- constants beyond double's reach -----------------------------------------------------------

// sin(10^300): the double nearest 10^300 lies ~10^283 away, so sin of it is unrelated to
// sin(10^300) = a = −0.98575042516037699660… (mpmath at 400 digits). The kernel gets the exact
// value. V = a x from rest: ẍ = −a, x(1) = −a/2, which any method of order ≥ 2 integrates
// exactly: only rounding remains.
BOOST_AUTO_TEST_CASE(a_constant_beyond_doubles_reach_is_evaluated_exactly_or_refused) {
    const fs::path dir = scratch("constants");
    const auto scene = [&](const std::string& constant) {
        return write_file(dir / "c.toml", "[scene]\nname = \"constant_force\"\n\n[coordinates]\n"
                                          "x = { initial = 0.0, rate = 0.0 }\n\n[lagrangian]\nT = \"x_dot^2/2\"\n"
                                          "V = \"" + constant + "*x\"\n\n[simulate]\nt_end = 1.0\n")
            .string();
    };
    const std::string cache = " --cache-dir " + (dir / "cache").string();
    Result r = run("simulate " + scene("sin(10^300)") + " --summary json" + cache, dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const auto at = r.out.find("\"x\": ");
    BOOST_TEST_REQUIRE(at != std::string::npos, r.out);
    const double x1 = std::stod(r.out.substr(at + 5));
    BOOST_TEST(std::abs(x1 - 0.4928752125801884983) < 1e-14, x1);

    // --observe the same: −3.9430017006415080 = 4a at omega = 4 (it was rounding noise).
    r = run("sweep " + hoop + " --grid omega=4:4:1 --t-end 0.01 --observe 'S=sin(10^300)*omega' -o " +
                (dir / "s.csv").string() + cache,
            dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const std::string csv = slurp(dir / "s.csv");
    const auto row = csv.find("\n0,4,ok,");
    BOOST_TEST_REQUIRE(row != std::string::npos, csv);
    const std::string cells = csv.substr(row + 1);
    std::size_t comma = 0;
    for (int k = 0; k < 6; ++k) comma = cells.find(',', comma) + 1;  // member,omega,status,t,theta,theta_dot,S
    BOOST_TEST(std::abs(std::stod(cells.substr(comma)) - 4 * -0.9857504251603769966) < 1e-15, cells);

    r = run("generate " + scene("exp(10^4)") + " -o " + dir.string(), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("the constant exp(10000) is outside the range of double") != std::string::npos, r.err);
    r = run("generate " + scene("log(-2)") + " -o " + dir.string(), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("is not real") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(dir / "constant_force.hpp"));
}
