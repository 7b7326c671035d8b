// Not compiled: preprocessed at build time (cmake/KernelMacros.cmake) for the names of the
// macros that code compiled with a kernel sees. Every header a kernel, the simulate adapter
// (templates/kernel_adapter.cpp) or the benchmark driver (templates/bench_driver.cpp) includes.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <dlfcn.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Dense>

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/integrate/integrate_n_steps.hpp>
#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_mclachlan.hpp>

#if __has_include(<quadmath.h>)  // GCC's libquadmath: the float128 references need it
#include <quadmath.h>

#include <eomc/runtime/float128.hpp>
#endif
#include <eomc/runtime/runtime.hpp>
