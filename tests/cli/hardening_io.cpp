// Issue 12, hardening: what eomc writes, what it loads, how much work it accepts, and what a
// signal leaves behind, tried as a hostile or careless user would. Most cases run the eomc
// binary; the SHA-256 vectors, the temporaries and the default cache directory are checked in
// process. CI runs as root, where permission bits do not stop anyone: the cases build the
// situations themselves (a 0777 directory, a chown to another uid) rather than rely on them.
#define BOOST_TEST_MODULE cli_hardening_io
#include <boost/test/unit_test.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "command.hpp"
#include "host/toolchain.hpp"
#include "support/cleanup.hpp"
#include "support/diagnostic.hpp"
#include "support/output_file.hpp"
#include "support/sha256.hpp"

extern char** environ;

namespace fs = std::filesystem;
using test_support::Result;
using test_support::slurp;

namespace {

fs::path scratch(const std::string& name) { return test_support::scratch("cli-hardening-io", name); }

Result run(const std::string& arguments, const fs::path& dir, const std::string& env = "") {
    // `timeout`: a regression that blocks (opening a FIFO) fails the case instead of hanging CI.
    return test_support::run_command("timeout 300 " + std::string(EOMC_EXECUTABLE) + " " + arguments, dir, env);
}

// For sh (the paths here hold no single quote). Built by appends: GCC 12's -Wrestrict misfires
// on "'" + std::string.
std::string quoted(const fs::path& p) {
    std::string out(1, '\'');
    out += p.string();
    out += '\'';
    return out;
}

const std::string dtb = EOMC_SOURCE_DIR "/scenes/disk_tube_ball.toml";
const std::string hoop = EOMC_SOURCE_DIR "/scenes/bead_on_hoop.toml";

// The entries of a directory whose names contain `part` (all of them for "").
std::vector<std::string> entries(const fs::path& dir, const std::string& part = "") {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().filename().string().find(part) != std::string::npos) out.push_back(e.path().filename().string());
    return out;
}

// The one kernel object in a cache directory.
fs::path only_object(const fs::path& cache) {
    const auto so = entries(cache, ".so");
    BOOST_REQUIRE_EQUAL(so.size(), 1u);
    return cache / so.front();
}

std::string final_q(const Result& r) {
    // JSON summary: ... "state": {"q": <value>, ...
    const auto at = r.out.find("\"q\": ");
    return at == std::string::npos ? "" : r.out.substr(at + 5, r.out.find_first_of(",}", at) - at - 5);
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

}  // namespace

// ---- 3: outputs replace only what they should --------------------------------------------

BOOST_AUTO_TEST_CASE(an_output_that_is_a_device_is_refused) {
    const fs::path dir = scratch("device");
    // Our own node, never a real one: a regression would replace this, not /dev/full.
    const fs::path device = dir / "full";
    if (::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0) {
        BOOST_TEST_MESSAGE("skipped: mknod needs root (" << std::strerror(errno) << "); /dev/zero stands in");
        const Result r = run("simulate " + dtb + " --cache-dir " + quoted(dir / "cache") + " --output /dev/zero", dir);
        BOOST_TEST(r.status == 2);
        BOOST_TEST(r.err.find("/dev/zero: error: the output exists and is a character device") != std::string::npos, r.err);
        return;
    }
    const Result r = run("simulate " + dtb + " --cache-dir " + quoted(dir / "cache") + " --output " + quoted(device), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find(device.string() + ": error: the output exists and is a character device") != std::string::npos,
               r.err);
    struct stat st {};
    BOOST_TEST((::lstat(device.c_str(), &st) == 0 && S_ISCHR(st.st_mode)));
    BOOST_TEST(entries(dir, ".tmp").empty());
    // Refused before anything was compiled.
    BOOST_TEST(entries(dir / "cache", ".so").empty());
}

