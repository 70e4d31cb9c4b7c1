// Dam break against Martin & Moyce 1952 (tests/data/martin_moyce_1952.csv, a copy of
// ../shared/data/): a column of width a = 2.25 in and height 2a collapses on a horizontal floor.
//
// Set-up (docs/results/validation.md): a/l = 20 particles across the column, 4 particle layers deep in y
// between free-slip walls (a quasi-2-D slice), tank 12 a long; h = 2 l, c = 20 m/s (over 10 times
// the surge speed of about 1.5 m/s), the consistent pressure form with wall weights, and a
// kinematic viscosity of 5e-4 m^2/s acting as SPH's artificial viscosity (500 x water).
// Surge front: the 99.8th percentile of x over particles below z = a/4 (robust to isolated
// spray), plus half a spacing. Column height: the highest particle within two spacings of the
// back wall with at least three other fluid particles within two spacings (not spray), plus half
// a spacing. Both are sampled every 0.05 in tau = t sqrt(g/a) and
// interpolated linearly at the tabulated times.
#include "pipeline/analysis/dam_break.h"
#include "sim/simulation.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>

using namespace kurage::sim;
using kurage::pipeline::DamBreakTrack;
using kurage::pipeline::meanRelativeError;

namespace {

struct Measured {
  double frontError = 0, heightError = 0;  // mean relative errors
  int frontPoints = 0, heightPoints = 0;
};

// The slice and the discretisation: the defaults are the set-up above.
struct Slice {
  int layers = 4;               // particle layers in y
  float supportRadius = 2.0f;   // h, in spacings
  float maxStep = 0.0f;         // s; 0: the scene default
  bool gradientCorrection = false;  // fluid.gradient_correction (DFSPH)
};

// Runs the dam break, prints both errors under `label` and records them as test properties.
Measured runDamBreak(WallSlip walls, const std::string& solver = "wcsph",
                     WallDensity wallDensity = WallDensity::WallWeight, SphKernel kernel = SphKernel::Auto,
                     const Slice& slice = {}) {
  const float a = 0.05715f, g = 9.81f, l = a / 20;
  const int layers = slice.layers;
  SimParams p;
  p.fluid.spacing = l;
  p.fluid.supportRadius = slice.supportRadius;
  p.fluid.pressureStiffness = 20.0f * 20.0f;
  p.fluid.kinematicViscosity = 5e-4f;
  if (slice.maxStep > 0) p.timeStep.maxStep = slice.maxStep;
  p.fluid.gradientCorrection = slice.gradientCorrection;
  p.fluid.pressureForce = PressureForce::Monaghan1992;
  p.gravity = Eigen::Vector3f(0, 0, -g);
  p.container.max = Eigen::Vector3f(12 * a, layers * l, 2.5f * a);
  p.container.walls = walls;
  p.container.wallDensity = wallDensity;
  p.fluid.solver = solver;
  p.fluid.kernel = kernel;
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(a, layers * l, 2 * a)});
  Simulation sim(p);
  const size_t count = sim.particles().size();

  // The measures of pipeline/analysis/dam_break.h (shared with `kurage study`), sampled every 0.05 in tau.
  DamBreakTrack track({a, 2.0 * a, g, l, Eigen::Vector3d::Zero()});
  for (int f = 1; f <= 152; ++f) {
    sim.advanceTo(track.timeAtTau(f * 0.05));
    track.record(sim.particles(), sim.time());
  }
  EXPECT_EQ(sim.particles().size(), count);

  const auto reference = kurage::pipeline::loadMartinMoyce(kurage::test::sourceDir() / "tests/data/martin_moyce_1952.csv");
  const auto front = meanRelativeError(track.front(), reference.surgeFront);
  const auto height = meanRelativeError(track.column(), reference.columnHeight);
  const Measured m{front.meanRelative, height.meanRelative, front.points, height.points};
  return m;
}

}  // namespace

TEST(DamBreak, FreeSlipMatchesMartinMoyceWithin10Percent) {
  const Measured m = runDamBreak(WallSlip::FreeSlip);
  EXPECT_EQ(m.frontPoints, 15);
  EXPECT_EQ(m.heightPoints, 17);
  EXPECT_LT(m.frontError, 0.10);  // measured 6.7 %
  EXPECT_LT(m.heightError, 0.10);  // measured 3.9 %
}

TEST(DamBreak, NoSlipWallsSlowTheSurge) {
  // The paper's wall (velocity zeroed on contact) acts as strong friction on the floor and the
  // back wall: the result is reported (docs/results/validation.md), and it must be worse than free slip.
  const Measured m = runDamBreak(WallSlip::NoSlip);
  EXPECT_GT(m.frontError, 0.10);
}

// The same dam break with the incompressible solvers and boundary-particle walls (Bender &
// Koschier 2017; Ihmsen et al. 2014; Akinci et al. 2012). Measured: DFSPH surge front 4.6 %,
// column height 9.9 % (the target is 5 % each; WCSPH with wall weights: 6.7 / 3.9 %;
// DFSPH without the walls' hydrostatic pressure 9.6 / 6.0 %, with it but a one-sided divergence
// solve 5.1 / 14.4 %); IISPH 4.4 / 9.4 %.
struct DamBreakLimits {
  std::string solver;
  double front, height;  // mean relative errors allowed
};
void PrintTo(const DamBreakLimits& l, std::ostream* os) { *os << l.solver; }
class IncompressibleDamBreak : public ::testing::TestWithParam<DamBreakLimits> {};

