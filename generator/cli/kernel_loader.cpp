#include "cli/kernel_loader.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "eomc/runtime/version.hpp"

extern char** environ;

namespace eomc::cli {

namespace fs = std::filesystem;

namespace {

// Bumped whenever the C interface below changes; the loader refuses a library that reports
// another value (a cache written by an older eomc).
constexpr int adapter_abi = 2;

// The adapter: C functions over double, so that the host needs no knowledge of the kernel's
// C++ types. Parameters travel by position in parameter_names order, never by member name
// (a parameter named like a C++ keyword becomes a member with a trailing underscore).
constexpr const char* adapter_template = R"(// eomc simulate: C interface over one generated kernel.
#include "kernel.hpp"

#include <array>
#include <bit>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace {
using K = eomc::models::@STRUCT@;
using P = K::Parameters;
constexpr std::size_t n_par = K::n_parameters;

// Parameters must be exactly n_parameters doubles in parameter_names order: aggregate
// initialisation then fills them by position, and their bytes are an array of doubles.
static_assert(std::is_aggregate_v<P> && std::is_trivially_copyable_v<P> && std::is_standard_layout_v<P>,
              "eomc simulate: Parameters must be a plain aggregate of doubles");
static_assert(n_par == 0 || sizeof(P) == n_par * sizeof(double),
              "eomc simulate: Parameters must hold exactly n_parameters doubles");

template <std::size_t... I>
P* create(const double* v, std::index_sequence<I...>) {
    (void)v;
    return new P{v[I]...};
}
}  // namespace

#define EOMC_EXPORT extern "C" __attribute__((visibility("default")))

EOMC_EXPORT int eomc_adapter_abi() { return @ABI@; }
EOMC_EXPORT const char* eomc_scene_name() { return K::scene_name; }
EOMC_EXPORT int eomc_n_state() { return K::n_state; }
EOMC_EXPORT int eomc_n_parameters() { return K::n_parameters; }
EOMC_EXPORT int eomc_n_invariants() { return K::n_invariants; }
EOMC_EXPORT int eomc_n_outputs() { return K::n_outputs; }
EOMC_EXPORT const char* const* eomc_state_names() { return K::state_names.data(); }
EOMC_EXPORT const char* const* eomc_parameter_names() { return K::parameter_names.data(); }
EOMC_EXPORT const char* const* eomc_invariant_names() { return K::invariant_names.data(); }
EOMC_EXPORT const char* const* eomc_output_names() { return K::output_names.data(); }
EOMC_EXPORT const double* eomc_initial_state() { return K::initial_state.data(); }

EOMC_EXPORT void eomc_parameter_defaults(double* out) {
    if constexpr (n_par > 0) {
        const auto values = std::bit_cast<std::array<double, n_par>>(P{});
        for (std::size_t i = 0; i < n_par; ++i) out[i] = values[i];
    } else {
        (void)out;
    }
}
EOMC_EXPORT void* eomc_create_parameters(const double* values) {
    return create(values, std::make_index_sequence<n_par>{});
}
EOMC_EXPORT void eomc_destroy_parameters(void* p) { delete static_cast<P*>(p); }

EOMC_EXPORT void eomc_rhs(double t, const double* x, double* dxdt, const void* p) {
    K::rhs<double>(t, x, dxdt, *static_cast<const P*>(p));
}
EOMC_EXPORT void eomc_invariants(double t, const double* x, double* out, const void* p) {
    K::invariants<double>(t, x, out, *static_cast<const P*>(p));
}
EOMC_EXPORT void eomc_outputs(double t, const double* x, double* out, const void* p) {
    K::outputs<double>(t, x, out, *static_cast<const P*>(p));
}
)";

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
}

