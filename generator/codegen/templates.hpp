// The kernel skeleton (templates/kernel.hpp.in) and the benchmark driver
// (templates/bench_driver.cpp), compiled into the generator so that the output never depends
// on where eomc is run from.
#pragma once

#include <string>

namespace eomc::codegen {
const std::string& kernel_template();
const std::string& bench_driver_template();
}