TEST_P(IncompressibleDamBreak, WithBoundaryParticlesMatchesMartinMoyce) {
  const DamBreakLimits limits = GetParam();
  const Measured m = runDamBreak(WallSlip::FreeSlip, limits.solver, WallDensity::BoundaryParticles);
  EXPECT_EQ(m.frontPoints, 15);
  EXPECT_EQ(m.heightPoints, 17);
  EXPECT_LT(m.frontError, limits.front);
  EXPECT_LT(m.heightError, limits.height);
}

INSTANTIATE_TEST_SUITE_P(Solvers, IncompressibleDamBreak,
                         ::testing::Values(DamBreakLimits{"dfsph", 0.08, 0.12}, DamBreakLimits{"iisph", 0.08, 0.12}),
                         [](const auto& info) { return info.param.solver; });

// The same solver and walls in a slice closer to the experiment's two dimensions, 16 layers deep
// (0.8 a) instead of 4, with a wider support (h = 3 l, 92 neighbours; the solve keeps h = 2 l's
// relaxation, sim/solvers/dfsph/dfsph.cpp), the first-order kernel-gradient correction
// (fluid.gradient_correction) and steps of at most 0.2 ms (DFSPH's own are about 0.6 ms here).
// Measured 4.46 % / 4.47 %: the 5 % each (docs/results/validation.md, "Martin & Moyce under DFSPH":
// every step from 0.1 to 0.3 ms and nu from 5e-4 to 7e-4 reads under 5 % on both; docs/results/accuracy.md,
// "DFSPH's support and slice": corrected at h = 2 l this slice reads 7.7 / 7.2 %, uncorrected at
// h = 3 l 4.6 / 5.1 %).
TEST(DamBreak, DfsphInADeeperSliceWithAWiderSupportMatchesMartinMoyceWithin5Percent) {
  const Measured m = runDamBreak(WallSlip::FreeSlip,
                                 "dfsph", WallDensity::BoundaryParticles, SphKernel::Auto,
                                 {.layers = 16, .supportRadius = 3.0f, .maxStep = 2e-4f, .gradientCorrection = true});
  EXPECT_EQ(m.frontPoints, 15);
  EXPECT_EQ(m.heightPoints, 17);
  EXPECT_LT(m.frontError, 0.05);
  EXPECT_LT(m.heightError, 0.05);
}

// Wall weights are tabulated with the fluid's own kernels (sim/boundary.h): with the cubic spline
// (fluid.kernel "cubic_spline" under WCSPH, and DFSPH's) the walls continue the fluid's sums. With
// tables of the paper's poly6 and spiky beside a cubic-spline fluid, as before, a lattice particle
// next to a wall summed the wrong density and this dam break read 62 % / 81 %. Measured: 7.7 / 5.1 %.
TEST(DamBreak, CubicSplineWithWallWeightsMatchesMartinMoyceWithin10Percent) {
  const Measured m = runDamBreak(WallSlip::FreeSlip, "wcsph",
                                 WallDensity::WallWeight, SphKernel::CubicSpline);
  EXPECT_EQ(m.frontPoints, 15);
  EXPECT_EQ(m.heightPoints, 17);
  EXPECT_LT(m.frontError, 0.10);
  EXPECT_LT(m.heightError, 0.10);
}

// DFSPH with wall weights: the walls' tables give the solver its wall gradient sum_b V_b grad W_ib
// and the walls' hydrostatic term (Simulation::computeWallWeightGradient, WallWeights::liftNormal),
// as boundary particles do. Without the gradient the walls counted in every density but the solves
// could not push away from them: in this slice, every particle within two spacings of a side wall,
// the run stopped at t = 0.43 s (a step below the floor). Measured: 4.8 / 11.6 % (boundary
// particles 4.6 / 9.9 %; without the hydrostatic term 8.7 / 6.0 %, docs/design/physics.md).
TEST(DamBreak, DfsphWithWallWeightsMatchesMartinMoyceAsBoundaryParticlesDo) {
  const Measured m = runDamBreak(WallSlip::FreeSlip, "dfsph", WallDensity::WallWeight);
  EXPECT_EQ(m.frontPoints, 15);
  EXPECT_EQ(m.heightPoints, 17);
  EXPECT_LT(m.frontError, 0.08);
  EXPECT_LT(m.heightError, 0.14);
}

// The column height is read from the column, not from spray: a lone drop above the back wall
// (measured: a particle thrown to 0.67 a while the column stood at 0.17 a read WCSPH's column
// error as 24 % instead of 8 %, docs/results/validation.md) does not count; a drop with company does.
TEST(DamBreakTrack, TheColumnIgnoresALoneDropAboveIt) {
  const double a = 0.05715, l = a / 20;
  const auto column = [&](int dropCompany) {
    ParticleSet p;
    int64_t id = 0;
    for (int ix = 0; ix < 4; ++ix)  // a column 10 l high, four spacings wide (two in the band), four deep
      for (int iy = 0; iy < 4; ++iy)
        for (int iz = 0; iz < 10; ++iz)
          p.add(float((ix + 0.5) * l), float((iy + 0.5) * l), float((iz + 0.5) * l), 0, 0, 0, 1000, 1, id++, 0);
    for (int k = 0; k <= dropCompany; ++k)  // a drop at 30 l, and its company within a spacing
      p.add(float(0.5 * l + k * 0.3 * l), float(0.5 * l), float(30 * l), 0, 0, 0, 1000, 1, id++, 0);
    DamBreakTrack track({a, 2.0 * a, 9.81, l, Eigen::Vector3d::Zero()});
    track.record(p, 0.1);
    return track.column().back().y * 2.0 * a / l;  // in spacings, half a spacing above the top particle
  };
  EXPECT_NEAR(column(0), 10.0, 1e-4) << "a lone drop";
  EXPECT_NEAR(column(2), 10.0, 1e-4) << "three drops together";
  EXPECT_NEAR(column(3), 30.5, 1e-4) << "four drops together";
}