// Exactly /dev/null is the one device accepted: the output is computed and thrown away (a run timed
// without its CSV), the node written to, never replaced.
BOOST_AUTO_TEST_CASE(dev_null_takes_the_output_and_stays_a_device) {
    const fs::path dir = scratch("dev_null");
    Result r = run("simulate " + dtb + " --cache-dir " + quoted(dir / "cache") + " --output /dev/null --summary json", dir);
    BOOST_TEST(r.status == 0, r.err);
    BOOST_TEST(!final_q(r).empty(), r.out);
    r = run("derive " + dtb + " -o /dev/null", dir);
    BOOST_TEST(r.status == 0, r.err);
    BOOST_TEST(r.out.empty());
    r = run("sweep " + dtb + " --cache-dir " + quoted(dir / "cache") + " --grid q=0.1:0.2:2 -o /dev/null", dir);
    BOOST_TEST(r.status == 0, r.err);
    struct stat st {};
    BOOST_TEST((::lstat("/dev/null", &st) == 0 && S_ISCHR(st.st_mode)));
    BOOST_TEST(entries(dir, ".tmp").empty());
}

BOOST_AUTO_TEST_CASE(an_output_that_is_a_fifo_is_refused_without_blocking) {
    const fs::path dir = scratch("fifo");
    const fs::path fifo = dir / "pipe.csv";
    BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
    const Result r = run("simulate " + dtb + " --cache-dir " + quoted(dir / "cache") + " --output " + quoted(fifo), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find(fifo.string() + ": error: the output exists and is a FIFO") != std::string::npos, r.err);
    const Result d = run("derive " + dtb + " -o " + quoted(fifo), dir);
    BOOST_TEST(d.status == 2);
    BOOST_TEST(d.err.find("is a FIFO") != std::string::npos, d.err);
    struct stat st {};
    BOOST_TEST((::lstat(fifo.c_str(), &st) == 0 && S_ISFIFO(st.st_mode)));
}

BOOST_AUTO_TEST_CASE(an_output_that_is_a_symbolic_link_is_refused_and_its_target_kept) {
    const fs::path dir = scratch("symlink");
    const fs::path victim = dir / "victim.txt", link = dir / "out.csv";
    write_text(victim, "precious\n");
    fs::create_symlink(victim, link);
    for (const std::string& command : {"simulate " + dtb + " --cache-dir " + quoted(dir / "cache") + " --output ",
                                      "derive " + dtb + " -o ", "run " + dtb + " --cache-dir " + quoted(dir / "cache") +
                                                                    " -d " + quoted(dir) + " --output "}) {
        const Result r = run(command + quoted(link), dir);
        BOOST_TEST(r.status == 2, command);
        BOOST_TEST(r.err.find(link.string() + ": error: the output exists and is a symbolic link") != std::string::npos,
                   r.err);
    }
    BOOST_TEST(fs::is_symlink(link));
    BOOST_TEST(slurp(victim) == "precious\n");
    BOOST_TEST(entries(dir, ".tmp").empty());
}

