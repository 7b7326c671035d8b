// `eomc sweep` and `eomc ensemble` as a user meets them: the CSV and summaries, the same bytes on
// 1 and 2 threads, bad specifications refused at their flag with exit 2 and nothing written.
#define BOOST_TEST_MODULE cli_ensemble
#include <boost/test/unit_test.hpp>

#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "command.hpp"

namespace fs = std::filesystem;
using test_support::run_command;
using test_support::run_eomc;
using test_support::scratch;
using test_support::slurp;

namespace {

const std::string damped = EOMC_SOURCE_DIR "/scenes/damped_oscillator.toml";
// Each test's kernels cached in the build tree, never the user's ~/.cache.
const std::string cache = " --cache-dir " EOMC_BINARY_DIR "/test-cache";

}  // namespace

BOOST_AUTO_TEST_CASE(an_ensemble_is_the_same_on_one_and_two_threads) {
    const fs::path dir = scratch("cli-ensemble", "threads");
    const std::string common = "ensemble " + damped + cache +
                               " --vary 'w=normal(1,0.1)' --vary 'x=uniform(0.5,1.5)' --samples 300 --seed 99"
                               " --t-end 5 --format json";
    const auto one = run_eomc(common + " --threads 1 -o " + (dir / "one.csv").string(), dir);
    const auto two = run_eomc(common + " --threads 2 -o " + (dir / "two.csv").string(), dir);
    BOOST_TEST_REQUIRE(one.status == 0, one.err);
    BOOST_TEST_REQUIRE(two.status == 0, two.err);
    const std::string a = slurp(dir / "one.csv"), b = slurp(dir / "two.csv");
    BOOST_TEST(a == b);
    BOOST_TEST(a.rfind("member,w,x,status,t,x,x_dot,events,message\n0,", 0) == 0u);
    std::size_t rows = 0;
    for (char c : a) rows += c == '\n';
    BOOST_TEST(rows == 301u);
    // The statistics (everything after the timings) are the same bytes too.
    BOOST_TEST(one.out.substr(one.out.find("\"statistics\"")) == two.out.substr(two.out.find("\"statistics\"")));
    BOOST_TEST(one.out.find("\"threads\": 1,") != std::string::npos);
    BOOST_TEST(two.out.find("\"threads\": 2,") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(a_sweep_prints_its_statistics) {
    const fs::path dir = scratch("cli-ensemble", "sweep");
    const auto r = run_eomc("sweep " + damped + cache + " --grid w=1:2:3 --grid gamma=0.1 -o " +
                                (dir / "sweep.csv").string(),
                            dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("3 runs with dopri5") != std::string::npos);
    BOOST_TEST(r.out.find("3 ok, 0 stopped by a terminal event, 0 failed") != std::string::npos);
    const std::string csv = slurp(dir / "sweep.csv");
    BOOST_TEST(csv.find("\n1,1.5,0.10000000000000001,ok,20,") != std::string::npos);
}

// Each bad specification: exit 2, the flag named on stderr, no CSV (not even a temporary).
BOOST_AUTO_TEST_CASE(bad_specifications_write_nothing) {
    const fs::path dir = scratch("cli-ensemble", "refusals");
    const std::string out = " -o " + (dir / "out.csv").string();
    const struct {
        std::string arguments, flag, words;
    } cases[] = {
        {"sweep " + damped + " --grid ww=1:2:3", "--grid ww=1:2:3", "did you mean 'w'"},
        {"sweep " + damped + " --grid w=2:1:3", "--grid w=2:1:3", "reversed"},
        {"sweep " + damped + " --grid w=1:1:3", "--grid w=1:1:3", "empty"},
        {"sweep " + damped + " --grid w=1:2:0", "--grid w=1:2:0", "at least 1"},
        {"sweep " + damped + " --grid w=1:2:3 --set w=2", "--grid w=1:2:3", "--set"},
        {"ensemble " + damped + " --vary 'w=normal(1,0.1)' --samples=-3", "--samples", "positive"},
        {"ensemble " + damped + " --vary 'w=normal(1,0.1)' --samples 0", "--samples", "at least 1"},
        {"ensemble " + damped + " --vary 'w=normal(1,-0.1)' --samples 5", "--vary w=normal(1,-0.1)", "sigma > 0"},
        {"ensemble " + damped + " --vary 'w=uniform(2,1)' --samples 5", "--vary w=uniform(2,1)", "a < b"},
        {"ensemble " + damped + " --vary 'w=normal(1,inf)' --samples 5", "--vary w=normal(1,inf)", "not a number"},
        {"ensemble " + damped + " --vary 'w=normal(1,0.1)' --samples 5 --seed x", "--seed", "whole number"},
    };
    for (const auto& c : cases) {
        BOOST_TEST_INFO(c.arguments);
        const auto r = run_eomc(c.arguments + cache + out, dir);
        BOOST_TEST(r.status == 2);
        BOOST_TEST(r.err.find(c.flag + ": error: ") != std::string::npos, r.err);
        BOOST_TEST(r.err.find(c.words) != std::string::npos, r.err);
        BOOST_TEST(!fs::exists(dir / "out.csv"));
    }
    std::size_t left = 0;
    for (const auto& entry : fs::directory_iterator(dir)) left += entry.path().filename() != "stdout" &&
                                                                 entry.path().filename() != "stderr";
    BOOST_TEST(left == 0u);
}

// --plot draws the bifurcation diagram as a PNG; without gnuplot the CSV is still written, with a
// warning; a bad column is refused before anything is written.
BOOST_AUTO_TEST_CASE(a_sweep_draws_its_picture) {
    const fs::path dir = scratch("cli-ensemble", "plot");
    const std::string hoop = EOMC_SOURCE_DIR "/scenes/bead_on_hoop_damped.toml";
    const std::string args = "sweep " + hoop + cache + " --grid omega=0:8:9 --t-end 5 -o " + (dir / "h.csv").string() +
                             " --plot " + (dir / "h.png").string();
    const auto drawn = run_eomc(args, dir);
    BOOST_TEST_REQUIRE(drawn.status == 0, drawn.err);
    if (!test_support::run_command("command -v gnuplot", dir).out.empty())
        BOOST_TEST(slurp(dir / "h.png").substr(0, 8) == std::string("\x89PNG\r\n\x1a\n"));
    fs::remove(dir / "h.png");
    fs::remove(dir / "h.csv");
    const auto none = test_support::run_command(std::string(EOMC_EXECUTABLE) + " " + args, dir,
                                                "EOMC_GNUPLOT=/nonexistent/gnuplot");
    BOOST_TEST(none.status == 0, none.err);
    BOOST_TEST(none.err.find("warning: gnuplot was not found") != std::string::npos, none.err);
    BOOST_TEST(fs::exists(dir / "h.csv"));
    BOOST_TEST(!fs::exists(dir / "h.png"));
    fs::remove(dir / "h.csv");
    const auto bad = run_eomc(args + " --plot-column thet", dir);
    BOOST_TEST(bad.status == 2);
    BOOST_TEST(bad.err.find("--plot-column: error: no column 'thet'; did you mean 'theta'?") != std::string::npos, bad.err);
    BOOST_TEST(!fs::exists(dir / "h.csv"));
    BOOST_TEST(!fs::exists(dir / "h.png"));
}

// The MPI tests run only where eomc is built with MPI and CMake found mpirun (not in sanitizer
// builds); elsewhere Boost.Test reports them skipped, with the reason.
namespace {

#ifdef EOMC_MPIEXEC
const std::string mpiexec = EOMC_MPIEXEC;
#else
const std::string mpiexec;
#endif

boost::test_tools::assertion_result mpi_available(boost::unit_test::test_unit_id) {
    boost::test_tools::assertion_result available(!mpiexec.empty());
    available.message() << "eomc is built without MPI or CMake found no mpirun: the MPI test is skipped";
    return available;
}

// `mpirun -np 2` (oversubscribed on a small machine) of eomc, killed after 60 s: a job that hangs
// fails its test instead of hanging it. CI runs as root, which Open MPI refuses unless told.
test_support::Result mpirun(const std::string& arguments, const fs::path& dir, const std::string& env = "") {
    return test_support::run_command("timeout 60 " + mpiexec + " -np 2 --oversubscribe -x EOMC_TEST_FAIL_RANK " +
                                         EOMC_EXECUTABLE + " " + arguments,
                                     dir, "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + env);
}

std::size_t occurrences(const std::string& text, const std::string& line) {
    std::size_t n = 0;
    for (auto at = text.find(line); at != std::string::npos; at = text.find(line, at + 1)) ++n;
    return n;
}

}  // namespace

// Each rank runs every other member and rank 0 gathers them: the CSV and the statistics are the
// bytes of one process.
BOOST_AUTO_TEST_CASE(two_mpi_ranks_give_the_bytes_of_one_process, *boost::unit_test::precondition(mpi_available)) {
    const fs::path dir = scratch("cli-ensemble", "mpi");
    const std::string args = "ensemble " + damped + cache +
                             " --vary 'w=lognormal(0,0.2)' --vary 'gamma=uniform(0,0.3)' --samples 101 --seed 5"
                             " --t-end 5 --threads 1 --format json -o ";
    const auto one = run_eomc(args + (dir / "one.csv").string(), dir);
    BOOST_TEST_REQUIRE(one.status == 0, one.err);
    const auto two = mpirun(args + (dir / "two.csv").string(), dir);
    BOOST_TEST_REQUIRE(two.status == 0, two.err);
    BOOST_TEST(slurp(dir / "one.csv") == slurp(dir / "two.csv"));
    BOOST_TEST(two.out.find("\"ranks\": 2,") != std::string::npos, two.out);
    BOOST_TEST(one.out.substr(one.out.find("\"statistics\"")) == two.out.substr(two.out.find("\"statistics\"")));
}

// An error on one rank ends the job with the one-process run's message, printed once, and its exit
// status; nothing is written. Rank 1's member ending at a subnormal value used to throw there
// while rank 0 waited in MPI_Gather and rank 1 in MPI_Finalize: the job hung with no output.
BOOST_AUTO_TEST_CASE(an_error_on_one_mpi_rank_ends_the_job_as_one_process_would,
                     *boost::unit_test::precondition(mpi_available)) {
    const fs::path dir = scratch("cli-ensemble", "mpi-errors");
    // Member 1 (rank 1's) ends at x_dot = 7.5e-322.
    const std::string sweep = "sweep " + damped + cache +
                              " --grid gamma=1:50:2 --set w=0 --set x_dot=1 --integrator rk4 --step 0.01 --t-end 14.8"
                              " --observe X=x_dot --threads 1 -o ";
    const auto one = run_eomc(sweep + (dir / "one.csv").string(), dir);
    BOOST_TEST_REQUIRE(one.status == 0, one.err);
    const auto two = mpirun(sweep + (dir / "two.csv").string(), dir);
    BOOST_TEST_REQUIRE(two.status == 0, two.err);
    BOOST_TEST(slurp(dir / "one.csv") == slurp(dir / "two.csv"));

    // Rank 1 alone fails (the test hook): the job ends with rank 1's error, as one process ends
    // with it, printed once (by rank 0), exit 2.
    const auto alone = run_command(std::string(EOMC_EXECUTABLE) + " " + sweep + (dir / "no.csv").string(), dir,
                                   "EOMC_TEST_FAIL_RANK=0");
    BOOST_TEST_REQUIRE(alone.status == 2, alone.err);
    const auto failed = mpirun(sweep + (dir / "no.csv").string(), dir, "EOMC_TEST_FAIL_RANK=1");
    BOOST_TEST(failed.status == alone.status, failed.err);
    BOOST_TEST(occurrences(failed.err, alone.err) == 1u, failed.err);
    BOOST_TEST(!fs::exists(dir / "no.csv"));

    // Every member refused on every rank: the one-process line and status.
    const std::string refused = "ensemble " + std::string(EOMC_SOURCE_DIR) + "/scenes/disk_tube_ball.toml" + cache +
                                " --vary 'r=lognormal(-712,0.001)' --samples 3 --t-end 0.01 --observe X=r -o " +
                                (dir / "no.csv").string();
    const auto refused_one = run_eomc(refused, dir);
    BOOST_TEST_REQUIRE(refused_one.status == 2, refused_one.err);
    BOOST_TEST(refused_one.err.find("every member was refused; member 0: r=") != std::string::npos, refused_one.err);
    const auto refused_two = mpirun(refused, dir);
    BOOST_TEST(refused_two.status == 2, refused_two.err);
    BOOST_TEST(occurrences(refused_two.err, refused_one.err) == 1u, refused_two.err);
    BOOST_TEST(!fs::exists(dir / "no.csv"));
}

// --batch as a user meets it: the rk4 CSV of the linear oscillator the same bytes as without; a
// method the batch does not run refused at --batch, exit 2, nothing written.
BOOST_AUTO_TEST_CASE(a_batched_ensemble_writes_the_same_csv) {
    const fs::path dir = scratch("cli-ensemble", "batch");
    const std::string common = "ensemble " + damped + cache + " --vary 'w=normal(1,0.1)' --samples 30 --seed 5 --t-end 5";
    const std::string rk4 = common + " --integrator rk4 --step 0.01";
    const auto alone = run_eomc(rk4 + " -o " + (dir / "alone.csv").string(), dir);
    const auto batched = run_eomc(rk4 + " --batch -o " + (dir / "batched.csv").string(), dir);
    BOOST_TEST_REQUIRE(alone.status == 0, alone.err);
    BOOST_TEST_REQUIRE(batched.status == 0, batched.err);
    BOOST_TEST(slurp(dir / "alone.csv") == slurp(dir / "batched.csv"));
    BOOST_TEST(batched.out.find("batches of 4 in lock step") != std::string::npos);
    const auto refused = run_eomc(common + " --integrator dop853 --batch -o " + (dir / "no.csv").string(), dir);
    BOOST_TEST(refused.status == 2);
    BOOST_TEST(refused.err.find("--batch") != std::string::npos, refused.err);
    BOOST_TEST(!fs::exists(dir / "no.csv"));
}

// sweep --equilibria: the hoop's verdicts per point, one CSV row per equilibrium, no kernel; an
// initial value on the grid refused at its --grid.
BOOST_AUTO_TEST_CASE(an_equilibrium_sweep_writes_its_verdicts) {
    const fs::path dir = scratch("cli-ensemble", "equilibria");
    const std::string hoop = EOMC_SOURCE_DIR "/scenes/bead_on_hoop_damped.toml";
    const auto r = run_eomc("sweep " + hoop + " --grid omega=4:5:2 --equilibria -o " + (dir / "eq.csv").string(), dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    BOOST_TEST(r.out.find("omega = 4: 2 equilibria, 1 stable, 1 unstable") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("omega = 5: 4 equilibria, 2 stable, 2 unstable") != std::string::npos, r.out);
    const std::string csv = slurp(dir / "eq.csv");
    BOOST_TEST(csv.rfind("point,omega,equilibria,theta,verdict,growth\n0,4,2,0,stable,", 0) == 0u, csv);
    const auto bad = run_eomc("sweep " + hoop + " --grid theta=0:1:2 --equilibria -o " + (dir / "no.csv").string(), dir);
    BOOST_TEST(bad.status == 2);
    BOOST_TEST(bad.err.find("--grid theta=0:1:2") != std::string::npos, bad.err);
    BOOST_TEST(!fs::exists(dir / "no.csv"));
}

namespace {

// The CSV's rows as cells (no quoted commas in these tests' messages).
std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::stringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells;
        std::stringstream cells_in(line);
        for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

}  // namespace

// A member that ends at a subnormal value (x_dot = 7.5e-322 after γ = 50 has damped it): its
// --observe columns are the double values, as for any other member; CLN, which has no subnormal
// floats, used to stop the whole sweep after every member ran ("floating point underflow", exit
// 1, no CSV).
BOOST_AUTO_TEST_CASE(an_observation_of_a_subnormal_final_state_is_its_value) {
    const fs::path dir = scratch("cli-ensemble", "subnormal-state");
    const auto r = run_eomc("sweep " + damped + cache +
                                " --grid gamma=1:50:2 --set w=0 --set x_dot=1 --integrator rk4 --step 0.01 --t-end 14.8"
                                " --observe 'V=x_dot' --observe 'R=x_dot/x' --observe 'L=log(-x)' -o " +
                                (dir / "s.csv").string(),
                            dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const auto rows = csv_rows(slurp(dir / "s.csv"));
    BOOST_TEST_REQUIRE(rows.size() == 3u);
    BOOST_TEST(slurp(dir / "s.csv").rfind("member,gamma,status,t,x,x_dot,V,R,L,events,message\n", 0) == 0u);
    for (std::size_t m : {1u, 2u}) {
        BOOST_TEST_INFO("member " << m - 1);
        BOOST_TEST(rows[m][2] == "ok");
        BOOST_TEST(rows[m][6] == rows[m][5]);  // V = x_dot, to the last digit
        const double x = std::stod(rows[m][4]), v = std::strtod(rows[m][5].c_str(), nullptr);
        BOOST_TEST(std::strtod(rows[m][7].c_str(), nullptr) == v / x);
        BOOST_TEST(rows[m][8].empty());  // the log of a negative number: no real value
    }
    const double v = std::strtod(rows[2][5].c_str(), nullptr);
    BOOST_TEST((v > 0 && v < std::numeric_limits<double>::min()));  // the case: a subnormal end
}

// A subnormal draw is refused as its member's bad input, like an infinite one (the start's checks
// hand the value to CLN), with its reason; the other members run, and their --observe column is
// their draw. Every member subnormal: the command's bad input, exit 2.
BOOST_AUTO_TEST_CASE(a_subnormal_draw_is_refused_and_the_others_run) {
    const fs::path dir = scratch("cli-ensemble", "subnormal-draw");
    const std::string ball = EOMC_SOURCE_DIR "/scenes/disk_tube_ball.toml";
    const auto r = run_eomc("ensemble " + ball + cache +
                                " --vary 'r=lognormal(-708.3,1)' --samples 12 --seed 2 --t-end 0.01 --observe X=r -o " +
                                (dir / "d.csv").string(),
                            dir);
    BOOST_TEST_REQUIRE(r.status == 0, r.err);
    const std::string csv = slurp(dir / "d.csv");
    const auto rows = csv_rows(csv);
    BOOST_TEST_REQUIRE(rows.size() == 13u);
    std::vector<std::string> lines;
    std::stringstream in(csv);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::size_t ok = 0, refused = 0;
    for (std::size_t m = 1; m < rows.size(); ++m) {
        BOOST_TEST_INFO("member " << m - 1);
        const double drawn = std::strtod(rows[m][1].c_str(), nullptr);
        if (drawn < std::numeric_limits<double>::min()) {
            ++refused;
            BOOST_TEST(rows[m][2] == "failed");
            BOOST_TEST(lines[m].find(",\"--set: error: r=") != std::string::npos, lines[m]);
            BOOST_TEST(lines[m].find("a subnormal value") != std::string::npos, lines[m]);
            BOOST_TEST(rows[m][7].empty());
        } else {
            ++ok;
            BOOST_TEST(rows[m][2] == "ok");
            BOOST_TEST(rows[m][7] == rows[m][1]);  // X = r, the draw
        }
    }
    BOOST_TEST(ok > 0u);
    BOOST_TEST(refused > 0u);
    BOOST_TEST(r.out.find(std::to_string(ok) + " ok, 0 stopped by a terminal event, " + std::to_string(refused) + " failed") !=
                   std::string::npos,
               r.out);
    const auto all = run_eomc("ensemble " + ball + cache +
                                  " --vary 'r=lognormal(-712,0.001)' --samples 3 --t-end 0.01 --observe X=r -o " +
                                  (dir / "no.csv").string(),
                              dir);
    BOOST_TEST(all.status == 2, all.err);
    BOOST_TEST(all.err.find("every member was refused") != std::string::npos, all.err);
    BOOST_TEST(all.err.find("a subnormal value") != std::string::npos, all.err);
    BOOST_TEST(!fs::exists(dir / "no.csv"));
}

// The memory an ensemble's rows will hold is estimated before anything is allocated or compiled
// (the kernel cache stays empty), and refused past --max-memory-mib at --samples with the estimate;
// the same flags under the limit run. 30 million members used to grow past 4 GB before the first ran.
BOOST_AUTO_TEST_CASE(an_ensemble_too_large_for_memory_is_refused_before_it_compiles) {
    const fs::path dir = scratch("cli-ensemble", "memory");
    const std::string args = "ensemble " + damped +
                             " --vary 'w=normal(1,0.1)' --t-end 0.01 --max-memory-mib 1000 -o " + (dir / "e.csv").string();
    const auto big = run_eomc(args + " --samples 30000000 --cache-dir " + (dir / "cache").string(), dir);
    BOOST_TEST(big.status == 2);
    BOOST_TEST(big.err.rfind("--samples: error: 30000000 members would hold about ", 0) == 0u, big.err);
    BOOST_TEST(big.err.find("GiB in memory") != std::string::npos, big.err);
    BOOST_TEST(big.err.find("more than the limit of 1000 MiB (--max-memory-mib") != std::string::npos, big.err);
    BOOST_TEST(!fs::exists(dir / "cache"));  // refused before the kernel compiled
    BOOST_TEST(!fs::exists(dir / "e.csv"));
    const auto grid = run_eomc("sweep " + damped + cache + " --grid w=1:2:10000 --grid gamma=0:1:10000 --max-memory-mib 100",
                               dir);
    BOOST_TEST(grid.status == 2);
    BOOST_TEST(grid.err.rfind("--grid: error: 100000000 members would hold about ", 0) == 0u, grid.err);
    const auto small = run_eomc(args + cache + " --samples 50 --progress", dir);
    BOOST_TEST_REQUIRE(small.status == 0, small.err);
    BOOST_TEST(small.err.find("50 / 50 runs") != std::string::npos, small.err);  // --progress without a terminal
    BOOST_TEST(csv_rows(slurp(dir / "e.csv")).size() == 51u);
}

// --budget-s: the work is estimated from the first point's (member's) time before the second runs,
// and refused past the budget (default an hour) with the estimate and the budget that would run it.
// `sweep --equilibria` over 10^8 points used to be accepted (days of work).
BOOST_AUTO_TEST_CASE(work_past_the_budget_is_refused_with_its_estimate) {
    const fs::path dir = scratch("cli-ensemble", "budget");
    const std::string hoop = EOMC_SOURCE_DIR "/scenes/bead_on_hoop_damped.toml";
    const auto huge = run_eomc("sweep " + hoop + " --grid omega=0:8:100000000 --equilibria -o " + (dir / "no.csv").string(),
                               dir);
    BOOST_TEST(huge.status == 2);
    BOOST_TEST(huge.err.rfind("--grid: error: 100000000 grid points would take about ", 0) == 0u, huge.err);
    BOOST_TEST(huge.err.find("more than --budget-s 3600; ask for fewer, or give --budget-s ") != std::string::npos, huge.err);
    // The budget it names runs them: it is at least the estimate, which is at least 3600 s.
    const std::string named = huge.err.substr(huge.err.rfind("--budget-s ") + 11);
    BOOST_TEST(std::stod(named) > 3600.0, named);
    BOOST_TEST(!fs::exists(dir / "no.csv"));

    const auto members = run_eomc("ensemble " + damped + cache +
                                      " --vary 'w=normal(1,0.1)' --samples 100000 --t-end 20 --budget-s 0.001 -o " +
                                      (dir / "no.csv").string(),
                                  dir);
    BOOST_TEST(members.status == 2);
    BOOST_TEST(members.err.rfind("--samples: error: 100000 members would take about ", 0) == 0u, members.err);
    BOOST_TEST(!fs::exists(dir / "no.csv"));

    // Within the budget, with --progress: the progress on stderr, the verdicts as without.
    const auto small = run_eomc("sweep " + hoop + " --grid omega=4:5:2 --equilibria --progress --budget-s 600 -o " +
                                    (dir / "eq.csv").string(),
                                dir);
    BOOST_TEST_REQUIRE(small.status == 0, small.err);
    BOOST_TEST(small.err.find("100%  2 / 2 grid points") != std::string::npos, small.err);
    BOOST_TEST(small.out.find("omega = 5: 4 equilibria, 2 stable, 2 unstable") != std::string::npos, small.out);
    BOOST_TEST(csv_rows(slurp(dir / "eq.csv")).size() == 7u);  // the header, 2 + 4 equilibria
}
