// How `simulate` compiles a kernel (host/kernel_loader.cpp): the plain adapter has no SIMD batch,
// which --batch asks for as a cache entry of its own; the kernel is compiled for the host
// (-march=native, part of the cache key; EOMC_PORTABLE=1 for portable code), and what the host's
// instructions compute agrees with the derivation within the running first-order rounding bound
// of tests/support/rounding_bound.hpp (each build within twice it, so the two builds within four
// times it of each other). The common flags keep -ffp-contract=off, but the bound would hold for a
// contracted build too: an FMA rounds once where a product and a sum round twice.
#define BOOST_TEST_MODULE kernel_targets
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "host/kernel_loader.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/first_order.hpp"
#include "rounding_bound.hpp"
#include "scenes.hpp"

using eomc::host::KernelLibrary;

namespace {

std::string generated(const std::string& name) {
    std::ifstream in(std::string(EOMC_SOURCE_DIR) + "/generated/" + name + ".hpp");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

bool has_flag(const eomc::host::CompileRequest& r, const std::string& flag) {
    return std::find(r.flags.begin(), r.flags.end(), flag) != r.flags.end();
}
bool native_target(const eomc::host::CompileRequest& r) {
    return std::find(r.optional_flags.begin(), r.optional_flags.end(), "-march=native") != r.optional_flags.end();
}

const eomc::host::TempDir& cache() {
    static const eomc::host::TempDir dir("eomc-kernel-targets-");
    return dir;
}

// Both libraries' forcing and explicit rates against the scene's first-order form at random states
// near its initial one.
void check_against_derivation(const std::string& scene, const std::string& struct_name) {
    const std::string header = generated(scene);
    const KernelLibrary native = KernelLibrary::load(header, struct_name, cache().path().string());
    ::setenv("EOMC_PORTABLE", "1", 1);
    const auto portable_request = eomc::host::kernel_request(header, struct_name);
    const KernelLibrary portable = KernelLibrary::load(header, struct_name, cache().path().string());
    ::unsetenv("EOMC_PORTABLE");
    const auto native_request = eomc::host::kernel_request(header, struct_name);
    BOOST_TEST(native_target(native_request));
    BOOST_TEST(!native_target(portable_request));
    BOOST_TEST(eomc::host::cache_key(native_request) != eomc::host::cache_key(portable_request));
    BOOST_TEST(native.library_path() != portable.library_path());

    GiNaC::Digits = 40;
    const auto model = test_support::bundled_model(scene);
    const auto form = eomc::mechanics::first_order_form(model, eomc::mechanics::derive(model));
    const std::size_t n = form.state.size();
    std::vector<GiNaC::ex> expected(form.forcing);
    for (const auto& [index, rate] : form.explicit_rates) expected.push_back(rate);
    const GiNaC::numeric largest = test_support::largest_power(expected);
    const auto values = native.parameter_defaults();
    const auto pn = native.make_parameters(values), pp = portable.make_parameters(values);

    std::mt19937_64 random(20261128);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    double worst = 0;
    for (int point = 0; point < 8; ++point) {
        std::vector<double> x(n);
        GiNaC::exmap inputs;
        inputs[model.t] = test_support::exact(0.25);
        for (std::size_t i = 0; i < n; ++i) {
            x[i] = native.initial_state()[i] * (1 + 0.1 * unit(random)) + 0.01 * unit(random);
            inputs[form.state[i].symbol] = test_support::exact(x[i]);
        }
        for (std::size_t j = 0; j < values.size(); ++j)
            for (const auto& parameter : model.parameters)
                if (parameter.name == native.parameter_names()[j]) inputs[parameter.symbol] = test_support::exact(values[j]);
        const auto outputs = [&](const KernelLibrary& lib, const KernelLibrary::Parameters& p) {
            std::vector<double> f(std::size_t(lib.n_velocities())), rates(n);
            lib.forcing(0.25, x.data(), f.data(), p);
            lib.rhs(0.25, x.data(), rates.data(), p);
            for (const auto& entry : form.explicit_rates) f.push_back(rates[entry.first]);
            return f;
        };
        const std::vector<double> a = outputs(native, pn), b = outputs(portable, pp);
        test_support::RoundingBound bound(inputs, largest);
        for (std::size_t k = 0; k < expected.size(); ++k) {
            const test_support::Bounded r = bound(expected[k]);
            const double reference = r.value.to_double(), limit = 2 * r.error.to_double() + 1e-300;
            BOOST_TEST(std::abs(a[k] - reference) <= limit, scene << " native [" << k << "] " << a[k] << " vs " << reference);
            BOOST_TEST(std::abs(b[k] - reference) <= limit, scene << " portable [" << k << "] " << b[k] << " vs " << reference);
            BOOST_TEST(std::abs(a[k] - b[k]) <= 2 * limit, scene << " [" << k << "] native " << a[k] << ", portable " << b[k]);
            worst = std::max(worst, std::abs(a[k] - b[k]) / limit);
        }
    }
    BOOST_TEST_MESSAGE(scene << ": largest |native − portable| / bound " << worst);
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_batch_is_compiled_only_when_asked_for) {
    const std::string header = generated("leo_j2");
    const auto plain = eomc::host::kernel_request(header, "LeoJ2"), batch = eomc::host::kernel_request(header, "LeoJ2", true);
    BOOST_TEST(!has_flag(plain, "-DEOMC_KERNEL_BATCH"));
    BOOST_TEST(has_flag(batch, "-DEOMC_KERNEL_BATCH"));
    BOOST_TEST(eomc::host::cache_key(plain) != eomc::host::cache_key(batch));
    const KernelLibrary a = KernelLibrary::load(header, "LeoJ2", cache().path().string());
    const KernelLibrary b = KernelLibrary::load(header, "LeoJ2", cache().path().string(), true);
    BOOST_TEST(a.batch_width() == 0);
    BOOST_TEST(b.batch_width() == 4);
    BOOST_CHECK_THROW(a.make_batch_parameters(std::vector<double>(12, 1.0)), std::logic_error);
    // The same kernel either way.
    const auto pa = a.make_parameters(a.parameter_defaults()), pb = b.make_parameters(b.parameter_defaults());
    std::vector<double> ra(6), rb(6);
    a.rhs(0.0, a.initial_state().data(), ra.data(), pa);
    b.rhs(0.0, b.initial_state().data(), rb.data(), pb);
    BOOST_TEST(ra == rb, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(host_and_portable_builds_agree_with_the_derivation) {
    check_against_derivation("leo_j2", "LeoJ2");
    check_against_derivation("pleiades", "Pleiades");
}

// A compiler that refuses -march=native (as GCC does where the flag is -mcpu=native) still builds
// the kernel: the compile is retried once without it, silently.
BOOST_AUTO_TEST_CASE(a_compiler_that_refuses_the_host_target_builds_the_portable_kernel) {
    const std::string header = generated("leo_j2");
    const std::filesystem::path wrapper = cache().path() / "refuses-march-native.sh";
    {
        std::ofstream out(wrapper);
        out << "#!/bin/sh\nfor a in \"$@\"; do [ \"$a\" = -march=native ] && { echo \"error: -march=native\" >&2; exit 1; }; done\n"
            << "exec '" << eomc::host::compiler() << "' \"$@\"\n";
    }
    std::filesystem::permissions(wrapper, std::filesystem::perms::owner_all);
    ::setenv("EOMC_CXX", wrapper.c_str(), 1);
    const KernelLibrary lib = KernelLibrary::load(header, "LeoJ2", (cache().path() / "refusing").string());
    ::unsetenv("EOMC_CXX");
    const KernelLibrary native = KernelLibrary::load(header, "LeoJ2", cache().path().string());
    BOOST_TEST(!lib.cache_hit());
    const auto p = lib.make_parameters(lib.parameter_defaults()), pn = native.make_parameters(native.parameter_defaults());
    std::vector<double> a(6), b(6);
    lib.rhs(0.0, lib.initial_state().data(), a.data(), p);
    native.rhs(0.0, native.initial_state().data(), b.data(), pn);
    BOOST_TEST(a == b, boost::test_tools::per_element());  // no contraction either way
}
