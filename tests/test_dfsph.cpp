// The pressure solver seam, DFSPH and IISPH, boundary-particle walls and the hydrostatic start.
// Label `validation` for the tank and dam-break figures, the rest run in seconds.
#include "pipeline/analysis/body_measures.h"
#include "pipeline/analysis/still_tank.h"
#include "sim/boundary.h"
#include "sim/boundary_particles.h"
#include "sim/fluid.h"
#include "sim/simulation.h"
#include "sim/solvers/pressure_solver.h"
#include "sim_util.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <numbers>

using namespace kurage::sim;

namespace {

// The jellyfish's tank (scenes/jellyfish.json): 20 x 14 m, 20 m of water, 24.5 m of wall, g = 6.
SimParams jellyfishTank(const std::string& solver, float spacing, InitialState start = InitialState::Hydrostatic) {
  SimParams p;
  p.fluid.spacing = spacing;
  p.fluid.supportRadius = 2.0f;
  p.fluid.solver = solver;
  p.fluid.pressureForce = PressureForce::Monaghan1992;
  p.fluid.kinematicViscosity = 0.3f;
  p.fluid.initialState = start;
  // WCSPH: stiff enough for a 0.6 % compression at the floor (c = 141 m/s)
  p.fluid.pressureStiffness = 20000.0f;
  p.container.max = Eigen::Vector3f(20, 14, 24.5f);
  p.container.walls = WallSlip::FreeSlip;
  p.container.wallDensity = WallDensity::BoundaryParticles;
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(20, 14, 20)});
  return p;
}

// The same 20 m of water on a quarter of the floor, 10 x 7 m: at 0.5 m spacing it has the 1 m
// tank's 20 x 14 columns, as many kernel radii from each side wall, and the full depth in 40
// layers, for a quarter of the 20 x 14 m tank's particles.
SimParams quarterFloor(SimParams p) {
  p.container.max.head<2>() *= 0.5f;
  p.fluidBlocks[0].max.head<2>() *= 0.5f;
  return p;
}

}  // namespace

TEST(CubicSpline, IntegratesToOneAndItsGradientMatchesFiniteDifferences) {
  const CubicSplineKernel w(1.3f);
  double integral = 0.0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    const double r = (k + 0.5) * w.h / n;
    integral += 4.0 * std::numbers::pi * r * r * w(float(r)) * w.h / n;
  }
  EXPECT_NEAR(integral, 1.0, 1e-3);
  for (float r : {0.1f, 0.4f, 0.6f, 0.9f, 1.2f}) {
    const float e = 1e-3f;
    EXPECT_NEAR(w.derivative(r), (w(r + e) - w(r - e)) / (2 * e), 2e-3f * w.sigma) << r;
  }
  EXPECT_EQ(w(1.3f), 0.0f);
  EXPECT_EQ(w.derivative(1.3f), 0.0f);
}

TEST(SolverRegistry, NamesTheSolversAndRefusesOthers) {
  const auto& names = pressureSolverNames();
  for (const char* name : {"wcsph", "dfsph", "iisph"}) EXPECT_NE(std::find(names.begin(), names.end(), name), names.end());
  FluidParams f;
  EXPECT_THROW(f.solver = "pcisph", std::invalid_argument);
  EXPECT_THROW(f.solver.as<DfsphParams>(), std::logic_error) << "WCSPH's parameters are not DFSPH's";
  f.solver = "dfsph";
  EXPECT_EQ(f.solver.as<DfsphParams>().maxIterations, 100);
  FluidParams copy = f;
  copy.solver.as<DfsphParams>().maxIterations = 3;
  EXPECT_EQ(f.solver.as<DfsphParams>().maxIterations, 100) << "a copy owns its parameters";
  EXPECT_EQ(makePressureSolver(f)->name(), "dfsph");
  EXPECT_EQ(makePressureSolver(f)->densityKernel(), DensityKernel::CubicSpline);
  // fluid.kernel "auto": DFSPH's own, the paper's for WCSPH, but the cubic spline for WCSPH with
  // boundary-particle walls; a kernel named in the scene is kept.
  EXPECT_EQ(resolvedKernel(f, WallDensity::None), SphKernel::CubicSpline);
  f.solver = "wcsph";
  EXPECT_EQ(resolvedKernel(f, WallDensity::None), SphKernel::Mueller2003);
  EXPECT_EQ(resolvedKernel(f, WallDensity::WallWeight), SphKernel::Mueller2003);
  EXPECT_EQ(resolvedKernel(f, WallDensity::BoundaryParticles), SphKernel::CubicSpline);
  f.kernel = SphKernel::Mueller2003;
  EXPECT_EQ(resolvedKernel(f, WallDensity::BoundaryParticles), SphKernel::Mueller2003);
  f.kernel = SphKernel::CubicSpline;
  EXPECT_EQ(makePressureSolver(f)->densityKernel(), DensityKernel::CubicSpline);
  f.solver = "dfsph";
  f.kernel = SphKernel::Mueller2003;
  EXPECT_THROW(makePressureSolver(f), std::invalid_argument);
}

