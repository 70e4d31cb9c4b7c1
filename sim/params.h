// Simulation parameters as plain value types. Defaults are the paper's values (SPEC §2);
// pipeline/scene_params.h describes every field (JSON key, unit, valid range) for the scene
// loader and the JSON Schema, so the model itself stays free of any file format.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <vector>

namespace kurage::sim {

enum class NegativePressure {
  Clamp,  // p = max(0, k (rho - rho0)): no tensile attraction at free surfaces (default)
  Keep,   // p = k (rho - rho0) as written in the paper, negative values kept
};

enum class WallSlip {
  NoSlip,    // the paper's wall: a particle that entered the wall is put back and stopped
  FreeSlip,  // put back, only the normal velocity component removed
};

enum class TimeStepMode { Fixed, Adaptive };

enum class PressureForce {
  Mueller2003,   // (5) as in the paper: -sum m_j (p_i + p_j) / (2 rho_j) grad W. It recovers only
                 // half of grad p in the interior, so a fluid at rest carries twice the physical
                 // pressure (docs/PHYSICS.md)
  Monaghan1992,  // -rho_i sum m_j (p_i / rho_i^2 + p_j / rho_j^2) grad W: momentum-conserving and
                 // consistent (grad p of a linear field is recovered)
};

enum class WallDensity {
  None,        // the paper's walls: only the position clamp; particles near a wall miss kernel mass
  WallWeight,  // wall weight functions (Harada, Koshizuka & Kawaguchi 2007): the density and
               // pressure contributions of a virtual particle lattice behind each wall
};

struct FluidParams {
  float spacing = 1.0f;             // l_avr, m (SPEC §2)
  float supportRadius = 1.5f;       // h / l_avr (SPEC §2: r_e = 1.5 l_avr)
  float restDensity = 1000.0f;      // rho0, kg/m^3
  float pressureStiffness = 2.2f;   // k_press, (m/s)^2
  float kinematicViscosity = 0.3f;  // nu, m^2/s
  NegativePressure negativePressure = NegativePressure::Clamp;
  PressureForce pressureForce = PressureForce::Mueller2003;
  // Monaghan1992 only: correct each particle's kernel gradient with L_i = (sum_j V_j grad W_ij
  // (x) (r_j - r_i))^-1 (Bonet & Lok 1999), symmetrised as (L_i + L_j) / 2, so that the gradient
  // of a linear pressure field is exact on any neighbourhood. Particles within h of a wall or with
  // a degenerate neighbourhood (free surface) keep the plain gradient.
  bool gradientCorrection = false;

  float supportRadiusMetres() const { return supportRadius * spacing; }
  float speedOfSound() const { return std::sqrt(pressureStiffness); }  // m/s
};

struct ContainerParams {
  Eigen::Vector3f min{0, 0, 0};  // m
  Eigen::Vector3f max{10, 10, 10};
  WallSlip walls = WallSlip::NoSlip;
  WallDensity wallDensity = WallDensity::None;
};

// An axis-aligned block filled with fluid particles on a cubic lattice of the fluid spacing,
// the first particle half a spacing inside `min`.
struct FluidBlock {
  Eigen::Vector3f min{0, 0, 0};
  Eigen::Vector3f max{1, 1, 1};
};

// A nozzle (the jellyfish's faucets, SPEC §4.3): a disc of `radius` at `position`, facing
// `direction`, that emits fluid at `speed` from `start` to `end`. Particles are spawned in
// layers one fluid spacing apart, each layer a sunflower (Vogel) pattern of the disc whose count
// keeps the emitted volume equal to area x speed x time to within one particle.
struct EmitterParams {
  Eigen::Vector3f position{0, 0, 0};   // m, centre of the nozzle disc
  Eigen::Vector3f direction{1, 0, 0};  // outflow direction (normalised on use)
  float radius = 1.0f;                 // m
  float speed = 2.0f;                  // m/s
  float start = 0.0f;                  // s
  float end = 1.0f;                    // s
};

// A region that removes the fluid particles that enter it (an outflow).
struct SinkParams {
  Eigen::Vector3f min{0, 0, 0};
  Eigen::Vector3f max{1, 1, 1};
};

struct TimeStepParams {
  TimeStepMode mode = TimeStepMode::Adaptive;
  float fixedStep = 0.01f;  // s, used when mode == Fixed
  float cflFactor = 0.4f;   // dt <= cfl * h / (c + |v|max)
  float viscousFactor = 0.125f;  // dt <= factor * h^2 / nu
  float forceFactor = 0.25f;     // dt <= factor * sqrt(h / |a|max)
  float maxStep = 0.05f;    // s, upper limit of the adaptive step
  float minStep = 1e-5f;    // s, floor: a smaller bound stops the run with an error
};

struct SimParams {
  FluidParams fluid;
  Eigen::Vector3f gravity{0.0f, 0.0f, -6.0f};  // m/s^2 (SPEC §2: g = 6.0)
  ContainerParams container;
  std::vector<FluidBlock> fluidBlocks;
  std::vector<EmitterParams> emitters;
  std::vector<SinkParams> sinks;
  TimeStepParams timeStep;
};

}  // namespace kurage::sim
