// The Siconos side of bench/contact_siconos.cpp, compiled apart: Siconos 4.4's headers (Boost.uBLAS
// with std::allocator::construct) need C++17, eomc's runtime C++20; only this plain record crosses.
#pragma once

#include <cmath>
#include <string>
#include <vector>

namespace contact_bench {

// One run's record.
struct Run {
    std::vector<double> impacts;  // impact times in order
    double q1 = NAN, v1 = NAN, q5 = NAN, v5 = NAN;
    double lambda5 = NAN;         // the contact force at the end (λ, or P/h)
    std::string zeno;             // what happened at t∞
    std::string failure;          // an exception's text, if any
    double last_step_count = 0;   // steps (time stepping) or accepted steps
};

// The bouncing ball (is_block false) or Housner's block from t = 0 to 5: EventDriven + LsodarOSI at
// rtol (atol = rtol/100), or TimeStepping + MoreauJeanOSI(1/2) + LCP at step h.
void siconos_event_driven(bool is_block, double rtol, Run& run);
void siconos_moreau_jean(bool is_block, double h, Run& run);

}  // namespace contact_bench