// A particle on the rest lattice next to a wall, an edge or a corner sums the rest density with
// boundary particles, as one deep inside does: no crowding, no gap.
TEST(BoundaryParticles, ALatticeParticleAtAWallEdgeOrCornerHasTheRestDensity) {
  for (const std::string solver : {"wcsph", "dfsph"}) {
    SimParams p;
    p.fluid.supportRadius = 2.0f;
    p.fluid.solver = solver;
    p.container.max = Eigen::Vector3f(8, 8, 8);
    p.container.wallDensity = WallDensity::BoundaryParticles;
    p.gravity.setZero();
    p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(8, 8, 8)});
    Simulation sim(p);
    sim.step(1e-4f);  // one tiny step: densities of the (unmoved) lattice
    ASSERT_NE(sim.boundaryParticles(), nullptr);
    EXPECT_GT(sim.boundaryParticles()->size(), 0u);
    const ParticleSet& s = sim.particles();
    double worst = 0.0;
    for (size_t i = 0; i < s.size(); ++i) worst = std::max(worst, std::fabs(s.density[i] / s.restDensity[i] - 1.0));
    EXPECT_LT(worst, 2e-3) << solver << ": every particle, walls, edges and corners included";
  }
}

// DFSPH's walls from wall weights (Simulation::computeWallWeightGradient) are the lateral average
// of what boundary particles give: sum_b V_b grad W_ib and the hydrostatic term
// sum_b V_b (g . (x_b - x)) grad W_ib, for a particle in front of the floor and of a side wall
// (measured: within 2 % at half a spacing, 3 % / 20 % of a smaller value at one spacing).
TEST(WallWeights, GiveDfsphTheTermsBoundaryParticlesGive) {
  const float l = 1.0f, h = 2.0f, rho0 = 1000.0f;
  const float m = calibratedParticleMass(l, h, rho0, DensityKernel::CubicSpline);
  ContainerParams box;
  box.max = Eigen::Vector3f(20, 20, 20);
  const WallWeights weights(l, h, m, DensityKernel::CubicSpline);
  const BoundaryParticles samples(box, l, h, m / rho0);
  const CubicSplineKernel w(h);
  const Eigen::Vector3f g(0, 0, -6);
  for (const float d : {0.5f, 1.0f})
    for (const bool floor : {true, false}) {
      const Eigen::Vector3f x = floor ? Eigen::Vector3f(10.5f, 10.5f, d) : Eigen::Vector3f(d, 10.5f, 10.5f);
      float volume = 0.0f;
      Eigen::Vector3f gradient, lift;
      samples.sums(w, w, x.x(), x.y(), x.z(), volume, gradient, &g, &lift);
      const WallContribution c = boxWallContribution(weights, box, h, x.x(), x.y(), x.z());
      const Eigen::Vector3f tableGradient = -c.gradient / rho0, tableLift = boxWallLift(weights, box, h, x, g) / rho0;
      EXPECT_NEAR(c.density / rho0, volume, 0.02f * volume) << d << (floor ? " floor" : " side wall");
      EXPECT_NEAR((tableGradient - gradient).norm(), 0.0f, 0.05f * gradient.norm()) << d;
      // The lift points down at both walls (DFSPH pushes with -dt lift: up), as the samples' does.
      EXPECT_LT(tableLift.z(), 0.0f);
      EXPECT_NEAR((tableLift - lift).norm(), 0.0f, (d < 0.75f ? 0.05f : 0.25f) * lift.norm()) << d;
    }
}

