// `eomc linearize` inputs and `eomc sweep SCENE --grid … --linearize`: the linearisation
// (mechanics/linearize/linearize.hpp) at every point of a grid of parameters or initial values, the
// Jacobians built once and evaluated per point. One CSV row per point with the eigenvalues in the
// listed order (decreasing real part, then decreasing imaginary part), the verdicts summarised, and
// a picture of the real parts against the one axis varied.
#pragma once

#include <complex>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "host/ensemble_spec.hpp"
#include "host/equilibria_sweep.hpp"
#include "mechanics/linearize/linearize.hpp"
#include "model/model.hpp"

namespace eomc::host {

// The values a linearisation starts from: the parameters (model order), every coordinate's initial
// value and rate.
struct LinearizeInputs {
    std::vector<double> parameters, q, u;
};

LinearizeInputs scene_inputs(const model::Model& model);

// NAME a parameter, a coordinate (its initial value) or a coordinate's NAME_dot (its rate); throws
// InputError at `where` otherwise, listing the names it takes.
void set_input(const model::Model& model, LinearizeInputs& inputs, const std::string& name, double value,
               const SourcePos& where);

struct LinearizePoint {
    std::size_t index = 0;
    std::vector<double> inputs;                     // in spec.input_names() order
    std::vector<std::complex<double>> eigenvalues;  // listed order
    std::string verdict;                            // stability_name, or "" with error
    std::vector<std::string> ignorable;
    std::string error;                              // why this point has no linearisation
};

struct LinearizeSweep {
    std::string scene_name, about;
    std::vector<std::string> input_names;
    std::size_t eigenvalue_count = 0;  // the largest count at any point: the CSV's columns
    std::vector<LinearizePoint> points;
};

// `base` holds the scene's values with `base_overrides` (--set) applied; at each point the initial
// values the scene gives as expressions of the parameters are recomputed from both and the grid's.
// Throws InputError at the --grid for random draws and for names set_input refuses, and for a grid
// that would take longer than limits.budget_s; a point whose operating point is refused (not steady,
// no equilibrium found) keeps the reason and the sweep goes on.
LinearizeSweep sweep_linearize(const mechanics::Linearizer& linearizer, const model::Model& model,
                               const EnsembleSpec& spec, mechanics::OperatingPointKind about,
                               const LinearizeInputs& base,
                               const std::vector<std::pair<std::string, double>>& base_overrides = {},
                               const SweepLimits& limits = {});

// point, the inputs, verdict, then re_1, im_1, re_2, im_2, …: the eigenvalues in the listed order.
std::string linearize_csv(const LinearizeSweep& sweep);
// Per point its verdict and largest real part (text), or one JSON object.
std::string linearize_summary(const LinearizeSweep& sweep, const std::string& format);
// Every eigenvalue's real part against the one axis varied; InputError at --plot otherwise.
std::string linearize_plot_script(const LinearizeSweep& sweep, const EnsembleSpec& spec, const std::string& terminal,
                                  const std::filesystem::path& output);

}  // namespace eomc::host
