// The SPH fluid of SPEC §1 (sim/): mass calibration, symmetric pressure, walls, exact frame
// times, determinism and independence of simulations.
#include "sim/fluid.h"
#include "sim/packing.h"
#include "sim/simulation.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

using namespace kurage::sim;

namespace {

SimParams tank(float size = 8.0f) {
  SimParams p;
  p.container.min = Eigen::Vector3f(0, 0, 0);
  p.container.max = Eigen::Vector3f(2 * size, size, 2 * size);
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(size, size, size)});
  return p;
}

size_t nearest(const ParticleSet& p, const Eigen::Vector3f& target) {
  size_t best = 0;
  float bestD = 1e30f;
  for (size_t i = 0; i < p.size(); ++i) {
    const float d = (Eigen::Vector3f(p.x[i], p.y[i], p.z[i]) - target).squaredNorm();
    if (d < bestD) { bestD = d; best = i; }
  }
  return best;
}

bool sameState(const ParticleSet& a, const ParticleSet& b) {
  auto same = [](const std::vector<float>& u, const std::vector<float>& v) {
    return u.size() == v.size() && std::memcmp(u.data(), v.data(), u.size() * sizeof(float)) == 0;
  };
  return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z) && same(a.vx, b.vx) && same(a.vy, b.vy) &&
         same(a.vz, b.vz) && a.id == b.id;
}

}  // namespace

TEST(FluidMass, InteriorParticleHasRestDensity) {
  for (float h : {1.5f, 2.0f}) {
    SimParams p = tank();
    p.fluid.supportRadius = h;
    p.fluid.restDensity = 1100.0f;
    Simulation sim(p);
    sim.step(0.0f);  // sorts and computes densities without moving anything
    const size_t centre = nearest(sim.particles(), Eigen::Vector3f(4, 4, 4));
    EXPECT_NEAR(sim.particles().density[centre], 1100.0f, 1100.0f * 1e-5f) << "h = " << h;
    EXPECT_NEAR(sim.fluidParticleMass(), calibratedParticleMass(1.0f, h, 1100.0f), 1e-3f);
  }
}

TEST(FluidPressure, PairForcesAreEqualAndOppositeAndViscosityDamps) {
  SimParams p;
  p.container.max = Eigen::Vector3f(10, 10, 10);
  p.gravity.setZero();
  Simulation sim(p);
  ParticleSet& s = sim.particles();
  const float m = sim.fluidParticleMass();
  // A low rest density gives both particles a positive pressure: they must push apart.
  s.add(5.0f, 5.0f, 5.0f, 0.1f, 0, 0, 10.0f, m, 0, 0);
  s.add(5.6f, 5.3f, 5.1f, -0.2f, 0.05f, 0, 10.0f, m, 1, 0);
  sim.step(0.0f);
  const ParticleSet& r = sim.particles();
  ASSERT_EQ(r.size(), 2u);
  const size_t a = r.id[0] == 0 ? 0 : 1, b = 1 - a;
  const Eigen::Vector3f accA(r.ax[a], r.ay[a], r.az[a]), accB(r.ax[b], r.ay[b], r.az[b]);
  EXPECT_LT((accA + accB).norm(), 1e-5f * accA.norm());
  const Eigen::Vector3f rAB(r.x[a] - r.x[b], r.y[a] - r.y[b], r.z[a] - r.z[b]);
  EXPECT_GT(accA.dot(rAB), 0.0f) << "pressure pushes a away from b";
  // With the rest density of water the pair is far below rest: the clamped pressure is zero and
  // only viscosity acts, which shrinks the relative velocity.
  Simulation sim2(p);
  sim2.particles().add(5.0f, 5.0f, 5.0f, 0.1f, 0, 0, 1000.0f, m, 0, 0);
  sim2.particles().add(5.6f, 5.3f, 5.1f, -0.2f, 0.05f, 0, 1000.0f, m, 1, 0);
  sim2.step(0.0f);
  const ParticleSet& q = sim2.particles();
  const size_t c = q.id[0] == 0 ? 0 : 1, d = 1 - c;
  const Eigen::Vector3f relVel(q.vx[c] - q.vx[d], q.vy[c] - q.vy[d], q.vz[c] - q.vz[d]);
  const Eigen::Vector3f relAcc(q.ax[c] - q.ax[d], q.ay[c] - q.ay[d], q.az[c] - q.az[d]);
  EXPECT_LT(relAcc.dot(relVel), 0.0f);
  EXPECT_EQ(q.pressure[0], 0.0f);
}