// Hydrostatic tank (the jellyfish's: 20 m of water, boundary particles, hydrostatic start),
// settled: free surface and interior pressure averaged from 2 to 5 s, sampled every 0.01 s, at 1 m
// and 0.5 m spacing. The surface (HydrostaticTrack: where the interior's colour field, averaged
// over its floor, is one half) is compared with the filled height (20 m), each slab's pressure
// with rho0 g times its depth below the free surface of the same sample (the filled height would
// count the surface's settling twice: a surface 0.1 m low is 4 % of a slab 2.5 m deep). Slabs are
// two spacings thick: the pressure force on a lattice layer reads differences of the layers as far
// above it as below, which share a parity, so a pressure alternating from layer to layer pushes
// nothing and no solve corrects it (in the bulk); a slab of
// two layers reads the pressure that acts (docs/design/physics.md "Slabs two spacings thick"; the
// one-spacing layers are printed). DFSPH's pressure is what both of its solves applied (the
// density solve's and the divergence solve's impulse over the step). The issue asks for the
// surface within 0.5 % and every slab within 2 % (DFSPH), 3 % (WCSPH). Measured (1 m / 0.5 m;
// in brackets the study hydrostatic_tank_scatter's four runs a thousandth of a step apart):
// - DFSPH calm and corrected (fluid.gradient_correction, the divergence solve by conjugate
//   gradients at 0.01 %, the density at the default 0.1 %; RMS 0.25 / 0.13 m/s): surface
//   0.25 % / 0.28 % (0.25-0.26 % / 0.30-0.31 %), slabs 0.44 % / 0.22 % (0.51-1.25 % / 0.57-1.11 %).
//   The figures hold at both spacings in every run: asserted at 0.5 % and 2 %. (Before,
//   the density tolerance was 0.01 % as well: 0.25 % / 0.30 % and 0.57 % / 0.56 %, at
//   1.8 / 3.0 times the default's time against 1.2 / 1.05 now.)
// - DFSPH calm (the same without the correction; RMS 0.27 / 0.17 m/s): surface 0.55 % / 0.36 %
//   (0.53-0.54 % / 0.32-0.33 %), slabs 0.57 % / 1.89 % (0.45-0.77 % / 1.09-1.63 %): the 1 m
//   surface misses the 0.5 % (asserted at 0.8 %), the 0.5 m slabs are near the 2 % (asserted at
//   2.5 %).
// - DFSPH at its defaults: surface 0.04 % / 0.07 %, slabs 2.08 % / 2.86 % (1.43-2.64 % /
//   0.74-6.01 %); with the correction alone 0.14 % / 0.12 %, 2.59 % / 2.46 % (2.62-4.29 % /
//   2.34-4.07 %). Not met; the tank bounces (RMS 0.6-0.7 m/s), so these are asserted at 6.5 %,
//   guards against a blow-up: the defaults at both spacings, the correction alone at 1 m (at
//   0.5 m its two paths run in the calm and corrected case and the defaults' Jacobi divergence
//   solve).
// - WCSPH (k = 20000, walls of boundary particles energy-consistent, docs/design/physics.md "Walls under
//   WCSPH"): surface 0.27 % / 0.67 % (0.28-0.29 % / 0.68-0.69 %), slabs 1.72 % / 2.06 %
//   (1.70-1.79 % / 2.66-2.86 %); with the gradient correction 0.04 % / 0.44 %, 1.02 % / 1.14 %.
//   Asserted at the 3 %, the corrected WCSPH at 1 m (the correction at 0.5 m runs under
//   DFSPH).
// - IISPH at its defaults (0.1 %, the paper's warm start of half the last step's pressure; no
//   divergence solve): surface 0.45 % / 0.50 %, slabs 3.93 % / 1.33 %, RMS 0.37 / 0.07 m/s.
//   Asserted at 0.7 % and 5 % / 2.5 %.
// (With one-spacing layers, as until 2026-11-27: calm and corrected, both tolerances at 0.01 %,
// 1.04 % / 1.94 %, four runs 1.04-1.58 % / 1.13-2.29 %; the defaults 2.79 % / 3.13 %; WCSPH
// 2.23 % / 2.15 %.)
// Printed beside them, each slab's pressure against the weight of the water actually above it
// (HydrostaticTrack::worstSlabAgainstWeight; docs/design/physics.md).
// The fluid's RMS speed at the end is bounded too: DFSPH's still tank is not calm at its defaults
// (0.6-0.7 m/s, bound 1 m/s; docs/design/physics.md), the calm ones are (0.13-0.27 m/s, bound 0.5), and
// WCSPH's is (0.2-0.33 m/s, bound 0.3 at 1 m and 0.4 at 0.5 m; 23 m/s with the mirrored walls,
// which boiled the tank).
struct TankCase {
  std::string solver;
  float spacing;
  bool corrected;                              // fluid.gradient_correction
  bool calm;  // the divergence solve by conjugate gradients at 0.01 % (the density at its default 0.1 %)
  double from, to;                             // the averaging window, s
  double surfaceTolerance, pressureTolerance;  // fractions
  double rmsSpeed;                             // m/s, the fluid's at the end
};

