// Measures of bodies in the fluid, each a function of one frame's particles (kind 0 the fluid,
// kind k >= 1 body k - 1): a kind's extent and RMS speed, the free surface clear of a body,
// Archimedes' submerged fraction, fluid tunnelled through a membrane and who carries the load
// on it, and how close a chain comes to crossing itself. Metres, seconds, pascals.
#pragma once

#include "sim/particles.h"

#include <Eigen/Core>

#include <cstddef>

namespace kurage::pipeline {

// Extent of the particles of one kind (k >= 1: body k - 1).
struct KindExtent {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(1e30f), max = Eigen::Vector3f::Constant(-1e30f);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  size_t count = 0;
};
KindExtent kindExtent(const sim::ParticleSet& particles, int kind);

// The free surface of the fluid away from a body: over columns `cellSize` wide (cells of the x-y
// grid anchored at 0) whose centre lies farther than `clear` from (cx, cy) horizontally, the mean
// height of the top fluid particle, plus half a fluid spacing. 0 when no column qualifies.
double freeSurfaceHeight(const sim::ParticleSet& particles, double cx, double cy, double clear, float cellSize,
                         float spacing);

// Archimedes: the share of body `kind`'s particles whose centre lies below the free surface, the
// surface measured clear of the body by its horizontal half extent plus 1.5 spacings.
double submergedFraction(const sim::ParticleSet& particles, int kind, float fluidSpacing);

// Fluid particles that have tunnelled through a membrane: those more than half a fluid spacing
// below the membrane's lowest particle (its centre).
struct MembraneLeak {
  size_t fluid = 0;   // fluid particles in the scene
  size_t leaked = 0;  // of which below the membrane
};
MembraneLeak membraneLeak(const sim::ParticleSet& particles, int kind, float fluidSpacing);

// Who carries the poured fluid's weight (docs/notebook/pressure_solvers.md, "Why the membrane's contrast is
// WCSPH's"): the 90th percentile of the pressure of the membrane's particles that have a fluid
// particle within 0.7 h, and the median pressure of the fluid particles within h of the membrane
// (Pa; 0 where there are none). Brute force over fluid x membrane pairs: for the small scenes
// that pour fluid onto a membrane.
struct MembraneLoad {
  double sheetPressure90 = 0;  // the loaded sheet's pressure, 90th percentile
  double fluidPressure50 = 0;  // the fluid's pressure against the sheet, median
  size_t sheetParticles = 0, fluidParticles = 0;  // how many each figure is over
};
MembraneLoad membraneLoad(const sim::ParticleSet& particles, int kind, float supportRadius);

// RMS speed of the particles of one kind (0 = fluid), m/s; 0 when there are none.
double rmsSpeed(const sim::ParticleSet& particles, int kind);

// The smallest distance between two segments of a chain (an oral arm: body `kind`'s particles
// in id order) that share no particle: a chain that crosses or knots itself brings two such
// segments within a particle spacing. Infinity for fewer than four particles.
double chainSelfApproach(const sim::ParticleSet& particles, int kind);

}  // namespace kurage::pipeline