BOOST_AUTO_TEST_CASE(an_output_that_is_a_directory_is_refused) {
    const fs::path dir = scratch("directory");
    fs::create_directories(dir / "taken" / "inside");
    const Result r = run("derive " + dtb + " -o " + quoted(dir / "taken"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find((dir / "taken").string() + ": error: the output exists and is a directory") != std::string::npos,
               r.err);
    BOOST_TEST(fs::is_directory(dir / "taken" / "inside"));
    BOOST_TEST(entries(dir, ".tmp").empty());
}

BOOST_AUTO_TEST_CASE(a_link_planted_at_a_temporary_name_is_never_followed) {
    const fs::path dir = scratch("planted");
    const fs::path victim = dir / "victim.txt", target = dir / "out.txt";
    write_text(victim, "precious\n");
    // The names this process would try first: <target>.tmp.<pid>.<serial>, serials from 0.
    std::vector<fs::path> planted;
    for (int serial = 0; serial < 8; ++serial) {
        planted.push_back(fmt::format("{}.tmp.{}.{}", target.string(), ::getpid(), serial));
        fs::create_symlink(victim, planted.back());
    }
    eomc::write_file_atomically(target, "new output\n");
    BOOST_TEST(slurp(target) == "new output\n");
    BOOST_TEST(slurp(victim) == "precious\n");
    for (const auto& p : planted) BOOST_TEST(fs::is_symlink(p), p << " was removed or replaced");  // not ours
}

BOOST_AUTO_TEST_CASE(an_output_gets_the_mode_of_a_new_file_and_replaces_a_regular_one) {
    const fs::path dir = scratch("mode");
    const fs::path target = dir / "out.txt";
    write_text(target, "old\n");
    const mode_t old_umask = ::umask(027);
    eomc::write_file_atomically(target, "new\n");
    ::umask(old_umask);
    struct stat st {};
    BOOST_REQUIRE(::stat(target.c_str(), &st) == 0);
    BOOST_TEST((st.st_mode & 07777) == 0640u);  // 0666 less the umask, like any new file
    BOOST_TEST(slurp(target) == "new\n");
    BOOST_TEST(entries(dir, ".tmp").empty());
}

BOOST_AUTO_TEST_CASE(a_target_that_turns_into_a_fifo_during_the_run_is_refused_and_the_temporary_removed) {
    const fs::path dir = scratch("late-fifo");
    const fs::path target = dir / "out.csv";
    eomc::AtomicOutput out(target);
    out.write("t,q\n0,1\n");
    BOOST_REQUIRE(fs::exists(out.temporary()));
    BOOST_REQUIRE(::mkfifo(target.c_str(), 0644) == 0);
    BOOST_CHECK_THROW(out.commit(), eomc::InputError);
    BOOST_TEST(entries(dir, ".tmp").empty());
    struct stat st {};
    BOOST_TEST((::lstat(target.c_str(), &st) == 0 && S_ISFIFO(st.st_mode)));
}

// ---- 4: the kernel cache -------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(sha256_meets_the_fips_180_4_examples) {
    using eomc::sha256_hex;
    // FIPS 180-4 examples (NIST CSRC "Examples with Intermediate Values", SHA-256).
    BOOST_TEST(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    BOOST_TEST(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
               "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    BOOST_TEST(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    BOOST_TEST(sha256_hex(std::string(1'000'000, 'a')) ==
               "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    // Fed in pieces that straddle the 64-byte blocks, the same digest.
    const std::string text(1000, 'x');
    eomc::Sha256 pieces;
    for (std::size_t at = 0, n = 1; at < text.size(); at += n, n = n * 3 % 97 + 1)
        pieces.update(text.data() + at, std::min(n, text.size() - at));
    std::string hex;
    for (auto b : pieces.digest()) hex += fmt::format("{:02x}", b);
    BOOST_TEST(hex == sha256_hex(text));
}

BOOST_AUTO_TEST_CASE(a_cache_directory_others_can_write_is_refused) {
    const fs::path dir = scratch("cache-0777");
    fs::create_directories(dir / "cache");
    fs::permissions(dir / "cache", fs::perms::all);  // 0777, as a shared /tmp/eomc-cache was
    const Result r = run("simulate " + dtb + " --cache-dir " + quoted(dir / "cache"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find((dir / "cache").string() + ": error: the kernel cache directory has mode 0777") !=
                   std::string::npos,
               r.err);
    BOOST_TEST(r.err.find("chmod go-w") != std::string::npos, r.err);
    BOOST_TEST(entries(dir / "cache").empty());
}

BOOST_AUTO_TEST_CASE(a_cache_directory_of_another_user_is_refused) {
    const fs::path dir = scratch("cache-foreign");
    fs::create_directories(dir / "cache");
    fs::permissions(dir / "cache", fs::perms::owner_all);
    if (::chown((dir / "cache").c_str(), 12345, 12345) != 0) {
        BOOST_TEST_MESSAGE("skipped: chown to another uid needs root (" << std::strerror(errno) << ")");
        return;
    }
    const Result r = run("simulate " + dtb + " --cache-dir " + quoted(dir / "cache"), dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("the kernel cache directory is owned by uid 12345, not by you") != std::string::npos, r.err);
    BOOST_TEST(r.err.find((dir / "cache").string()) != std::string::npos, r.err);
    // A link to a private directory of ours, but owned by another user, is refused as well.
    fs::create_directories(dir / "mine");
    fs::permissions(dir / "mine", fs::perms::owner_all);
    fs::create_symlink(dir / "mine", dir / "link");
    BOOST_REQUIRE(::lchown((dir / "link").c_str(), 12345, 12345) == 0);
    const Result l = run("simulate " + dtb + " --cache-dir " + quoted(dir / "link"), dir);
    BOOST_TEST(l.status == 2);
    BOOST_TEST(l.err.find("is a symbolic link owned by uid 12345") != std::string::npos, l.err);
}

BOOST_AUTO_TEST_CASE(a_new_cache_directory_is_private_and_without_home_it_is_per_user) {
    const fs::path dir = scratch("cache-new");
    const fs::path made = eomc::host::ensure_private_directory(dir / "a" / "cache");
    struct stat st {};
    BOOST_REQUIRE(::stat(made.c_str(), &st) == 0);
    BOOST_TEST((st.st_mode & 07777) == 0700u);
    // HOME and XDG_CACHE_HOME unset: <tmp>/eomc-cache-<euid>, never one directory for everyone.
    const std::string home = std::getenv("HOME") ? std::getenv("HOME") : "";
    const std::string xdg = std::getenv("XDG_CACHE_HOME") ? std::getenv("XDG_CACHE_HOME") : "";
    ::unsetenv("HOME");
    ::unsetenv("XDG_CACHE_HOME");
    const std::string fallback = eomc::host::default_cache_dir();
    if (!home.empty()) ::setenv("HOME", home.c_str(), 1);
    if (!xdg.empty()) ::setenv("XDG_CACHE_HOME", xdg.c_str(), 1);
    BOOST_TEST(fallback == (fs::temp_directory_path() / ("eomc-cache-" + std::to_string(::geteuid()))).string());
}

BOOST_AUTO_TEST_CASE(a_truncated_cached_kernel_is_rebuilt_not_loaded) {
    const fs::path dir = scratch("truncated");
    const std::string args = "simulate " + dtb + " --summary json --cache-dir " + quoted(dir / "cache");
    const Result first = run(args, dir);
    BOOST_REQUIRE(first.status == 0);
    const fs::path so = only_object(dir / "cache");
    // Cut after the ELF and program headers: dlopen maps it, and the first touch of a missing
    // page is a SIGBUS.
    fs::resize_file(so, 4096);
    const Result second = run(args, dir);
    BOOST_TEST(second.status == 0, second.err);
    BOOST_TEST(second.err.find("note: rebuilding the generated kernel cached as " + so.string()) != std::string::npos,
               second.err);
    BOOST_TEST(second.err.find("no eomc record") != std::string::npos, second.err);
    BOOST_TEST(final_q(second) == final_q(first));
    BOOST_TEST(eomc::host::verify_cache_entry(so, so.stem().string()) == "");
    // A byte changed in the middle: the hash tells.
    {
        std::fstream f(so, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(2000);
        f.put('\x5a');
    }
    const Result third = run(args, dir);
    BOOST_TEST(third.status == 0, third.err);
    BOOST_TEST(third.err.find("SHA-256 differs from its record") != std::string::npos, third.err);
    BOOST_TEST(final_q(third) == final_q(first));
}

BOOST_AUTO_TEST_CASE(a_kernel_of_another_scene_under_the_key_is_rebuilt_not_loaded) {
    const fs::path dir = scratch("swapped");
    const fs::path cache = dir / "cache", other = dir / "other";
    const std::string args = "simulate " + dtb + " --summary json --cache-dir " + quoted(cache);
    const Result first = run(args, dir);
    BOOST_REQUIRE(first.status == 0);
    BOOST_REQUIRE(run("simulate " + hoop + " --cache-dir " + quoted(other), dir).status == 0);
    const fs::path so = only_object(cache), foreign = only_object(other);

    // Copied with its record: the record names another key.
    fs::copy_file(foreign, so, fs::copy_options::overwrite_existing);
    Result r = run(args, dir);
    BOOST_TEST(r.status == 0, r.err);
    BOOST_TEST(r.err.find("its record is for another kernel or build") != std::string::npos, r.err);
    BOOST_TEST(final_q(r) == final_q(first));

    // With a record forged for our key (size and SHA-256 right): loaded, it says which kernel it
    // is, and is refused and rebuilt before anything runs on it.
    const std::string bytes = slurp(foreign);
    const std::string object = bytes.substr(0, bytes.rfind("\neomc-cache-record"));
    write_text(so, object + fmt::format("\neomc-cache-record 1 key={} size={:020} sha256={}\n", so.stem().string(),
                                        object.size(), eomc::sha256_hex(object)));
    BOOST_REQUIRE(eomc::host::verify_cache_entry(so, so.stem().string()) == "");
    r = run(args, dir);
    BOOST_TEST(r.status == 0, r.err);
    BOOST_TEST(r.err.find("it is the kernel 'BeadOnHoop") != std::string::npos, r.err);
    BOOST_TEST(final_q(r) == final_q(first));
    BOOST_TEST(r.out.find("\"cache_hit\": false") != std::string::npos, r.out);
}

// ---- 11: --set values ----------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(set_values_follow_one_decimal_grammar) {
    const fs::path dir = scratch("set-grammar");
    const std::string base = "simulate " + dtb + " --t-end 0.01 --cache-dir " + quoted(dir / "cache") + " --set ";
    for (const std::string bad : {"m=0x10", "m=0x1p4", "m=inf", "m=nan", "m=1e5x", "m=--1", "m=+-1", "m=", "m=1,5",
                                  "=1", "m=1 2"}) {
        const Result r = run(base + "'" + bad + "'", dir);
        BOOST_TEST(r.status == 2, bad << ": " << r.err);
        BOOST_TEST(r.err.find("--set " + bad + ": error: ") == 0u, bad << ": " << r.err);
    }
    for (const std::string range : {"m=1e400", "m=1e-400"}) {
        const Result r = run(base + range, dir);
        BOOST_TEST(r.status == 2, range);
        BOOST_TEST(r.err.find("is outside the range of a double") != std::string::npos, r.err);
    }
    // A subnormal number is read as a number, and refused for what it is: CLN, under GiNaC, has
    // no subnormal floats (it was "not a number" before).
    for (const std::string subnormal : {"Omega=1e-320", "Omega=4.9e-324"}) {
        const Result r = run(base + subnormal, dir);
        BOOST_TEST(r.status == 2, subnormal);
        BOOST_TEST(r.err.find("is a subnormal double") != std::string::npos, r.err);
    }
    // Blanks around the name and the value are dropped, on both sides alike; a '+' is a sign.
    for (const std::string good : {"m=1 ", "m= 1", " m = 1", "m=+2", "m=.5", "m=2."}) {
        const Result r = run(base + "'" + good + "'", dir);
        BOOST_TEST(r.status == 0, good << ": " << r.err);
    }
    // The other numeric options take the same grammar.
    const Result hex = run("simulate " + dtb + " --t-end 0x10 --cache-dir " + quoted(dir / "cache"), dir);
    BOOST_TEST(hex.status == 2, hex.err);
}

BOOST_AUTO_TEST_CASE(set_values_meet_the_scenes_own_checks) {
    const fs::path dir = scratch("set-checks");
    const std::string cache = " --cache-dir " + quoted(dir / "cache");
    for (const std::string bad : {"m=-1", "m=0"}) {
        const Result r = run("simulate " + dtb + cache + " --set " + bad, dir);
        BOOST_TEST(r.status == 2, bad);
        BOOST_TEST(r.err.find("--set " + bad + ": error: the mass of body 'ball' must be positive") == 0u, r.err);
        BOOST_TEST(r.err.find("disk_tube_ball.toml:") != std::string::npos, r.err);  // where the scene checks it
    }
    const Result run_cmd = run("run " + dtb + cache + " -d " + quoted(dir) + " --set m=-1", dir);
    BOOST_TEST(run_cmd.status == 2);
    BOOST_TEST(!fs::exists(dir / "disk_tube_ball.csv"));
    BOOST_TEST(!fs::exists(dir / "disk_tube_ball.hpp"));
    const Result mu = run("simulate " + std::string(EOMC_SOURCE_DIR "/scenes/leo_j2.toml") + cache + " --set mu=-1", dir);
    BOOST_TEST(mu.status == 2);
    BOOST_TEST(mu.err.find("mu must be positive") != std::string::npos, mu.err);
    BOOST_TEST(entries(dir / "cache", ".so").empty());  // refused before compiling
}

// ---- 6: bounded work -----------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(a_fixed_step_run_beyond_its_step_budget_is_refused_before_compiling) {
    const fs::path dir = scratch("step-budget");
    const std::string base = "simulate " + dtb + " --integrator rk4 --cache-dir " + quoted(dir / "cache");
    Result r = run(base + " --step 1e-12", dir);  // 10^13 steps
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--step: error: rk4 with step 1e-12") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("more than the budget of 100000000 (--max-steps)") != std::string::npos, r.err);
    r = run(base + " --t-end 1e300", dir);
    BOOST_TEST(r.status == 2);
    r = run(base + " --step 0.125 --t-end 1 --max-steps 7", dir);  // 8 steps
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("takes 8 steps, more than the budget of 7 ") != std::string::npos, r.err);
    BOOST_TEST(entries(dir / "cache", ".so").empty());
    r = run(base + " --step 0.125 --t-end 1 --max-steps 8", dir);
    BOOST_TEST(r.status == 0, r.err);
}

BOOST_AUTO_TEST_CASE(a_csv_beyond_its_row_limit_is_refused_or_not_written) {
    const fs::path dir = scratch("row-limit");
    const fs::path csv = dir / "out.csv";
    const std::string cache = " --cache-dir " + quoted(dir / "cache") + " --output " + quoted(csv);
    // Fixed step: known before the run.
    Result r = run("simulate " + dtb + " --integrator rk4 --step 1e-3 --t-end 10 --max-rows 1000" + cache, dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--output: error: the CSV " + csv.string() + " would hold 1e+04 rows") != std::string::npos,
               r.err);
    BOOST_TEST(!fs::exists(csv));
    // Adaptive: stopped when it gets there, nothing kept (--t-end 1e300 wrote 772 MB before).
    r = run("simulate " + dtb + " --t-end 1e300 --max-rows 1000" + cache, dir);
    BOOST_TEST(r.status == 1);
    BOOST_TEST(r.err.find("reached its limit of 1000 rows") != std::string::npos, r.err);
    BOOST_TEST(entries(dir, "out.csv").empty());
    // And the adaptive step budget is the user's to set.
    r = run("simulate " + dtb + " --t-end 1e300 --max-steps 50 --cache-dir " + quoted(dir / "cache"), dir);
    BOOST_TEST(r.status == 1);
    BOOST_TEST(r.err.find("step budget of 50 steps exhausted") != std::string::npos, r.err);
}

// ---- 9: signals ------------------------------------------------------------------------------

namespace {

// eomc with these arguments, started directly (no shell) with SIGINT and SIGTERM at their
// defaults and `env` added to the environment; its standard streams go to files in `dir`.
pid_t spawn_eomc(const std::vector<std::string>& arguments, const fs::path& dir, const std::vector<std::string>& env) {
    std::vector<std::string> argv{EOMC_EXECUTABLE};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    std::vector<std::string> environment = env;
    for (char** e = environ; *e; ++e) environment.emplace_back(*e);
    std::vector<char*> envp;
    for (auto& e : environment) envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, (dir / "stdout").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, (dir / "stderr").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t defaults;
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGINT);
    sigaddset(&defaults, SIGTERM);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
    pid_t pid = 0;
    const int rc = ::posix_spawn(&pid, args[0], &actions, &attributes, args.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    BOOST_REQUIRE(rc == 0);
    return pid;
}

// Polls until `ready()` or the time is up.
template <class F>
bool wait_for(F ready, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (ready()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return ready();
}

// Processes (zombies excepted: they run nothing) in process group `pgid`.
std::vector<pid_t> live_members(pid_t pgid) {
    std::vector<pid_t> out;
    for (const auto& e : fs::directory_iterator("/proc")) {
        const std::string name = e.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        const std::string stat = slurp(e.path() / "stat");
        const auto close = stat.rfind(')');
        if (close == std::string::npos) continue;
        char state = 0;
        int ppid = 0, pgrp = 0;
        if (std::sscanf(stat.c_str() + close + 1, " %c %d %d", &state, &ppid, &pgrp) == 3 && pgrp == pgid && state != 'Z')
            out.push_back(std::stoi(name));
    }
    return out;
}

void expect_killed_by(pid_t pid, int sig, const fs::path& dir) {
    int status = 0;
    BOOST_REQUIRE(::waitpid(pid, &status, 0) == pid);
    BOOST_TEST(WIFSIGNALED(status), "status " << status << ", stderr: " << slurp(dir / "stderr"));
    if (WIFSIGNALED(status)) BOOST_TEST(WTERMSIG(status) == sig);
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_signal_during_a_long_simulate_leaves_no_temporary) {
    for (const int sig : {SIGTERM, SIGINT}) {
        const fs::path dir = scratch(sig == SIGTERM ? "signal-simulate-term" : "signal-simulate-int");
        const fs::path csv = dir / "out.csv";
        BOOST_REQUIRE(run("simulate " + dtb + " --t-end 0.1 --cache-dir " + quoted(dir / "cache"), dir).status == 0);
        // 10^8 rk4 steps: minutes of work and gigabytes of CSV, were it not stopped.
        const pid_t pid = spawn_eomc({"simulate", dtb, "--integrator", "rk4", "--step", "1e-7", "--t-end", "10",
                                      "--max-rows", "200000000", "--max-steps", "200000000", "--cache-dir", (dir / "cache").string(), "--output",
                                      csv.string()},
                                     dir, {});
        const bool writing = wait_for(
            [&] {
                for (const auto& name : entries(dir, "out.csv.tmp."))
                    if (fs::file_size(dir / name) > (1u << 20)) return true;
                return false;
            },
            120);
        BOOST_TEST(writing, "the CSV temporary never grew past 1 MiB; stderr: " << slurp(dir / "stderr"));
        ::kill(pid, sig);
        expect_killed_by(pid, sig, dir);
        BOOST_TEST(entries(dir, "out.csv").empty());
    }
}

BOOST_AUTO_TEST_CASE(a_signal_during_the_compile_leaves_no_build_directory_no_partial_object_and_no_compiler) {
    const fs::path dir = scratch("signal-compile");
    const fs::path tmp = dir / "tmp", cache = dir / "cache", pid_file = dir / "compiler.pid";
    fs::create_directories(tmp);
    // A compiler that takes its time: records its pid (the leader of its process group) and
    // sleeps in a child of its own, as a driver runs cc1plus.
    const fs::path slow = dir / "slow-cxx.sh";
    write_text(slow, "#!/bin/sh\necho $$ > '" + pid_file.string() + "'\nsleep 300\n");
    fs::permissions(slow, fs::perms::owner_all);
    const pid_t pid = spawn_eomc({"simulate", dtb, "--cache-dir", cache.string()}, dir,
                                 {"EOMC_CXX=" + slow.string(), "TMPDIR=" + tmp.string()});
    BOOST_REQUIRE_MESSAGE(wait_for([&] { return fs::exists(pid_file) && fs::file_size(pid_file) > 0; }, 120),
                          "the compiler never started; stderr: " << slurp(dir / "stderr"));
    const pid_t compiler = std::stoi(slurp(pid_file));
    BOOST_TEST(wait_for([&] { return live_members(compiler).size() >= 2; }, 10));  // sh and its sleep
    BOOST_TEST(entries(tmp, "eomc-build-").size() == 1u);
    BOOST_TEST(entries(cache, ".so").size() == 1u);  // the partial object's name
    ::kill(pid, SIGTERM);
    expect_killed_by(pid, SIGTERM, dir);
    BOOST_TEST(entries(tmp).empty(), "left in TMPDIR: " << entries(tmp).size());
    BOOST_TEST(entries(cache).empty(), "left in the cache: " << entries(cache).size());
    BOOST_TEST(wait_for([&] { return live_members(compiler).empty(); }, 10),
               live_members(compiler).size() << " compiler processes survive");
}

BOOST_AUTO_TEST_CASE(a_signal_while_an_output_is_written_removes_its_temporary) {
    const fs::path dir = scratch("signal-output");
    const fs::path target = dir / "derivation.txt";
    int ready[2];
    BOOST_REQUIRE(::pipe(ready) == 0);
    const pid_t child = ::fork();
    BOOST_REQUIRE(child >= 0);
    if (child == 0) {
        // As `derive -o` between creating its temporary and renaming it.
        eomc::install_signal_cleanup();
        eomc::AtomicOutput out(target);
        out.write("half of it\n");
        (void)!::write(ready[1], "x", 1);
        ::pause();
        ::_exit(0);
    }
    char c = 0;
    BOOST_REQUIRE(::read(ready[0], &c, 1) == 1);
    BOOST_TEST(entries(dir, ".tmp.").size() == 1u);
    ::kill(child, SIGTERM);
    expect_killed_by(child, SIGTERM, dir);
    BOOST_TEST(entries(dir).empty());
    ::close(ready[0]);
    ::close(ready[1]);
}