void PrintTo(const TankCase& c, std::ostream* os) {
  *os << c.solver << " l = " << c.spacing << (c.corrected ? ", gradient correction" : "") << (c.calm ? ", calm" : "");
}

class HydrostaticTank : public ::testing::TestWithParam<TankCase> {};

TEST_P(HydrostaticTank, SettledSurfaceAndInteriorPressure) {
  const TankCase c = GetParam();
  SimParams params = jellyfishTank(c.solver, c.spacing);
  params.fluid.gradientCorrection = c.corrected;
  if (c.calm) {
    params.fluid.solver.as<DfsphParams>().divergenceSolve = DivergenceSolve::ConjugateGradient;
    params.fluid.solver.as<DfsphParams>().maxDivergenceError = 0.01f;
  }
  Simulation sim(params);
  // The free surface against the filled height, 20 m; each slab's depth below the sample's free
  // surface (the depth below the filled height is printed)
  kurage::pipeline::HydrostaticTrack track(params, 20.0);
  for (int k = 1; k <= int(std::lround(c.to / 0.01)); ++k) {
    sim.advanceTo(0.01 * k);
    if (sim.time() >= c.from - 1e-9) track.record(sim.particles());
  }
  const double surfaceError = track.surfaceError();
  const double worstPressure = track.worstSlab();
  // How still the tank is at the end: the fluid's RMS speed.
  const double rms = kurage::pipeline::rmsSpeed(sim.particles(), 0);
  std::printf("surface %.2f %%, slabs %.2f %%, one-spacing layers %.2f %%, against the weight above %.2f %%, RMS %.2f m/s\n",
              100 * surfaceError, 100 * worstPressure, 100 * track.worstLayer(), 100 * track.worstSlabAgainstWeight(), rms);
  EXPECT_LT(rms, c.rmsSpeed);
  EXPECT_GT(track.slabs(), 5);
  EXPECT_LT(surfaceError, c.surfaceTolerance);
  EXPECT_LT(worstPressure, c.pressureTolerance);
}