TEST(FluidPressure, CoincidentParticlesSeparateSymmetrically) {
  SimParams p;
  p.container.max = Eigen::Vector3f(10, 10, 10);
  p.gravity.setZero();
  Simulation sim(p);
  const float m = sim.fluidParticleMass();
  sim.particles().add(5, 5, 5, 0, 0, 0, 10.0f, m, 0, 0);  // low rest density: positive pressure
  sim.particles().add(5, 5, 5, 0, 0, 0, 10.0f, m, 1, 0);
  sim.step(0.01f);
  const ParticleSet& r = sim.particles();
  EXPECT_TRUE(std::isfinite(r.x[0]) && std::isfinite(r.x[1]));
  EXPECT_NE(r.x[0], r.x[1]);
  EXPECT_NEAR(r.x[0] + r.x[1], 10.0f, 1e-5f);
}

TEST(Walls, NoSlipStopsAndFreeSlipKeepsTangentialVelocity) {
  for (WallSlip mode : {WallSlip::NoSlip, WallSlip::FreeSlip}) {
    SimParams p;
    p.container.max = Eigen::Vector3f(10, 10, 10);
    p.container.walls = mode;
    p.gravity.setZero();
    Simulation sim(p);
    sim.particles().add(5, 5, 0.05f, 1.0f, 0, -10.0f, 1000.0f, sim.fluidParticleMass(), 0, 0);
    sim.step(0.01f);
    const ParticleSet& r = sim.particles();
    EXPECT_EQ(r.z[0], 0.0f) << "put back onto the wall";
    EXPECT_EQ(r.vz[0], 0.0f);
    if (mode == WallSlip::NoSlip) EXPECT_EQ(r.vx[0], 0.0f);
    else EXPECT_GT(r.vx[0], 0.9f);
  }
}

TEST(TimeStepping, FramesLandExactlyOnOutputTimes) {
  Simulation sim(tank(6.0f));
  // Frames 0.13 s apart with a maximum step of 0.05 s: every frame ends on a shortened step.
  for (int f = 1; f <= 4; ++f) {
    const double t = f * 0.13;
    sim.advanceTo(t);
    EXPECT_EQ(sim.time(), t);
  }
  EXPECT_GE(sim.stats().steps, 12u);
  EXPECT_LT(sim.stats().minStep, sim.stats().maxStep);
  EXPECT_LE(sim.stats().maxStep, sim.params().timeStep.maxStep);
  EXPECT_LE(sim.stats().minStep, sim.stats().maxStep);
}

TEST(TimeStepping, ContainerHoldsEveryParticleAndCountIsConserved) {
  Simulation sim(tank(6.0f));
  const size_t count = sim.particles().size();
  sim.advanceTo(1.5);
  const ParticleSet& p = sim.particles();
  ASSERT_EQ(p.size(), count);
  const auto& box = sim.params().container;
  for (size_t i = 0; i < p.size(); ++i) {
    ASSERT_TRUE(p.x[i] >= box.min.x() && p.x[i] <= box.max.x());
    ASSERT_TRUE(p.y[i] >= box.min.y() && p.y[i] <= box.max.y());
    ASSERT_TRUE(p.z[i] >= box.min.z() && p.z[i] <= box.max.z());
  }
}

TEST(Determinism, IndependentSimulationsInOneProcessAgree) {
  Simulation a(tank(5.0f)), b(tank(5.0f));
  for (int f = 1; f <= 6; ++f) {
    a.advanceTo(f * 0.05);
    b.advanceTo(f * 0.05);
  }
  EXPECT_TRUE(sameState(a.particles(), b.particles()));
}

TEST(Determinism, BitIdenticalWithOneAndTwoThreads) {
  auto runWith = [](size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Simulation sim(tank(10.0f));
    sim.advanceTo(0.5);
    return sim.particles();
  };
  const ParticleSet one = runWith(1), two = runWith(2);
  EXPECT_TRUE(sameState(one, two));
}