bool is_identifier(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

// The compiler can be overridden at run time (an installed eomc on a machine whose compiler
// lives elsewhere); it is part of the cache key either way.
std::string compiler() {
    if (const char* cxx = std::getenv("EOMC_CXX"); cxx && *cxx) return cxx;
    return EOMC_KERNEL_CXX;
}

// No -ffast-math and no FMA contraction: a simulation gives the same numbers wherever the
// kernel is compiled (DESIGN, habit 11). Hidden visibility keeps the kernel's template
// instantiations out of the dynamic symbol table; only the adapter's C functions are exported.
std::vector<std::string> compile_flags() {
    return {"-std=c++20", "-O2",       "-fPIC", "-shared", "-ffp-contract=off", "-fvisibility=hidden",
            "-I",         EOMC_KERNEL_RUNTIME_INCLUDE,      "-I",      EOMC_KERNEL_EIGEN_INCLUDE};
}

// FNV-1a, 64 bits: a fixed function (std::hash may differ between runs and builds), good
// enough for a cache whose entries are all produced by this program.
std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h = 0xcbf29ce484222325ull) {
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

// A fresh private directory, removed with everything in it when the object goes away.
class TempDir {
public:
    TempDir() {
        std::string tmpl = (fs::temp_directory_path() / "eomc-kernel-XXXXXX").string();
        if (!::mkdtemp(tmpl.data()))
            throw std::runtime_error(fmt::format("cannot create a temporary directory {}: {}", tmpl, std::strerror(errno)));
        path_ = tmpl;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

// Runs argv (searched on PATH when argv[0] has no slash) with stdout and stderr going to `log`;
// returns the wait status.
int run_process(const std::vector<std::string>& argv, const fs::path& log) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error(fmt::format("cannot run the C++ compiler '{}': {}", argv[0], std::strerror(rc)));
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error(fmt::format("waiting for the C++ compiler: {}", std::strerror(errno)));
    return status;
}

std::string describe_status(int status) {
    if (WIFEXITED(status)) return fmt::format("exited with status {}", WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return fmt::format("was killed by signal {}", WTERMSIG(status));
    return fmt::format("failed (wait status {})", status);
}

// Compiles header + adapter into `target`. The output goes to a unique temporary name in the
// cache directory and is renamed into place only when complete: rename() is atomic within a
// directory, so a concurrent run sees either no library or a whole one, and a crash leaves at
// most a stray hidden temporary, never a truncated <key>.so. Two runs racing on the same key
// both compile and the last rename wins; the contents are the same.
void compile_into(const fs::path& target, const std::string& header_text, const std::string& adapter) {
    TempDir dir;
    write_file(dir.path() / "kernel.hpp", header_text);
    write_file(dir.path() / "adapter.cpp", adapter);

    std::string tmpl = (target.parent_path() / ("." + target.filename().string() + ".XXXXXX")).string();
    const int fd = ::mkstemp(tmpl.data());
    if (fd < 0) throw std::runtime_error(fmt::format("cannot create {}: {}", tmpl, std::strerror(errno)));
    ::close(fd);
    const fs::path partial = tmpl;

    std::vector<std::string> argv{compiler()};
    for (auto& f : compile_flags()) argv.push_back(std::move(f));
    argv.insert(argv.end(), {"-o", partial.string(), (dir.path() / "adapter.cpp").string()});
    const fs::path log = dir.path() / "compiler.log";
    int status = 0;
    try {
        status = run_process(argv, log);
    } catch (...) {
        std::error_code ignored;
        fs::remove(partial, ignored);
        throw;
    }
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        std::error_code ec;
        fs::remove(partial, ec);
        std::string output = read_file(log);
        constexpr std::size_t max_output = 64 * 1024;  // template errors can run to megabytes
        if (output.size() > max_output) output = output.substr(0, max_output) + "\n[... compiler output truncated]\n";
        throw std::runtime_error(fmt::format("compiling the generated kernel failed: {} {}:\n{}", argv[0],
                                             describe_status(status), output));
    }
    std::error_code ec;
    fs::rename(partial, target, ec);
    if (ec) {
        fs::remove(partial, ec);
        throw std::runtime_error(fmt::format("cannot move the compiled kernel to {}: {}", target.string(), ec.message()));
    }
}

template <class F>
F symbol(void* handle, const char* name, const std::string& path) {
    void* p = ::dlsym(handle, name);
    if (!p) throw std::runtime_error(fmt::format("{}: no symbol {} (not an eomc kernel library)", path, name));
    return reinterpret_cast<F>(p);
}

std::vector<std::string> names(const char* const* array, int n) {
    return std::vector<std::string>(array, array + n);
}

}  // namespace

std::string default_cache_dir() {
    // XDG Base Directory: $XDG_CACHE_HOME counts only when set to an absolute path.
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/') return (fs::path(xdg) / "eomc").string();
    if (const char* home = std::getenv("HOME"); home && *home) return (fs::path(home) / ".cache" / "eomc").string();
    return (fs::temp_directory_path() / "eomc-cache").string();
}

std::string adapter_source(const std::string& struct_name) {
    if (!is_identifier(struct_name))
        throw std::runtime_error(fmt::format("'{}' is not a C++ identifier (expected the kernel's struct name)", struct_name));
    return replace_all(replace_all(adapter_template, "@STRUCT@", struct_name), "@ABI@", std::to_string(adapter_abi));
}

std::string cache_key(const std::string& header_text, const std::string& struct_name) {
    // Everything that determines the bytes of the library, each part NUL-terminated so that
    // moving text from one part to the next changes the key.
    std::string key = "eomc kernel cache 1";
    key += '\0';
    key += compiler();
    key += '\0';
    for (const auto& f : compile_flags()) key += f + '\0';
    key += "runtime " + std::to_string(EOMC_RUNTIME_VERSION) + '\0';
    key += adapter_source(struct_name) + '\0';
    key += header_text;
    return fmt::format("{:016x}", fnv1a(key));
}

KernelLibrary KernelLibrary::load(const std::string& header_text, const std::string& struct_name,
                                  const std::string& cache_dir) {
    const auto start = std::chrono::steady_clock::now();
    const fs::path dir = cache_dir.empty() ? default_cache_dir() : cache_dir;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error(fmt::format("cannot create the kernel cache {}: {}", dir.string(), ec.message()));
    const std::string adapter = adapter_source(struct_name);
    const fs::path path = dir / (cache_key(header_text, struct_name) + ".so");

    KernelLibrary lib;
    lib.path_ = path.string();
    lib.handle_ = fs::exists(path) ? ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL) : nullptr;
    lib.cache_hit_ = lib.handle_ != nullptr;
    if (!lib.handle_) {
        // Missing, or present but unloadable (damaged by hand, a foreign file): build it afresh.
        compile_into(path, header_text, adapter);
        lib.handle_ = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!lib.handle_) throw std::runtime_error(fmt::format("cannot load the compiled kernel: {}", ::dlerror()));
    }

    void* h = lib.handle_;
    const std::string& p = lib.path_;
    const int abi = symbol<int (*)()>(h, "eomc_adapter_abi", p)();
    if (abi != adapter_abi)
        throw std::runtime_error(fmt::format("{}: adapter interface {} (expected {}); delete it to rebuild", p, abi, adapter_abi));
    lib.scene_name_ = symbol<const char* (*)()>(h, "eomc_scene_name", p)();
    const int n_state = symbol<int (*)()>(h, "eomc_n_state", p)();
    const int n_par = symbol<int (*)()>(h, "eomc_n_parameters", p)();
    const int n_inv = symbol<int (*)()>(h, "eomc_n_invariants", p)();
    const int n_out = symbol<int (*)()>(h, "eomc_n_outputs", p)();
    using Names = const char* const* (*)();
    lib.state_names_ = names(symbol<Names>(h, "eomc_state_names", p)(), n_state);
    lib.parameter_names_ = names(symbol<Names>(h, "eomc_parameter_names", p)(), n_par);
    lib.invariant_names_ = names(symbol<Names>(h, "eomc_invariant_names", p)(), n_inv);
    lib.output_names_ = names(symbol<Names>(h, "eomc_output_names", p)(), n_out);
    const double* x0 = symbol<const double* (*)()>(h, "eomc_initial_state", p)();
    lib.initial_state_.assign(x0, x0 + n_state);
    lib.parameter_defaults_.assign(static_cast<std::size_t>(n_par), 0.0);
    symbol<void (*)(double*)>(h, "eomc_parameter_defaults", p)(lib.parameter_defaults_.data());
    lib.create_parameters_ = symbol<void* (*)(const double*)>(h, "eomc_create_parameters", p);
    lib.destroy_parameters_ = symbol<void (*)(void*)>(h, "eomc_destroy_parameters", p);
    lib.rhs_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_rhs", p);
    lib.invariants_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_invariants", p);
    lib.outputs_ = symbol<void (*)(double, const double*, double*, const void*)>(h, "eomc_outputs", p);
    lib.seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return lib;
}