INSTANTIATE_TEST_SUITE_P(Solvers, HydrostaticTank,
                         ::testing::Values(TankCase{"dfsph", 1.0f, false, false, 2.0, 5.0, 0.005, 0.065, 1.0},
                                           TankCase{"dfsph", 0.5f, false, false, 2.0, 5.0, 0.005, 0.065, 1.0},
                                           TankCase{"dfsph", 1.0f, true, false, 2.0, 5.0, 0.005, 0.065, 1.0},
                                           TankCase{"dfsph", 1.0f, false, true, 2.0, 5.0, 0.008, 0.02, 0.5},
                                           TankCase{"dfsph", 0.5f, false, true, 2.0, 5.0, 0.005, 0.025, 0.5},
                                           TankCase{"dfsph", 1.0f, true, true, 2.0, 5.0, 0.005, 0.02, 0.5},
                                           TankCase{"dfsph", 0.5f, true, true, 2.0, 5.0, 0.005, 0.02, 0.5},
                                           TankCase{"wcsph", 1.0f, false, false, 2.0, 5.0, 0.03, 0.03, 0.3},
                                           TankCase{"wcsph", 0.5f, false, false, 2.0, 5.0, 0.03, 0.03, 0.4},
                                           TankCase{"wcsph", 1.0f, true, false, 2.0, 5.0, 0.03, 0.03, 0.3},
                                           TankCase{"iisph", 1.0f, false, false, 2.0, 5.0, 0.007, 0.05, 0.6},
                                           TankCase{"iisph", 0.5f, false, false, 2.0, 5.0, 0.007, 0.025, 0.3}),
                         [](const auto& info) {
                           return info.param.solver + (info.param.calm ? "_calm" : "") + (info.param.corrected ? "_corrected" : "") +
                                  (info.param.spacing < 1.0f ? "_half_metre" : "_one_metre");
                         });

// A hydrostatic start does not fall: over the first second the free surface moves by less than
// 1 % of the depth, with either solver and boundary particles; a lattice start falls further.
TEST(HydrostaticStart, TheStillTankDoesNotFallInItsFirstSecond) {
  for (const std::string solver : {"dfsph", "wcsph", "iisph"}) {
    Simulation sim(jellyfishTank(solver, 1.0f));
    const kurage::pipeline::HydrostaticTrack surface(sim.params(), 20.0);
    const double start = surface.freeSurface(sim.particles());
    double worst = 0.0;
    for (int k = 1; k <= 10; ++k) {
      sim.advanceTo(0.1 * k);
      worst = std::max(worst, std::fabs(surface.freeSurface(sim.particles()) - start));
    }
    EXPECT_LT(worst, 0.01 * start) << solver;  // measured 0.033 m (dfsph), 0.062 m (wcsph)
  }
}

// The still tank's volume over 30 s (fluid.packing, sim/packing.h): the jellyfish scene's water
// (DFSPH calm and corrected, boundary particles, hydrostatic start). On the simple cubic lattice
// the column rearranges into a denser packing and its free surface sinks; started on the relaxed
// packing, with the mass calibrated on it, the free surface (HydrostaticTrack::freeSurface, the
// interior's water per floor area) over the last 5 s stays within 0.05 m of where it started
// (0.25 % of the 20 m). At 0.5 m the same column stands on a quarter of the floor (10 x 7 m, the
// 1 m tank's 20 x 14 columns): measured 0.001 m, against swings of +-0.02 m on the whole floor
// (docs/notebook/water-volume.md). The lattice start's drift is printed at 1 m, not asserted.
class StillTankVolume : public ::testing::TestWithParam<float> {};

namespace {
// |mean free surface over 25-30 s - free surface at t = 0|, m.
double thirtySecondDrift(SimParams p) {
  p.fluid.gradientCorrection = true;
  p.fluid.solver.as<DfsphParams>().divergenceSolve = DivergenceSolve::ConjugateGradient;
  p.fluid.solver.as<DfsphParams>().maxDivergenceError = 0.01f;
  Simulation sim(p);
  const kurage::pipeline::HydrostaticTrack track(sim.params(), 20.0);
  const double start = track.freeSurface(sim.particles());
  double sum = 0.0;
  int count = 0;
  for (int k = 1; k <= 60; ++k) {
    sim.advanceTo(0.5 * k);
    if (k > 50) {
      sum += track.freeSurface(sim.particles());
      ++count;
    }
  }
  const double drift = std::fabs(sum / count - start);
  std::printf("l = %g m, packing %s: free surface %.4f m at t = 0, %.4f m over 25-30 s\n", p.fluid.spacing,
              p.fluid.packing == StartPacking::Relaxed ? "relaxed" : "lattice", start, sum / count);
  return drift;
}
}  // namespace

