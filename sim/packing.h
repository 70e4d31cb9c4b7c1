// The relaxed packing fluid blocks may start on (fluid.packing "relaxed"; ours): a disordered
// tile instead of the simple cubic lattice, and the particle mass calibrated on it.
//
// Why: the simple cubic lattice is unstable under load. A column started on it rearranges within
// a few seconds into a disordered packing whose kernel sum per number density is lower (cubic
// spline, h = 2 l: by 0.3 %), so at the same SPH density its particles stand closer and the column
// loses that share of its volume (docs/design/physics.md, "The packing"). Started on a disordered
// packing with the mass calibrated on it, the column is at rest density from the start and has
// no volume to lose.
//
// The tile: n^3 particles in a periodic cube of edge n l (number density 1 / l^3), the cubic
// lattice jittered by up to +-0.15 l, moved down the gradient of the sum of their densities,
// E = sum_i sum_{j != i} W(x_i - x_j) over periodic images (what a uniform pressure does to
// them), with the density kernel of the scene's solver, to a local minimum without lattice order
// (a glass): steepest descent, x_i <- x_i - s dE/dx_i, the step s grown by a tenth after a step
// that lowers E and halved (the step refused) otherwise, no point moving more than 0.1 l a step,
// a fixed number of steps, serial and in a fixed order from a fixed pseudo-random jitter, so the
// tile is the same on every machine and thread count. Its mean kernel sum S (per l^3, self
// included) calibrates the mass, m = rho0 l^3 / S, in place of the lattice's sum
// (calibratedParticleMass, sim/fluid.h).
//
// Units: positions in spacings (l = 1) in the tile, metres once placed. Limits: the tile's edge
// n = max(8, ceil(2 h / l) + 2) spacings keeps the support below half of it; a block thinner than
// the edge on some axis has no interior a periodic packing stands for (holdsTile) and starts on
// the lattice; the tile's faces meet the walls wherever they fall (a particle may start closer to
// a wall than half a spacing); only the cubic spline is accepted by Simulation (poly6's sum has
// no such minimum: it is lowered by clustering).
#pragma once

#include "sim/kernels.h"
#include "sim/params.h"

#include <Eigen/Core>

#include <vector>

namespace kurage::sim {

struct PackingTile {
  int cells = 0;                         // n: the tile is n spacings on each edge and holds n^3 points
  std::vector<Eigen::Vector3f> points;   // in [0, n)^3, spacings
  double kernelSum = 0.0;                // mean over the points of sum_j W(x_i - x_j) (self included), 1 / l^3
  double latticeKernelSum = 0.0;         // the same on the simple cubic lattice, for comparison
};

// The tile's edge in spacings for a support radius of `supportRatio` spacings, and whether a block
// holds a bulk the tile can fill: every extent at least the tile's edge (a thinner block, a slice
// or a sheet, has no interior a periodic packing stands for, and starts on the cubic lattice).
int tileCells(float supportRatio);
bool holdsTile(const FluidBlock& block, float spacing, float supportRatio);

// The relaxed tile for a support radius of `supportRatio` spacings and the given density kernel.
PackingTile relaxedTile(float supportRatio, DensityKernel kernel);

// The tile repeated over a fluid block from its `min` corner, scaled to `spacing` (m): every
// point with min <= x < max.
std::vector<Eigen::Vector3f> tiledPoints(const FluidBlock& block, float spacing, const PackingTile& tile);

// The particle mass that gives the tile's mean density rho0 at the given spacing (m):
// m = rho0 / (S / l^3).
float tileParticleMass(const PackingTile& tile, float spacing, float restDensity);

}  // namespace kurage::sim
