#pragma once

// Umbrella header of the eomc runtime.

#include "eomc/runtime/checker.hpp"
#include "eomc/runtime/control/error_checker.hpp"
#include "eomc/runtime/control/initial_step.hpp"
#include "eomc/runtime/control/step_adjuster.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/events.hpp"
#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/kepler.hpp"
#include "eomc/runtime/orbital_elements.hpp"
#include "eomc/runtime/registry.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/dop853.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"
#include "eomc/runtime/stepper/gauss_legendre.hpp"
#include "eomc/runtime/stepper/rk4.hpp"
#include "eomc/runtime/stepper/splitting.hpp"
#include "eomc/runtime/version.hpp"