TEST_P(StillTankVolume, TheRelaxedPackingKeepsTheSurfaceForThirtySeconds) {
  const float spacing = GetParam();
  SimParams p = jellyfishTank("dfsph", spacing);
  if (spacing < 1.0f) p = quarterFloor(p);
  p.fluid.packing = StartPacking::Relaxed;
  EXPECT_LT(thirtySecondDrift(p), 0.05);
  if (spacing == 1.0f) {
    p.fluid.packing = StartPacking::Lattice;
    std::printf("the lattice start drifts %.3f m\n", thirtySecondDrift(p));
  }
}

INSTANTIATE_TEST_SUITE_P(Spacings, StillTankVolume, ::testing::Values(1.0f, 0.5f), [](const auto& info) {
  return std::string(info.param < 1.0f ? "half_metre" : "one_metre");
});

// A caller's rounding can leave a sliver before the time it asks for. A study sampling every
// 0.01 s as a float stops at 4.9999999 s and is then asked for 5 s. Under DFSPH a step of 0.07 us
// there took the still tank's RMS speed from 0.65 to 16,000 m/s. A request shorter than
// time_step.min_step now moves the clock without a step (Simulation::advanceTo). Measured
// without that: a 10 us sliver gave 47 m/s at 1 s and 53 m/s at 1.1 s; 0.1 us stops the run.
TEST(Dfsph, ASliverBeforeTheRequestedTimeDoesNotKickTheFluid) {
  for (const double sliver : {1e-7, 5e-6}) {
    Simulation sim(jellyfishTank("dfsph", 1.0f));
    sim.advanceTo(1.0 - sliver);
    const double before = kurage::pipeline::rmsSpeed(sim.particles(), 0);
    sim.advanceTo(1.0);
    EXPECT_EQ(sim.time(), 1.0);
    const double at = kurage::pipeline::rmsSpeed(sim.particles(), 0);
    sim.advanceTo(1.1);
    const double after = kurage::pipeline::rmsSpeed(sim.particles(), 0);
    EXPECT_LT(at, 2.0 * before + 0.05) << sliver;
    EXPECT_LT(after, 1.0) << sliver;  // the default tank reads 0.2-0.4 m/s here
  }
}

// The pressure push is pairwise antisymmetric, with the gradient correction too: the pair (i, j)
// exchanges m_i m_j (k_i L_i + k_j L_j) grad W_ij, so the solves conserve the fluid's momentum.
// A blob squeezed in free space (no gravity, no viscosity, no wall within reach) keeps its total
// momentum. This checks the corrected push's packed form (M_i x_i - Y_i, dfsph.h) against the
// pairwise sum it replaces: a wrong entry in its packing breaks the antisymmetry (L02 and L12
// swapped: the momentum moved by 5,000 kg m/s of 540,000; measured drift 0.1 / 0.6 kg m/s).
TEST(Dfsph, TheSolvesConserveMomentumWithAndWithoutTheGradientCorrection) {
  for (const bool corrected : {false, true}) {
    SimParams p;
    p.fluid.spacing = 1.0f;
    p.fluid.supportRadius = 2.0f;
    p.fluid.solver = "dfsph";
    p.fluid.pressureForce = PressureForce::Monaghan1992;
    p.fluid.kinematicViscosity = 0.0f;
    p.fluid.gradientCorrection = corrected;
    p.gravity = Eigen::Vector3f::Zero();
    p.container.max = Eigen::Vector3f(30, 30, 30);
    p.container.wallDensity = WallDensity::BoundaryParticles;
    p.fluidBlocks.push_back({Eigen::Vector3f(10, 10, 10), Eigen::Vector3f(20, 20, 20)});
    Simulation sim(p);
    ParticleSet& s = sim.particles();
    Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
    double scale = 0.0;  // sum of m |v|
    for (size_t i = 0; i < s.size(); ++i) {
      // Converging towards the centre, with a swirl and a drift, so every pair is pushed.
      const Eigen::Vector3f x(s.x[i] - 15.0f, s.y[i] - 15.0f, s.z[i] - 15.0f);
      const Eigen::Vector3f v = -0.8f * x + Eigen::Vector3f(-0.3f * x.y(), 0.3f * x.x(), 0.0f) + Eigen::Vector3f(0.5f, 0.2f, -0.1f);
      s.vx[i] = v.x(); s.vy[i] = v.y(); s.vz[i] = v.z();
      momentum += double(s.mass[i]) * v.cast<double>();
      scale += double(s.mass[i]) * double(v.norm());
    }
    sim.advanceTo(0.2);
    Eigen::Vector3d after = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < s.size(); ++i) after += double(s.mass[i]) * Eigen::Vector3d(s.vx[i], s.vy[i], s.vz[i]);
    const DfsphStats& stats = kurage::test::dfsphStats(sim);
    ASSERT_GT(stats.steps, 3u);
    ASSERT_GT(stats.density.iterations, 0u) << "the squeeze must call on the pressure";
    EXPECT_LT((after - momentum).norm(), 1e-6 * scale) << (corrected ? "corrected" : "plain");
  }
}

