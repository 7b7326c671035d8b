#pragma once

// Umbrella header of the eomc runtime.

#include "eomc/runtime/checker.hpp"
#include "eomc/runtime/dop853.hpp"
#include "eomc/runtime/dopri5.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/events.hpp"
#include "eomc/runtime/gauss_legendre.hpp"
#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/kernel.hpp"
#include "eomc/runtime/orbit/encke.hpp"
#include "eomc/runtime/orbit/kepler.hpp"
#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "eomc/runtime/quaternion.hpp"
#include "eomc/runtime/rk4.hpp"
#include "eomc/runtime/splitting.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/step_control.hpp"
#include "eomc/runtime/variational.hpp"
#include "eomc/runtime/version.hpp"
