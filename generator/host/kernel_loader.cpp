#include "host/kernel_loader.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <fstream>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "codegen/templates.hpp"
#include "support/identifier.hpp"
#include "support/sha256.hpp"

namespace eomc::host {

namespace c = runtime::kernel_c;

namespace {

// "<struct> <SHA-256 of the header>": the adapter exports it, and the loader checks it.
std::string kernel_identity(const std::string& struct_name, const std::string& header_text) {
    return struct_name + " " + sha256_hex(header_text);
}

// Why the library at `handle` is not the kernel expected, "" when it is. Checked before anything
// else is read from it, its interface first: a cache entry written by another eomc, or another
// kernel's object under the key, is rebuilt or refused, never used.
std::string mismatch(void* handle, const std::string& identity) {
    const auto abi = reinterpret_cast<int (*)()>(::dlsym(handle, "eomc_adapter_abi"));
    const auto id = reinterpret_cast<const char* (*)()>(::dlsym(handle, "eomc_kernel_identity"));
    const auto vtable = reinterpret_cast<const c::VTable* (*)()>(::dlsym(handle, "eomc_kernel_vtable"));
    if (!abi || !id) return "it is not an eomc kernel library";
    if (abi() != c::abi) return fmt::format("it has adapter interface {}, not {}", abi(), c::abi);
    if (!vtable) return "it is not an eomc kernel library";
    if (id() != identity) return fmt::format("it is the kernel '{}', not '{}'", id(), identity);
    if (std::strcmp(vtable()->blocks, c::block_table) != 0)
        return "it was built with another table of kernel blocks (eomc/runtime/kernel/blocks.def)";
    return "";
}

// n entries of a table the library holds (none when n is not positive).
std::vector<std::string> copy_names(const char* const* names, int n) {
    return n > 0 ? std::vector<std::string>(names, names + n) : std::vector<std::string>();
}
template <class T, int width>
ColumnOf<T, width> copy_column(const T* values, int rows) {
    ColumnOf<T, width> column;
    for (int row = 0; row < rows; ++row) {
        if constexpr (width == 1) {
            column.push_back(values[row]);
        } else {
            std::array<T, width> entry;
            std::copy(values + row * width, values + (row + 1) * width, entry.begin());
            column.push_back(entry);
        }
    }
    return column;
}

// The CPU as /proc/cpuinfo describes its first processor (vendor, family, model, name, flags,
// cache size): what -march=native resolves to, with the compiler (already in the key), so that a
// cache shared by unlike machines (a home directory on NFS) keeps one object per instruction set.
// Read once per process; no compiler run, so a cache hit costs nothing more.
const std::string& host_cpu() {
    static const std::string described = [] {
        static const std::set<std::string> wanted{"vendor_id",  "cpu family", "model",    "model name", "flags",
                                                  "cache size", "Features",   "CPU part", "isa",        "uarch"};
        std::ifstream in("/proc/cpuinfo");
        std::string line, text;
        while (std::getline(in, line) && !line.empty()) {  // the first processor's block
            const std::size_t colon = line.find(':');
            const std::size_t end = line.find_last_not_of(" \t", colon == std::string::npos ? 0 : colon - 1);
            if (colon != std::string::npos && colon > 0 && end != std::string::npos && wanted.count(line.substr(0, end + 1)))
                text += line + '\n';
        }
        return text.empty() ? std::string("unknown") : text;
    }();
    return described;
}

// $EOMC_PORTABLE (non-empty, not "0") asks for portable code, e.g. for a cache shared by unlike machines.
bool portable() {
    const char* env = std::getenv("EOMC_PORTABLE");
    return env && *env && std::string(env) != "0";
}

}  // namespace

// The adapter and the kernel, built into a shared object with only the adapter's C functions
// exported (hidden visibility keeps the kernel's template instantiations out of the dynamic
// symbol table). The adapter is told its kernel on the command line, so its text is the same for
// every kernel; the flags and both files are in the cache key.
CompileRequest kernel_request(const std::string& header_text, const std::string& struct_name, bool batch) {
    if (!is_identifier(struct_name))
        throw std::runtime_error(fmt::format("'{}' is not a C++ identifier (expected the kernel's struct name)", struct_name));
    CompileRequest r;
    r.files = {{"adapter.cpp", codegen::kernel_adapter_template()}, {"kernel.hpp", header_text}};
    r.flags = {"-fPIC",
               "-shared",
               "-fvisibility=hidden",
               "-DEOMC_KERNEL_HEADER=\"kernel.hpp\"",
               "-DEOMC_KERNEL_STRUCT=" + struct_name,
               "-DEOMC_KERNEL_IDENTITY=\"" + kernel_identity(struct_name, header_text) + "\""};
    // The SIMD batch only for --batch: <experimental/simd> is most of the adapter's compile.
    if (batch) r.flags.push_back("-DEOMC_KERNEL_BATCH");
    // For this machine's instructions where the compiler accepts it (a compiler that refuses it
    // builds the portable object). No FMA contraction still (common flags): the instructions
    // change, not the roundings.
    if (!portable()) {
        r.optional_flags.push_back("-march=native");
        r.key_notes.push_back("cpu " + host_cpu());
    }
    r.suffix = ".so";
    r.what = "the generated kernel";
    return r;
}

std::string cache_key(const std::string& header_text, const std::string& struct_name, bool batch) {
    return cache_key(kernel_request(header_text, struct_name, batch));
}

KernelLibrary KernelLibrary::load(const std::string& header_text, const std::string& struct_name,
                                  const std::string& cache_dir, bool batch) {
    const auto start = std::chrono::steady_clock::now();
    const CompileRequest request = kernel_request(header_text, struct_name, batch);
    // Verified against its record before dlopen (which runs the object's initialisers and maps
    // its pages: a truncated file would SIGBUS later): a bad entry is rebuilt, never loaded.
    const Artifact artifact = find_or_compile(request, cache_dir);
    KernelLibrary lib;
    lib.path_ = artifact.path;
    lib.cache_hit_ = artifact.cache_hit;
    lib.open(request, kernel_identity(struct_name, header_text));
    lib.read_kernel();
    lib.read_blocks();
    lib.seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return lib;
}

// Once loaded, the kernel must say it is this one: the same struct, from the same header, through
// the same interface. A cached library that does not is rebuilt once; a fresh one is refused.
void KernelLibrary::open(const CompileRequest& request, const std::string& identity) {
    std::string wrong = open_checked(identity);
    if (!wrong.empty() && cache_hit_) {
        handle_.reset();
        std::cerr << fmt::format("eomc: note: rebuilding {} cached as {}: {}\n", request.what, path_, wrong);
        compile(request, path_);
        cache_hit_ = false;
        wrong = open_checked(identity);
    }
    if (!wrong.empty()) throw std::runtime_error(fmt::format("cannot load the compiled kernel {}: {}", path_, wrong));
    vt_ = *reinterpret_cast<const c::VTable* (*)()>(::dlsym(handle_.get(), "eomc_kernel_vtable"))();
}

std::string KernelLibrary::open_checked(const std::string& identity) {
    handle_.reset(::dlopen(path_.c_str(), RTLD_NOW | RTLD_LOCAL));
    return handle_ ? mismatch(handle_.get(), identity) : std::string(::dlerror());
}

void KernelLibrary::read_kernel() {
    scene_name_ = vt_.scene_name;
    state_names_ = copy_names(vt_.state_names, vt_.n_state);
    parameter_names_ = copy_names(vt_.parameter_names, vt_.n_parameters);
    invariant_names_ = copy_names(vt_.invariant_names, vt_.n_invariants);
    output_names_ = copy_names(vt_.output_names, vt_.n_outputs);
    initial_state_ = copy_column<double, 1>(vt_.initial_state, vt_.n_state);
    parameter_defaults_ = copy_column<double, 1>(vt_.parameter_defaults, vt_.n_parameters);
}

void KernelLibrary::read_blocks() {
#define EOMC_KERNEL_ROWS(concept, count, names) names##_ = copy_names(vt_.names, vt_.count);
#define EOMC_KERNEL_COLUMN(concept, count, column, type, width) \
    column##_ = copy_column<type, width>(vt_.column, vt_.count);
#include "eomc/runtime/kernel/blocks.def"
}

KernelLibrary::Parameters KernelLibrary::make_parameters(const std::vector<double>& values) const {
    if (values.size() != parameter_names_.size())
        throw std::invalid_argument(fmt::format("make_parameters: {} values for {} parameters", values.size(),
                                                parameter_names_.size()));
    return Parameters(vt_.create_parameters(values.data()), ParameterDeleter{vt_.destroy_parameters});
}

KernelLibrary::Parameters KernelLibrary::make_batch_parameters(const std::vector<double>& values) const {
    const std::size_t lanes = static_cast<std::size_t>(vt_.batch_width);
    if (lanes == 0)
        throw std::logic_error(fmt::format("make_batch_parameters: the kernel {} is not batchable, or was loaded without "
                                           "its batch (KernelLibrary::load's `batch`)", scene_name_));
    if (values.size() != parameter_names_.size() * lanes)
        throw std::invalid_argument(fmt::format("make_batch_parameters: {} values for {} parameters × {} lanes",
                                                values.size(), parameter_names_.size(), lanes));
    return Parameters(vt_.create_batch_parameters(values.data()), ParameterDeleter{vt_.destroy_batch_parameters});
}

void KernelLibrary::Unload::operator()(void* handle) const { ::dlclose(handle); }

}  // namespace eomc::host