// Determinism: the solvers' error sums reduce in a fixed order, so 1 and 2 threads agree bit for
// bit: DFSPH with either divergence solve and with the gradient correction, and IISPH.
TEST(IncompressibleSolvers, OneAndTwoThreadsGiveIdenticalParticles) {
  auto run = [](int threads, const std::string& solver, const nlohmann::json& keys, bool corrected = false) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    SimParams p = jellyfishTank(solver, 1.0f, InitialState::Lattice);
    p.fluidBlocks[0].max = Eigen::Vector3f(8, 14, 16);  // a dam break in the tank
    kurage::test::setSolverKeys(p.fluid, keys);
    p.fluid.gradientCorrection = corrected;
    Simulation sim(p);
    sim.advanceTo(1.0);
    return kurage::test::positionsById(sim.particles());
  };
  const nlohmann::json none = nlohmann::json::object(), cg = {{"divergence_solve", "cg"}};
  const auto one = run(1, "dfsph", none), two = run(2, "dfsph", none);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_TRUE(one == two);
  const auto cgOne = run(1, "dfsph", cg), cgTwo = run(2, "dfsph", cg);
  ASSERT_EQ(cgOne.size(), cgTwo.size());
  EXPECT_TRUE(cgOne == cgTwo) << "conjugate gradients (its dot products reduce in a fixed order too)";
  const auto gcOne = run(1, "dfsph", none, true), gcTwo = run(2, "dfsph", none, true);
  ASSERT_EQ(gcOne.size(), gcTwo.size());
  EXPECT_TRUE(gcOne == gcTwo) << "gradient correction";
  EXPECT_FALSE(gcOne == one) << "the correction changes the run";
  const auto iisphOne = run(1, "iisph", none), iisphTwo = run(2, "iisph", none);
  ASSERT_EQ(iisphOne.size(), iisphTwo.size());
  EXPECT_TRUE(iisphOne == iisphTwo) << "iisph";
  EXPECT_FALSE(iisphOne == one) << "another solver, another run";
}