KernelLibrary::Parameters KernelLibrary::make_parameters(const std::vector<double>& values) const {
    if (values.size() != parameter_names_.size())
        throw std::invalid_argument(fmt::format("make_parameters: {} values for {} parameters", values.size(),
                                                parameter_names_.size()));
    return Parameters(create_parameters_(values.data()), ParameterDeleter{destroy_parameters_});
}

KernelLibrary::KernelLibrary(KernelLibrary&& other) noexcept { *this = std::move(other); }

KernelLibrary& KernelLibrary::operator=(KernelLibrary&& other) noexcept {
    if (this != &other) {
        close();
        handle_ = std::exchange(other.handle_, nullptr);
        path_ = std::move(other.path_);
        cache_hit_ = other.cache_hit_;
        seconds_ = other.seconds_;
        scene_name_ = std::move(other.scene_name_);
        state_names_ = std::move(other.state_names_);
        parameter_names_ = std::move(other.parameter_names_);
        invariant_names_ = std::move(other.invariant_names_);
        output_names_ = std::move(other.output_names_);
        initial_state_ = std::move(other.initial_state_);
        parameter_defaults_ = std::move(other.parameter_defaults_);
        create_parameters_ = other.create_parameters_;
        destroy_parameters_ = other.destroy_parameters_;
        rhs_ = other.rhs_;
        invariants_ = other.invariants_;
        outputs_ = other.outputs_;
    }
    return *this;
}

KernelLibrary::~KernelLibrary() { close(); }

void KernelLibrary::close() {
    if (handle_) ::dlclose(handle_);
    handle_ = nullptr;
}

}  // namespace eomc::cli
