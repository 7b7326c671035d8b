// `eomc sweep SCENE --grid … --equilibria`: the relative equilibria (mechanics/relative/
// equilibria.hpp) and their verdicts at every point of a parameter grid: the equations derived
// once, the equilibria solved and classified with each point's parameter values. One CSV row per
// equilibrium found, and the picture: over one axis a bifurcation diagram (each equilibrium's first
// coordinate against the parameter, stable and unstable apart), over two a stability map (the
// number of stable equilibria at each point).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "host/ensemble_budget.hpp"
#include "host/ensemble_spec.hpp"
#include "mechanics/relative/equilibria.hpp"
#include "mechanics/rigid/equilibria.hpp"

namespace eomc::host {

struct EquilibriumPoint {
    std::size_t index = 0;
    std::vector<double> inputs;  // in spec.input_names() order
    std::vector<mechanics::Equilibrium> equilibria;
    // A [rigid_body] scene: the permanent rotations about the principal axes at this point's spin
    // (mechanics/rigid/equilibria.hpp), in place of the relative equilibria.
    std::vector<mechanics::rigid::PermanentRotation> rotations;
    std::string error;           // why none could be found here ("" when solved)
};

struct EquilibriumSweep {
    std::string scene_name;
    std::vector<std::string> input_names, coordinate_names;
    bool rigid = false;  // rows are permanent rotations: label, γ, Ω
    std::vector<EquilibriumPoint> points;
};

// What a sweep may take: --budget-s (the time estimated after the first point, refused past it
// at --grid), and its progress bar (stderr a terminal, or --progress: `always`).
struct SweepLimits {
    double budget_s = default_budget_s;
    bool progress = true, always = false;
};

// Throws InputError at the --grid of a name that is not a parameter (an equilibrium has no initial
// values), for random draws (--vary), for a grid whose points would take longer than
// limits.budget_s (the first point's time × the points, before the second runs) and, from relative_equilibria, for a carrier that is not steady.
// For a [rigid_body] scene the grid may also sweep `spin`, the Ω of the families ω = Ω γ (the
// sleeping top's r0; absent: `eomc equilibria`'s default, ω0·γ0).
EquilibriumSweep sweep_equilibria(const model::Model& model, const mechanics::Equations& equations,
                                  const EnsembleSpec& spec, const SweepLimits& limits = {});

// The largest real part among an equilibrium's eigenvalues (its growth rate when > 0); for a
// permanent rotation, among those on its leaf.
double largest_growth(const mechanics::Equilibrium& e);
double largest_growth(const mechanics::rigid::PermanentRotation& r);

// point, the inputs, equilibria (the count at the point), the coordinates, verdict, growth (the
// largest Re λ): one row per equilibrium, a point without any one row with empty cells. A rigid
// body's: point, the inputs, rotations, rotation (its label), gamma1..3, spin, verdict, growth.
std::string equilibria_csv(const EquilibriumSweep& sweep);

// Printed after a sweep: per point its count and verdicts (text), or one JSON object.
std::string equilibria_summary(const EquilibriumSweep& sweep, const std::string& format);

// The gnuplot script (terminal, output) of the picture above; InputError at --plot for a grid that
// varies no axis or more than two.
std::string equilibria_plot_script(const EquilibriumSweep& sweep, const EnsembleSpec& spec, const std::string& terminal,
                                   const std::filesystem::path& output);

}  // namespace eomc::host