// The cubic spline's density pass sifts candidates into a stack buffer of 1,024 and a per-chunk
// buffer past that (fluid.cpp): both give the brute-force sum and neighbour set, here with a
// clump of 1,500 particles inside one cell beside a sparse cloud, at random positions (the sift
// writes every group of four candidates, neighbours or not). Its packed kernel sums give the
// scalar loop's floats exactly.
TEST(DensityPass, CubicSplineMatchesBruteForceAlsoPastTheStackBuffer) {
  const CubicSplineKernel kernel(1.0f);
  ParticleSet particles;
  uint32_t state = 12345u;
  const auto uniform = [&]() {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) * 0x1p-24f;
  };
  for (int k = 0; k < 1500; ++k)
    particles.add(2.2f + 0.5f * uniform(), 2.2f + 0.5f * uniform(), 2.2f + 0.5f * uniform(), 0, 0, 0, 1000.0f, 0.01f, k, 0);
  for (int k = 0; k < 400; ++k)
    particles.add(5.0f * uniform(), 5.0f * uniform(), 5.0f * uniform(), 0, 0, 0, 1000.0f, 0.01f, 1500 + k, 0);
  NeighborGrid grid;
  grid.configure(Eigen::Vector3f::Zero(), Eigen::Vector3f::Constant(5.0f), kernel.h);
  std::vector<uint32_t> order;
  grid.sort(particles.x.data(), particles.y.data(), particles.z.data(), particles.size(), order);
  ParticleSet scratch;
  particles.permute(order, scratch);
  NeighborLists neighbors;
  computeDensity(grid, particles, kernel, neighbors, WallSums{});
  size_t pastStack = 0;
  for (size_t i = 0; i < particles.size(); ++i) {
    double expected = particles.mass[i] * kernel.fromSquared(0.0f);
    std::vector<uint32_t> within;
    for (size_t j = 0; j < particles.size(); ++j) {
      const float dx = particles.x[j] - particles.x[i], dy = particles.y[j] - particles.y[i],
                  dz = particles.z[j] - particles.z[i];
      const float r2 = dx * dx + dy * dy + dz * dz;
      if (j == i || !(r2 < kernel.h2)) continue;
      within.push_back(uint32_t(j));
      expected += particles.mass[j] * kernel.fromSquared(r2);
    }
    std::vector<uint32_t> found(neighbors.begin(i), neighbors.end(i));
    // The sums one neighbour at a time in the list's order, with the scalar kernel: the pass
    // takes W and W'(r)/r four neighbours at a time and must give the same floats.
    float inOrder = particles.mass[i] * kernel.fromSquared(0.0f);
    const float* slope = neighbors.slopes(i / NeighborLists::kChunk).data() + neighbors.offset(i);
    size_t slopesDiffering = 0;
    for (size_t k = 0; k < found.size(); ++k) {
      const uint32_t j = found[k];
      const float dx = particles.x[j] - particles.x[i], dy = particles.y[j] - particles.y[i],
                  dz = particles.z[j] - particles.z[i];
      const float r = std::sqrt(dx * dx + dy * dy + dz * dz);
      inOrder += particles.mass[j] * kernel(r);
      const float expectedSlope = r > 1e-6f * kernel.h ? kernel.derivative(r) / r : 0.0f;
      slopesDiffering += slope[k] != expectedSlope ? 1 : 0;
    }
#if !defined(__FMA__)  // (KURAGE_NATIVE's FMA may contract the packed and the scalar arithmetic differently)
    EXPECT_EQ(particles.density[i], inOrder) << "particle " << i;
    EXPECT_EQ(slopesDiffering, 0u) << "particle " << i;
#endif
    std::sort(found.begin(), found.end());
    ASSERT_EQ(found, within) << "particle " << i;
    EXPECT_NEAR(particles.density[i], expected, 1e-4 * expected) << "particle " << i;
    pastStack += within.size() > 1024 ? 1 : 0;
  }
  EXPECT_GE(pastStack, 1000u) << "the clump's particles have more candidates than the stack buffer";
}

