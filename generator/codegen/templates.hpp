// The kernel skeleton (templates/kernel.hpp.in), the benchmark driver (templates/bench_driver.cpp)
// and the kernel's C adapter (templates/kernel_adapter.cpp), compiled into the generator so that
// the output never depends on where eomc is run from.
#pragma once

#include <string>

namespace eomc::codegen {
const std::string& kernel_template();
const std::string& bench_driver_template();
const std::string& kernel_adapter_template();
}
