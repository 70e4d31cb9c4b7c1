// Simulation parameters as plain value types. Defaults are the paper's values (SPEC §2);
// pipeline/scene_params.h describes every field (JSON key, unit, valid range) for the scene
// loader and the JSON Schema, so the model itself stays free of any file format.
#pragma once

#include <Eigen/Core>

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

struct FluidParams {
  float spacing = 1.0f;             // l_avr, m (SPEC §2)
  float supportRadius = 1.5f;       // h / l_avr (SPEC §2: r_e = 1.5 l_avr)
  float restDensity = 1000.0f;      // rho0, kg/m^3
  float pressureStiffness = 2.2f;   // k_press, (m/s)^2
  float kinematicViscosity = 0.3f;  // nu, m^2/s
  NegativePressure negativePressure = NegativePressure::Clamp;

  float supportRadiusMetres() const { return supportRadius * spacing; }
  float speedOfSound() const;  // sqrt(k_press), m/s
};

struct ContainerParams {
  Eigen::Vector3f min{0, 0, 0};  // m
  Eigen::Vector3f max{10, 10, 10};
  WallSlip walls = WallSlip::NoSlip;
};

// An axis-aligned block filled with fluid particles on a cubic lattice of the fluid spacing,
// the first particle half a spacing inside `min`.
struct FluidBlock {
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
  TimeStepParams timeStep;
};

}  // namespace kurage::sim