// The relaxed packing (fluid.packing "relaxed", sim/packing.h): the tile is a glass whose kernel
// sum lies below the simple cubic lattice's (0.1-1 %: the volume a lattice start loses as it
// rearranges), the same on every call, its points inside it; tiled over a block it holds the
// block's volume in particles of l^3 (to within its part-filled border), and the mass calibrated
// on it gives the tile's mean particle rho0.
TEST(RelaxedPacking, TheTileIsADeterministicGlassBelowTheLatticesKernelSum) {
  const PackingTile tile = relaxedTile(2.0f, DensityKernel::CubicSpline);
  ASSERT_EQ(tile.cells, 8);
  ASSERT_EQ(tile.points.size(), size_t(8 * 8 * 8));
  for (const Eigen::Vector3f& q : tile.points) {
    ASSERT_TRUE((q.array() >= 0.0f).all() && (q.array() < 8.0f).all());
  }
  const double lowered = 1.0 - tile.kernelSum / tile.latticeKernelSum;
  EXPECT_GT(lowered, 0.001);
  EXPECT_LT(lowered, 0.01);
  const PackingTile again = relaxedTile(2.0f, DensityKernel::CubicSpline);
  EXPECT_EQ(std::memcmp(again.points.data(), tile.points.data(), tile.points.size() * sizeof(Eigen::Vector3f)), 0);
  // A 10 x 9 x 8 m block at l = 0.5: 5760 lattice points; the tiled block holds as many within 1 %.
  const FluidBlock block{Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(11, 11, 11)};
  ASSERT_TRUE(holdsTile(block, 0.5f, 2.0f));
  EXPECT_FALSE(holdsTile({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(10, 10, 3.5f)}, 0.5f, 2.0f)) << "a slab";
  const std::vector<Eigen::Vector3f> points = tiledPoints(block, 0.5f, tile);
  EXPECT_NEAR(double(points.size()), 5760.0, 57.6);
  for (const Eigen::Vector3f& q : points) {
    ASSERT_TRUE((q.array() >= block.min.array()).all() && (q.array() < block.max.array()).all());
  }
  const float mass = tileParticleMass(tile, 0.5f, 1000.0f);
  EXPECT_NEAR(double(mass) * tile.kernelSum / 0.125, 1000.0, 1e-3);
  EXPECT_GT(mass, calibratedParticleMass(0.5f, 1.0f, 1000.0f, DensityKernel::CubicSpline));
}

// The simulation starts a block that holds a tile on it, and one thinner than the tile on the
// lattice, both with the tile's mass; the paper's poly6 density sum refuses it.
TEST(RelaxedPacking, SimulationStartsBlocksOnTheTileAndRefusesPoly6) {
  SimParams p;
  p.fluid.spacing = 0.5f;
  p.fluid.supportRadius = 2.0f;
  p.fluid.solver = "dfsph";
  p.fluid.packing = StartPacking::Relaxed;
  p.container.max = Eigen::Vector3f(10, 10, 10);
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(5, 5, 5)});
  p.fluidBlocks.push_back({Eigen::Vector3f(6, 6, 0), Eigen::Vector3f(10, 10, 1)});
  const Simulation sim(p);
  const PackingTile tile = relaxedTile(2.0f, DensityKernel::CubicSpline);
  EXPECT_FLOAT_EQ(sim.fluidParticleMass(), tileParticleMass(tile, 0.5f, 1000.0f));
  size_t offLattice = 0, slab = 0;
  const ParticleSet& s = sim.particles();
  for (size_t i = 0; i < s.size(); ++i) {
    if (s.x[i] >= 6.0f) {
      ++slab;
      continue;
    }
    const float fx = s.x[i] / 0.5f - std::floor(s.x[i] / 0.5f);
    offLattice += std::fabs(fx - 0.5f) > 1e-3f;
  }
  EXPECT_EQ(slab, size_t(8 * 8 * 2)) << "the slab on the lattice";
  EXPECT_GT(offLattice, (s.size() - slab) / 2) << "the block on the tile";
  SimParams wcsph = p;
  wcsph.fluid.solver = "wcsph";
  wcsph.fluid.kernel = SphKernel::Mueller2003;
  EXPECT_THROW(Simulation{wcsph}, std::invalid_argument);
}