// The divergence solve by conjugate gradients meets the same tolerance as the Jacobi one on the
// dam break in the tank, in far fewer iterations (bench sim's dam break: 4.9 -> 2.3 a step); with
// the gradient correction too, whose push must stay the transpose of its density rate for
// conjugate gradients to work (dfsph.h).
TEST(Dfsph, ConjugateGradientDivergenceSolveNeedsFewerIterations) {
  auto run = [](DivergenceSolve method, bool corrected = false) {
    SimParams p = jellyfishTank("dfsph", 1.0f, InitialState::Lattice);
    p.fluidBlocks[0].max = Eigen::Vector3f(8, 14, 16);
    p.fluid.solver.as<DfsphParams>().divergenceSolve = method;
    p.fluid.gradientCorrection = corrected;
    Simulation sim(p);
    sim.advanceTo(2.0);
    const DfsphStats& s = kurage::test::dfsphStats(sim);
    EXPECT_EQ(s.divergence.capHits, 0u);
    EXPECT_LE(s.divergence.lastError, 0.001 + 1e-9);
    return double(s.divergence.iterations) / double(s.steps);
  };
  const double jacobi = run(DivergenceSolve::Jacobi), cg = run(DivergenceSolve::ConjugateGradient);
  EXPECT_LT(cg, 0.75 * jacobi);
  const double jacobiCorrected = run(DivergenceSolve::Jacobi, true), cgCorrected = run(DivergenceSolve::ConjugateGradient, true);
  EXPECT_LT(cgCorrected, 0.75 * jacobiCorrected);
}

// The solver reaches its tolerance on a dam break and reports its iterations (an unreachable
// tolerance: Solvers/IncompressibleHardCases.UnreachableToleranceHitsTheCapAndRunsOn, label stability).
TEST(Dfsph, ReachesItsToleranceOnADamBreak) {
  SimParams p = jellyfishTank("dfsph", 1.0f, InitialState::Lattice);
  p.fluidBlocks[0].max = Eigen::Vector3f(8, 14, 16);
  Simulation sim(p);
  sim.advanceTo(2.0);
  const DfsphStats& s = kurage::test::dfsphStats(sim);
  EXPECT_GT(s.density.iterations, 0u);
  EXPECT_EQ(s.density.capHits, 0u);
  EXPECT_EQ(s.divergence.capHits, 0u);
  EXPECT_LE(s.density.maxError, 0.001 + 1e-9);
}

// A wider support (h = 3 l, 92 neighbours on the lattice) keeps h = 2 l's relaxation: with its
// own lattice's count the Jacobi iteration diverged and this run stopped with a simulation error
// (Martin & Moyce went non-finite within 0.08 s at h = 2.5 and 3 l).
TEST(Dfsph, AWiderSupportKeepsTheSolveConvergent) {
  SimParams p = jellyfishTank("dfsph", 1.0f, InitialState::Lattice);
  p.fluid.supportRadius = 3.0f;
  p.fluidBlocks[0].max = Eigen::Vector3f(8, 14, 16);
  Simulation sim(p);
  ASSERT_NO_THROW(sim.advanceTo(1.0));
  const DfsphStats& s = kurage::test::dfsphStats(sim);
  EXPECT_EQ(s.density.capHits, 0u);
  EXPECT_LE(s.density.maxError, 0.001 + 1e-9);
}

// The pressure step bound (sim/time_step.h): in the jellyfish's tank at 0.5 m spacing, 20 m of
// water, it is the active bound at rest, 0.4 l / sqrt(|g| H) with H the fluid's extent (the tank
// blew up from its floor at the 0.05 s largest step without it; the settled-tank test above runs
// that tank for 5 s). WCSPH's CFL already covers it (its speed of sound is far above sqrt(g H)).
TEST(PressureStepBound, IsTheActiveBoundInADeepStillTank) {
  Simulation sim(jellyfishTank("dfsph", 0.5f));
  sim.advanceTo(0.2);
  const auto& counts = sim.stats().boundCounts;
  EXPECT_EQ(counts[size_t(StepBound::Pressure)], sim.stats().steps) << "every step";
  const StepLimit rest = sim.stabilityLimit();
  ASSERT_EQ(rest.bound, StepBound::Pressure);
  EXPECT_NEAR(rest.step, 0.4 * 0.5 / std::sqrt(6.0 * 19.75), 0.002) << "fluid from z = 0.25 to 20 - 0.25 m";
  Simulation wcsph(jellyfishTank("wcsph", 0.5f));
  EXPECT_NE(wcsph.stabilityLimit().bound, StepBound::Pressure);
}
