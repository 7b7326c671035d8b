// The pipeline every command runs, as one call: scene --parse--> Scene --build--> Model
// --derive--> Equations (--> Hamilton's equations) --lower--> KernelIR --emit--> header.
#pragma once

#include <chrono>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "codegen/kernel_ir.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::host {

// Seconds per pipeline stage, for `eomc generate --timings` and the benchmarks.
class StageClock {
public:
    void lap(const char* stage);
    void add(const char* stage, double seconds) { stages_.emplace_back(stage, seconds); }
    void print(std::ostream& out) const;

private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    std::vector<std::pair<const char*, double>> stages_;
};

struct Pipeline {
    model::Model model;
    mechanics::Equations equations;
    std::optional<mechanics::CanonicalEquations> canonical;  // the Hamiltonian formulation, when asked for
    bool variational = false;                                // emit variational_rhs too (--variational)
};

struct FrontEndOptions {
    bool hamiltonian = false;        // --hamiltonian (or the scene's [formulation] kind)
    std::string orbit_formulation;   // --orbit-formulation; "" = the scene's own
    std::string rigid_formulation;   // --rigid-formulation; "" = the scene's own
    bool variational = false;        // --variational
    const char* flag = nullptr;  // the option that chose the formulation, for messages (nullptr: the one above)
};

// Parse, build and derive (and form Hamilton's equations when asked). Throws InputError for a
// scene, or a combination of options, that the chapters refuse.
Pipeline front_end(const std::string& scene_path, const FrontEndOptions& options, StageClock* clock = nullptr);

// Lower and emit; `ir_out` (when given) receives the kernel IR the header was printed from.
std::string kernel_header(const Pipeline& p, StageClock* clock = nullptr, codegen::KernelIR* ir_out = nullptr);

// The equations depend on t explicitly (a driven carrier, a time-dependent force).
bool depends_on_time(const Pipeline& p);

}  // namespace eomc::host
