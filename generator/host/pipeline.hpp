// The pipeline every command runs, as one call: scene --parse--> Scene --build--> Model
// --derive--> Equations (--> Hamilton's equations) --lower--> KernelIR --emit--> header.
#pragma once

#include <chrono>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
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
    bool jacobian = false;  // emit jacobian() (--jacobian, [kernel] jacobian, or --variational, which needs it)
};

struct FrontEndOptions {
    bool hamiltonian = false;        // --hamiltonian (or the scene's [formulation] kind)
    std::string orbit_formulation;   // --orbit-formulation; "" = the scene's own
    std::string rigid_formulation;   // --rigid-formulation; "" = the scene's own
    bool variational = false;        // --variational
    bool jacobian = false;           // --jacobian
    const char* flag = nullptr;  // the option that chose the formulation, for messages (nullptr: the one above)
};

// Parse, build and derive (and form Hamilton's equations when asked). Throws InputError for a
// scene, or a combination of options, that the chapters refuse.
Pipeline front_end(const std::string& scene_path, const FrontEndOptions& options, StageClock* clock = nullptr);

// Lower and emit; `ir_out` (when given) receives the kernel IR the header was printed from.
// jacobian() is emitted when the pipeline asks for it (p.jacobian) or `jacobian` is set (the run
// needs it: method_needs_jacobian).
std::string kernel_header(const Pipeline& p, StageClock* clock = nullptr, codegen::KernelIR* ir_out = nullptr,
                          bool jacobian = false);

// The integrators whose run takes the kernel's jacobian(): radau5's Newton iteration. (gl4, gl6
// and gl8 iterate to a fixed point in `eomc simulate` and need none.) simulate, sweep, ensemble and
// bench generate jacobian() only when their method is one of these, or for --variational.
bool method_needs_jacobian(std::string_view integrator);

// The equations depend on t explicitly (a driven carrier, a time-dependent force).
bool depends_on_time(const Pipeline& p);

}  // namespace eomc::host
