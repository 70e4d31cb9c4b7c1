// Time step control (SPEC §1, our decision): a fixed step, or an adaptive one bounded by
//   CFL:      dt <= c_cfl  * h / (c + |v|max),  c = sqrt(k_press)
//   viscous:  dt <= c_visc * h^2 / nu
//   force:    dt <= c_f    * sqrt(h / |a|max)
//   spring:   dt <= c_spr  * min_i min(sqrt(2 m_i / K_i), m_i / D_i) over body particles, K_i and D_i
//             the sums of k and d over particle i's springs (explicit spring and damper stability)
//   pressure: dt <= c_p    * l / sqrt(|g| H), incompressible solvers only (ours; H the fluid's extent
//             along gravity, so |g| H is the deepest hydrostatic pressure over rho0): a particle
//             displaced in its neighbours' lattice under a pressure p is pushed back by the symmetric
//             pressure force, -(2 p / rho0) sum_j V_j grad W_ij, with no density error the solve could
//             see, so the solve leaves it explicit: an oscillator with omega^2 = C p / (rho0 l^2),
//             symplectic Euler stable for omega dt < 2. C = 1.9 for a perfect lattice (cubic spline,
//             h = 2 l: the Hessian of sum_j V_j W); measured C ~ 6 (a still tank of depth H at spacing
//             l blew up when g H dt^2 / l^2 exceeded about 0.6: at 0.5 m spacing, 20 m of water and
//             dt 0.04 s, the velocities grew 5-fold a step from the floor). c_p = 0.4: omega dt ~ 1.
// and the user's maximum step. The active bound is reported so users can see what limits speed.
#pragma once

#include "sim/params.h"

#include <array>
#include <string_view>

namespace kurage::sim {

enum class StepBound { Fixed, Cfl, Viscous, Force, Spring, Pressure, Maximum, Count };

std::string_view stepBoundName(StepBound bound);

struct StepLimit {
  float step = 0.0f;
  StepBound bound = StepBound::Fixed;
};

struct StepInputs {
  float supportRadius = 1.5f;  // h, m
  float cflLength = 0.0f;      // length of the CFL bound, m (0: h); an incompressible solver uses the
                               // particle spacing and a zero speed of sound (Bender & Koschier 2017, §6)
  float speedOfSound = 1.0f;   // m/s
  float kinematicViscosity = 0.0f;
  float maxSpeed = 0.0f;       // m/s
  float maxAcceleration = 0.0f;  // m/s^2
  float springStep = 0.0f;     // the bound above before the factor, s; 0 when there are no springs
  float pressureStep = 0.0f;   // l / sqrt(|g| H), s; 0 when the bound does not apply (header)
};

// The adaptive step and the bound that set it (the smallest of the bounds above).
StepLimit adaptiveStep(const TimeStepParams& params, const StepInputs& inputs);

// The stability bound of a scene's own parameters at rest (|v| = 0, |a| = |g|), used to warn
// about a fixed step that is too large.
StepLimit stabilityBound(const TimeStepParams& params, const StepInputs& inputs);

}  // namespace kurage::sim
