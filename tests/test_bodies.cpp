// Telescopic bodies in the simulation (label `bodies`): the stretch ratio, the dampers, muscles,
// the collision loop and its cap, pins, Archimedes' principle, the paper's box sequence (Fig. 3)
// and membrane (Fig. 2), and which stages a scene runs.
#include "pipeline/io/files.h"
#include "pipeline/analysis/body_measures.h"
#include "pipeline/scene.h"
#include "sim/body_shapes.h"
#include "sim/simulation.h"
#include "sim_util.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

using namespace kurage;
using namespace kurage::sim;
using kurage::test::boxBody;
using kurage::test::kineticEnergy;
using kurage::test::positionsById;

namespace {

// A body-only world without gravity.
SimParams emptyWorld() {
  SimParams p;
  p.gravity = Eigen::Vector3f::Zero();
  p.container.min = Eigen::Vector3f(0, 0, 0);
  p.container.max = Eigen::Vector3f(12, 12, 12);
  return p;
}

// A bell: a two-layer shell of inner radius 3 m, opening 75 degrees.
BodyParams shellBody(const Eigen::Vector3f& center, const Eigen::Vector3f& axis) {
  BodyParams b;
  b.name = "bell";
  b.shape = BodyShape::Shell;
  b.center = center;
  b.axis = axis;
  b.innerRadius = 3.0f;
  b.openingAngle = 75.0f;
  b.layers = 2;
  return b;
}

// scenes/box.json's body (k = 10000 N/m, d = 15000, connection radius 2.4 m) over the given box.
BodyParams boxSceneBody(const Eigen::Vector3f& min, const Eigen::Vector3f& max, float specificGravity) {
  BodyParams b = boxBody(min, max);
  b.specificGravity = specificGravity;
  b.stiffness = 10000.0f;
  b.damping = 15000.0f;
  b.connectionRadius = 2.4f;
  return b;
}

// The free surface height: over 1 m columns farther than `clear` from (cx, cy), the mean height
// of the top fluid particle, plus half a spacing (a particle's centre lies half a spacing below
// the surface it bounds).
double freeSurface(const ParticleSet& p, double cx, double cy, double clear, float spacing) {
  std::map<std::pair<int, int>, float> top;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == 0 && std::hypot(p.x[i] - cx, p.y[i] - cy) > clear) {
      const auto key = std::make_pair(int(std::floor(p.x[i])), int(std::floor(p.y[i])));
      const auto it = top.find(key);
      if (it == top.end() || it->second < p.z[i]) top[key] = p.z[i];
    }
  double sum = 0.0;
  for (const auto& [key, z] : top) sum += z;
  return top.empty() ? 0.0 : sum / double(top.size()) + 0.5 * spacing;
}

// Submerged fraction: the share of the body's particles whose centre lies below the free surface.
double submergedFraction(const ParticleSet& p, float spacing) {
  const pipeline::KindExtent e = pipeline::kindExtent(p, 1);
  const double surface = freeSurface(p, e.centre.x(), e.centre.y(), 3.0, spacing);
  size_t below = 0;
  for (size_t i = 0; i < p.size(); ++i) below += p.kind[i] == 1 && p.z[i] < surface;
  return double(below) / double(e.count);
}

pipeline::Scene sceneFile(const char* name) { return pipeline::loadScene(test::sourceDir() / "scenes" / name); }

// A scene file as the issue-13 tests run it under DFSPH: boundary-particle walls, hydrostatic start.
pipeline::Scene sceneUnderDfsph(const char* name) {
  pipeline::Scene s = sceneFile(name);
  s.sim.fluid.solver = "dfsph";
  s.sim.container.wallDensity = WallDensity::BoundaryParticles;
  s.sim.fluid.initialState = InitialState::Hydrostatic;
  return s;
}

}  // namespace

TEST(LengthRatio, IsOneAtRestAndOneOverSWhenScaledByS) {
  SimParams p = emptyWorld();
  p.bodies.push_back(boxBody({2, 2, 2}, {5, 5, 5}));
  Simulation sim(p);
  const SpringNetwork network = [&] {
    std::vector<Eigen::Vector3f> points;
    std::vector<int64_t> ids;
    const ParticleSet& s = sim.particles();
    for (size_t i = 0; i < s.size(); ++i) {
      points.emplace_back(s.x[i], s.y[i], s.z[i]);
      ids.push_back(s.id[i]);
    }
    return SpringNetwork::connect(points, ids, p.bodies[0].connectionRadius * p.fluid.spacing);
  }();
  ParticleSet s = sim.particles();
  std::vector<uint32_t> index;
  indexParticlesById(s, index);
  for (size_t i = 0; i < s.size(); ++i) EXPECT_EQ(lengthRatio(network, s, index, i), 1.0f) << "at rest";
  for (const float scale : {0.5f, 1.3f, 2.0f}) {
    ParticleSet scaled = sim.particles();
    for (size_t i = 0; i < scaled.size(); ++i) {
      scaled.x[i] = 3.5f + scale * (scaled.x[i] - 3.5f);
      scaled.y[i] = 3.5f + scale * (scaled.y[i] - 3.5f);
      scaled.z[i] = 3.5f + scale * (scaled.z[i] - 3.5f);
    }
    for (size_t i = 0; i < scaled.size(); ++i) EXPECT_NEAR(lengthRatio(network, scaled, index, i), 1.0f / scale, 1e-6f);
  }
}

// The premise of `telescopic_measure`: a ring muscle shortens the margin's springs along the ring
// while the springs across the wall keep its thickness, and the paper's (8) reads that as lost
// volume (L^leng > 1: a heavier margin); `stretch_only` leaves a shortened particle's rest
// density and follows a stretch exactly as (8) does.
TEST(LengthRatio, ARingContractionReadsAsLostVolumeOnlyUnderTheIsotropicMeasure) {
  SimParams p = emptyWorld();
  p.bodies.push_back(shellBody({6, 6, 3}, {0, 0, 1}));
  Simulation sim(p);
  const ParticleSet& rest = sim.particles();
  std::vector<Eigen::Vector3f> points;
  std::vector<int64_t> ids;
  for (size_t i = 0; i < rest.size(); ++i) {
    points.emplace_back(rest.x[i], rest.y[i], rest.z[i]);
    ids.push_back(rest.id[i]);
  }
  const SpringNetwork network = SpringNetwork::connect(points, ids, p.bodies[0].connectionRadius * p.fluid.spacing);
  std::vector<uint32_t> index;
  indexParticlesById(rest, index);
  for (const float scale : {0.8f, 1.25f}) {
    // Every particle's distance from the axis scaled (a ring contraction or widening), heights kept.
    ParticleSet ring = rest;
    for (size_t i = 0; i < ring.size(); ++i) {
      ring.x[i] = 6.0f + scale * (ring.x[i] - 6.0f);
      ring.y[i] = 6.0f + scale * (ring.y[i] - 6.0f);
    }
    size_t margin = 0;
    for (size_t i = 0; i < ring.size(); ++i) {
      if (std::hypot(rest.x[i] - 6.0f, rest.y[i] - 6.0f) < 2.0f) continue;  // the flanks, not the apex
      ++margin;
      const float leng = lengthRatio(network, ring, index, i);
      const float isotropic = telescopicLengthRatio(TelescopicMeasure::Isotropic, leng);
      const float stretchOnly = telescopicLengthRatio(TelescopicMeasure::StretchOnly, leng);
      if (scale < 1.0f) {
        EXPECT_GT(isotropic, 1.02f) << "a ring contraction reads as lost volume under (8)";
        EXPECT_EQ(stretchOnly, 1.0f) << "and as none under stretch_only";
      } else {
        EXPECT_LT(isotropic, 0.98f) << "a widening reads as a stretch";
        EXPECT_EQ(stretchOnly, isotropic) << "which stretch_only follows as (8) does";
      }
    }
    EXPECT_GT(margin, size_t(50));
  }
}

TEST(ImplicitDamper, NeverAddsEnergyAndLetsABodyFallFreely) {
  // Two particles joined by a spring, stretched, with a damper 1000 times the paper's: the explicit
  // damper needs dt < m / (2 d) = 0.005 s here. The implicit one never adds energy, even at 4 times
  // that step (x = d (1/m_i + 1/m_q) dt = 4); at x = 1 the pair also creeps back to its rest length
  // as the overdamped spring does (time constant d / k = 1 s). At x >> 1 the split (forces, then
  // dampers) creeps too slowly; the spring step bound keeps x below about 2 zeta sqrt(2 / n)
  // (docs/design/physics.md).
  for (const float dt : {0.02f, 0.005f}) {
    ParticleSet p;
    p.add(0, 0, 0, 0, 0, 0, 1000, 100, 0, 1);
    p.add(0.6f, 0, 0, 0, 0, 0, 1000, 100, 1, 1);
    const SpringNetwork net = SpringNetwork::fromPairs({{0, 1, 0.5f, 0, 0}});
    const std::vector<SpringGroup> groups{{10000.0f, 10000.0f, true}};
    std::vector<uint32_t> index;
    indexParticlesById(p, index);
    std::vector<Eigen::Vector3f> scratch;
    auto energy = [&] {
      const double stretch = std::fabs(p.x[1] - p.x[0]) - 0.5;
      return kineticEnergy(p) + 0.5 * 10000.0 * stretch * stretch;
    };
    double last = energy();
    for (int step = 0; step < int(std::lround(20.0f / dt)); ++step) {
      std::fill(p.ax.begin(), p.ax.end(), 0.0f);
      addSpringAccelerations(net, groups, dt, p, index, scratch);
      for (size_t i = 0; i < 2; ++i) {
        p.vx[i] += p.ax[i] * dt;
        p.x[i] += p.vx[i] * dt;
      }
      const double e = energy();
      ASSERT_LE(e, last * (1.0 + 1e-5) + 1e-9) << "dt " << dt << ", step " << step;
      last = e;
    }
    if (dt == 0.005f) {
      EXPECT_NEAR(p.x[1] - p.x[0], 0.5f, 1e-3f) << "relaxed after 20 time constants";
    }
  }

  // A box in free fall keeps the acceleration of gravity: the dampers resist only relative motion.
  SimParams world = emptyWorld();
  world.gravity = Eigen::Vector3f(0, 0, -6);
  BodyParams box = boxBody({4, 4, 7}, {6, 6, 9});
  box.stiffness = 10000.0f;
  box.damping = 15000.0f;
  world.bodies.push_back(box);
  Simulation sim(world);
  sim.advanceTo(1.0);
  const pipeline::KindExtent e = pipeline::kindExtent(sim.particles(), 1);
  EXPECT_NEAR(e.centre.z(), 8.0 - 0.5 * 6.0 * 1.0, 0.05);  // z = z0 - g t^2 / 2
}

double radiusOfGyration(const ParticleSet& p) {
  const pipeline::KindExtent e = pipeline::kindExtent(p, 1);
  double sum = 0.0;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == 1) sum += (Eigen::Vector3d(p.x[i], p.y[i], p.z[i]) - e.centre).squaredNorm();
  return std::sqrt(sum / double(e.count));
}

TEST(Muscles, ContractingForceShrinksAndExpandingForceSwellsABody) {
  for (const float force : {1000.0f, -1000.0f}) {
    SimParams world = emptyWorld();
    BodyParams box = boxBody({4, 4, 4}, {7, 7, 7});
    box.stiffness = 10000.0f;
    box.damping = 15000.0f;
    MuscleParams muscle;
    muscle.force.keys = {{0.0f, 0.0f}, {0.5f, force}};
    box.muscles.push_back(muscle);
    world.bodies.push_back(box);
    Simulation sim(world);
    const double before = radiusOfGyration(sim.particles());
    sim.advanceTo(3.0);
    const double after = radiusOfGyration(sim.particles());
    double factor = 0.0;  // mean rest density factor L^dens
    for (size_t i = 0; i < sim.particles().size(); ++i) factor += sim.particles().restDensity[i] / box.restDensity();
    factor /= double(sim.particles().size());
    if (force > 0) {
      EXPECT_LT(after, 0.97 * before) << "contraction";
      EXPECT_GT(factor, 1.05) << "a contracted body is denser";
    } else {
      EXPECT_GT(after, 1.03 * before) << "expansion";
      EXPECT_LT(factor, 0.95) << "an expanded body is lighter";
    }
    EXPECT_TRUE(sim.stats().phaseRan(StepPhase::Muscles));
  }
}

namespace {

// Two one-particle bodies thrown at each other at 40 m/s closing speed: their closest approach
// over 0.4 s, and the loop's stats. `spread`: a third body far away in a 400 m container, so that
// the collision grid's dense cell table would be too large and cells are found by binary search.
std::pair<float, BodyStats> headOn(bool spread) {
  SimParams world = emptyWorld();
  world.bodies.push_back(boxBody({4, 5.75f, 5.75f}, {4.5f, 6.25f, 6.25f}));  // one particle each
  world.bodies.push_back(boxBody({7, 5.75f, 5.75f}, {7.5f, 6.25f, 6.25f}));
  world.bodies[1].name = "other";
  if (spread) {
    world.container.max = Eigen::Vector3f(400, 400, 400);
    world.bodies.push_back(boxBody({399, 399, 399}, {399.5f, 399.5f, 399.5f}));
    world.bodies[2].name = "far";
  }
  Simulation sim(world);
  ParticleSet& p = sim.particles();
  for (size_t i = 0; i < p.size(); ++i)
    if (p.x[i] < 100.0f) p.vx[i] = p.x[i] < 6.0f ? 20.0f : -20.0f;
  float closest = 1e9f;
  for (int step = 0; step < 40; ++step) {
    sim.step(0.01f);
    const ParticleSet& q = sim.particles();
    float x[2] = {0.0f, 0.0f};
    for (size_t i = 0; i < q.size(); ++i)
      if (q.id[i] < 2) x[q.id[i]] = q.x[i];
    closest = std::min(closest, std::fabs(x[0] - x[1]));
  }
  return {closest, sim.bodies()->stats()};
}

}  // namespace

TEST(Collisions, UnconnectedParticlesThrownAtEachOtherEndApart) {
  const float diameter = 0.5f * SimParams().fluid.spacing;
  for (bool spread : {false, true}) {
    const auto [closest, stats] = headOn(spread);
    EXPECT_GE(closest, diameter * (1.0f - 1e-3f)) << (spread ? "binary-search cells" : "cell table");
    EXPECT_GT(stats.collisionsResolved, 0u);
    EXPECT_EQ(stats.capHits, 0u);
  }
}

TEST(Collisions, LoopStopsAtTheCapAndReportsIt) {
  // Nine one-particle bodies piled almost on one spot: one pass cannot separate them.
  SimParams world = emptyWorld();
  for (int k = 0; k < 9; ++k) {
    const float x = 5.0f + 0.01f * float(k);
    world.bodies.push_back(boxBody({x, 5.75f, 5.75f}, {x + 0.5f, 6.25f, 6.25f}));
    world.bodies.back().name = std::string(1, char('a' + k));
  }
  world.collisions.maxPasses = 1;
  Simulation sim(world);
  sim.step(0.001f);
  EXPECT_EQ(sim.bodies()->stats().mostPasses, 1);
  EXPECT_EQ(sim.bodies()->stats().capHits, 1u);
  world.collisions.maxPasses = 1000;
  Simulation uncapped(world);
  uncapped.step(0.001f);
  EXPECT_GT(uncapped.bodies()->stats().mostPasses, 1);
  EXPECT_EQ(uncapped.bodies()->stats().capHits, 0u);
}

TEST(Pins, HoldTheirParticlesInPlace) {
  SimParams world = emptyWorld();
  world.gravity = Eigen::Vector3f(0, 0, -6);
  BodyParams sheet;
  sheet.name = "sheet";
  sheet.shape = BodyShape::Membrane;
  sheet.min = Eigen::Vector3f(2, 2, 8);
  sheet.max = Eigen::Vector3f(8, 8, 8);
  Selection rim;
  rim.kind = SelectionKind::Rim;
  sheet.pins.push_back(rim);
  world.bodies.push_back(sheet);
  Simulation sim(world);
  const ParticleSet start = sim.particles();
  sim.advanceTo(2.0);
  const ParticleSet& now = sim.particles();
  size_t pinned = 0;
  std::map<int64_t, Eigen::Vector3f> initial;
  for (size_t i = 0; i < start.size(); ++i) initial[start.id[i]] = Eigen::Vector3f(start.x[i], start.y[i], start.z[i]);
  for (size_t i = 0; i < now.size(); ++i) {
    const Eigen::Vector3f x0 = initial[now.id[i]];
    const bool rim = x0.x() < 2.5f || x0.x() > 7.5f || x0.y() < 2.5f || x0.y() > 7.5f;
    if (!rim) continue;
    ++pinned;
    EXPECT_EQ(Eigen::Vector3f(now.x[i], now.y[i], now.z[i]), x0);
  }
  EXPECT_EQ(pinned, 3u * 44u);  // the outer ring of a 12 x 12 sheet, 3 layers
  EXPECT_LT(pipeline::kindExtent(now, 1).min.z(), 7.0f) << "the middle sags under its weight";
}

TEST(Pins, AHeldBodyStaysWhereItWasBuiltUntilItsReleaseThenFalls) {
  SimParams world = emptyWorld();
  world.gravity = Eigen::Vector3f(0, 0, -6);
  world.bodies.push_back(boxBody({5, 5, 8}, {6, 6, 9}));
  world.bodies.back().holdUntil = 0.5f;
  world.timeStep.maxStep = 0.001f;  // symplectic Euler falls g dt t farther than the exact fall
  Simulation sim(world);
  const double z0 = pipeline::kindExtent(sim.particles(), 1).centre.z();
  sim.advanceTo(0.45);
  EXPECT_EQ(pipeline::kindExtent(sim.particles(), 1).centre.z(), z0) << "held";
  EXPECT_TRUE(sim.stats().phaseRan(StepPhase::Pins));
  sim.advanceTo(1.0);
  const double fallen = z0 - pipeline::kindExtent(sim.particles(), 1).centre.z();
  EXPECT_NEAR(fallen, 0.5 * 6.0 * 0.5 * 0.5, 0.05) << "free fall from the release at 0.5 s";
}

TEST(Parts, GiveTheirParticlesTheirOwnRestDensityAndMass) {
  // A two-layer shell of specific gravity 1 with a heavier margin ring (a 'rim' part one spacing
  // wide) and, overriding it where they overlap, a lighter half.
  SimParams world = emptyWorld();
  BodyParams bell = shellBody(Eigen::Vector3f(6, 6, 4), Eigen::Vector3f::UnitZ());
  bell.specificGravity = 1.0f;
  bell.rimWidth = 4.0f;  // a muscle band; the part names its own width
  BodyPart margin;
  margin.particles.kind = SelectionKind::Rim;
  margin.particles.width = 1.0f;
  margin.specificGravity = 2.0f;
  BodyPart half;
  half.particles.kind = SelectionKind::Region;
  half.particles.min = Eigen::Vector3f(0, 0, 0);
  half.particles.max = Eigen::Vector3f(6, 12, 12);
  half.specificGravity = 0.5f;
  bell.parts = {margin, half};
  world.bodies.push_back(bell);
  const BodyPoints points = bodyPoints(bell, world.fluid.spacing);
  Simulation sim(world);
  const ParticleSet& p = sim.particles();
  const float m = sim.bodies()->particleMass(0);
  ASSERT_EQ(p.size(), points.positions.size());
  size_t heavy = 0, light = 0, rings = 0;
  double gravity = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const size_t k = size_t(p.id[i]);  // body ids follow the order of bodyPoints
    const bool inHalf = points.positions[k].x() <= 6.0f;
    const bool onMargin = points.edge[k] < 0.5f;
    const float expected = inHalf ? 0.5f : onMargin ? 2.0f : 1.0f;
    EXPECT_FLOAT_EQ(p.restDensity[i], 1000.0f * expected) << "particle " << k;
    EXPECT_FLOAT_EQ(p.mass[i], m * expected) << "particle " << k;
    // What the caches' rest_density_factor divides by: 1 at rest for every part.
    EXPECT_FLOAT_EQ(sim.bodies()->initialRestDensity(p.id[i]), 1000.0f * expected) << "particle " << k;
    heavy += expected == 2.0f;
    light += expected == 0.5f;
    rings += points.edge[k] < 1.0f;
    gravity += expected;
  }
  EXPECT_GT(heavy, 10u);
  EXPECT_GT(light, p.size() / 3);
  EXPECT_GT(rings, heavy) << "the margin ring lies on both halves";
  EXPECT_NEAR(sim.bodies()->meanSpecificGravity(0), gravity / double(p.size()), 1e-5);
  // The band of a 'rim' selection: width 2 takes the last two rings, no width the body's rim_width.
  Selection two;
  two.kind = SelectionKind::Rim;
  two.width = 2.0f;
  Selection band;
  band.kind = SelectionKind::Rim;
  size_t inTwo = 0, inBand = 0;
  for (size_t k = 0; k < points.positions.size(); ++k) {
    inTwo += selected(two, points, k);
    inBand += selected(band, points, k);
    EXPECT_EQ(selected(two, points, k), points.edge[k] < 1.5f) << k;
    EXPECT_EQ(selected(band, points, k), points.edge[k] < 3.5f) << k;
  }
  EXPECT_LT(rings, inTwo);
  EXPECT_LT(inTwo, inBand);
}

namespace {

// Muscle force on the lower and the upper half of a shell's ring muscle (N, summed magnitudes),
// the shell tilted by `tilt` degrees about y, the muscle's righting gain `gain`.
// The body particles of `world` with only its muscles' accelerations at t = 0.
ParticleSet muscleAccelerations(const SimParams& world) {
  ParticleSet p;
  int64_t nextId = 0;
  BodySystem bodies(world, p, nextId);
  bodies.index(p);
  std::fill(p.ax.begin(), p.ax.end(), 0.0f);
  std::fill(p.ay.begin(), p.ay.end(), 0.0f);
  std::fill(p.az.begin(), p.az.end(), 0.0f);
  bodies.addMuscleForces(p, 0.0);
  return p;
}

std::pair<double, double> ringForces(float tilt, float gain) {
  SimParams world = emptyWorld();
  world.gravity = Eigen::Vector3f(0, 0, -6);
  const float a = tilt * 3.14159265f / 180.0f;
  BodyParams bell = shellBody(Eigen::Vector3f(6, 6, 5), Eigen::Vector3f(std::sin(a), 0, std::cos(a)));
  bell.rimWidth = 2.0f;
  MuscleParams ring;
  ring.springs.kind = SelectionKind::Rim;
  ring.force.keys = {{0.0f, 100.0f}};
  ring.righting = gain;
  bell.muscles.push_back(ring);
  world.bodies.push_back(bell);
  const ParticleSet p = muscleAccelerations(world);
  // The ring's centre height: the mean height of the particles the muscle pulls.
  double zRing = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < p.size(); ++i)
    if (p.ax[i] != 0.0f || p.ay[i] != 0.0f || p.az[i] != 0.0f) {
      zRing += p.z[i];
      ++n;
    }
  zRing /= double(n);
  double lower = 0.0, upper = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const double f = p.mass[i] * Eigen::Vector3d(p.ax[i], p.ay[i], p.az[i]).norm();
    (p.z[i] < zRing ? lower : upper) += f;
  }
  return {lower, upper};
}

}  // namespace

TEST(Muscles, RightingReflexContractsTheLowerSideOfATiltedRingHarder) {
  const auto [plainLow, plainHigh] = ringForces(20.0f, 0.0f);
  const auto [rightLow, rightHigh] = ringForces(20.0f, 1.0f);
  const auto [levelLow, levelHigh] = ringForces(0.0f, 1.0f);
  const auto [levelPlainLow, levelPlainHigh] = ringForces(0.0f, 0.0f);
  EXPECT_NEAR(plainLow / plainHigh, 1.0, 0.1) << "without the reflex both sides pull alike";
  // Gain 1 scales the lowest spring by 1 + sin 20 deg = 1.34 and the highest by 0.66.
  EXPECT_GT(rightLow / rightHigh, 1.3 * plainLow / plainHigh);
  EXPECT_NEAR(rightLow + rightHigh, plainLow + plainHigh, 0.05 * (plainLow + plainHigh)) << "on average unchanged";
  EXPECT_NEAR(levelLow, levelPlainLow, 1e-3 * levelPlainLow) << "a level ring is not steered";
  EXPECT_NEAR(levelHigh, levelPlainHigh, 1e-3 * levelPlainHigh);
}

TEST(Muscles, DepthReflexFadesTheForceThroughTheBandBelowTheCeiling) {
  // The scene's reflex (ceiling 16 m, band 4 m) on a bell whose centroid is at 5 m (the shell's
  // centre 3 m lower), then lifted: full force below 12 m, half at 14 m, none above 16 m.
  EXPECT_EQ(ceilingFactor(16.0f, 4.0f, 11.0), 1.0f);
  EXPECT_FLOAT_EQ(ceilingFactor(16.0f, 4.0f, 14.0), 0.5f);
  EXPECT_EQ(ceilingFactor(16.0f, 4.0f, 17.0), 0.0f);
  EXPECT_EQ(ceilingFactor(16.0f, 0.0f, 17.0), 1.0f) << "band 0: no reflex";
  auto totalForce = [](float lift) {
    SimParams world = emptyWorld();
    world.gravity = Eigen::Vector3f(0, 0, -6);
    world.container.max = Eigen::Vector3f(12, 12, 30);
    BodyParams bell = shellBody(Eigen::Vector3f(6, 6, 3.0f + lift), Eigen::Vector3f::UnitZ());
    MuscleParams ring;
    ring.springs.kind = SelectionKind::Rim;
    ring.force.keys = {{0.0f, 100.0f}};
    ring.ceiling = 16.0f;
    ring.ceilingBand = 4.0f;
    bell.muscles.push_back(ring);
    world.bodies.push_back(bell);
    const ParticleSet p = muscleAccelerations(world);
    double centroid = 0.0, force = 0.0;
    for (size_t i = 0; i < p.size(); ++i) {
      centroid += p.z[i] / double(p.size());
      force += p.mass[i] * Eigen::Vector3d(p.ax[i], p.ay[i], p.az[i]).norm();
    }
    return std::make_pair(centroid, force);
  };
  const auto [low, full] = totalForce(0.0f);
  ASSERT_LT(low, 12.0);
  ASSERT_GT(full, 0.0);
  const auto [mid, half] = totalForce(float(14.0 - low));
  EXPECT_NEAR(mid, 14.0, 1e-3);
  EXPECT_NEAR(half / full, 0.5, 1e-3);
  const auto [high, none] = totalForce(float(16.5 - low));
  EXPECT_EQ(none, 0.0);
}

TEST(Chains, BendingStraightensABentChainAndConservesMomentum) {
  // A five-particle chain bent 60 degrees at its middle particle, no gravity, no fluid: with a
  // bending stiffness it swings through straight (the smallest angle between its end segments
  // over 3 s; nothing damps a bend in a vacuum) while its total momentum stays zero; without,
  // its springs (first neighbours only) leave the bend.
  auto bendAfter = [](float bending, double* momentum) {
    SimParams world = emptyWorld();
    BodyParams chain;
    chain.name = "arm";
    chain.shape = BodyShape::Chain;
    chain.start = Eigen::Vector3f(6, 6, 6);
    chain.end = Eigen::Vector3f(6, 6, 8);
    chain.spacing = 0.5f;
    chain.connectionRadius = 0.6f;  // first neighbours only
    chain.stiffness = 500.0f;
    chain.damping = 10.0f;
    chain.bending = bending;
    world.bodies.push_back(chain);
    Simulation sim(world);
    // Bend: rotate the upper half about the middle particle by 60 degrees about y.
    ParticleSet& p = sim.particles();
    const float c = std::cos(1.0472f), s = std::sin(1.0472f);
    for (size_t i = 0; i < p.size(); ++i)
      if (p.z[i] > 7.01f) {
        const float dx = p.x[i] - 6.0f, dz = p.z[i] - 7.0f;
        p.x[i] = 6.0f + c * dx + s * dz;
        p.z[i] = 7.0f - s * dx + c * dz;
      }
    double smallest = 180.0;
    *momentum = 0.0;
    for (int n = 1; n <= 300; ++n) {
      sim.advanceTo(0.01 * n);
      const ParticleSet& r = sim.particles();
      std::vector<std::pair<int64_t, Eigen::Vector3d>> q;
      Eigen::Vector3d m = Eigen::Vector3d::Zero();
      for (size_t i = 0; i < r.size(); ++i) {
        q.emplace_back(r.id[i], Eigen::Vector3d(r.x[i], r.y[i], r.z[i]));
        m += r.mass[i] * Eigen::Vector3d(r.vx[i], r.vy[i], r.vz[i]);
      }
      *momentum = std::max(*momentum, m.norm());
      std::sort(q.begin(), q.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      const Eigen::Vector3d first = (q[1].second - q[0].second).normalized();
      const Eigen::Vector3d last = (q[q.size() - 1].second - q[q.size() - 2].second).normalized();
      smallest = std::min(smallest, std::acos(std::clamp(first.dot(last), -1.0, 1.0)) * 180.0 / 3.14159265358979);
    }
    return smallest;
  };
  double momentumBent = 0.0, momentumPlain = 0.0;
  const double bent = bendAfter(20000.0f, &momentumBent), plain = bendAfter(0.0f, &momentumPlain);
  EXPECT_LT(bent, 10.0);
  EXPECT_GT(plain, 45.0);
  EXPECT_LT(momentumBent, 1e-2 * 62.5);  // under half a particle's mass (137 kg) times 1 cm/s
}

TEST(Collisions, FluidContactKeepsAFastFluidParticleOutOfAMembrane) {
  // One fluid particle shot at 40 m/s down onto a held one-layer membrane. The SPH pressure of a
  // lone particle is clamped at zero, so without the fluid contact it passes straight through.
  for (const float contact : {0.0f, 1.0f}) {
    SimParams world = emptyWorld();
    world.fluidBlocks.push_back({Eigen::Vector3f(5.5f, 5.5f, 8.5f), Eigen::Vector3f(6.5f, 6.5f, 9.5f)});
    BodyParams sheet;
    sheet.name = "sheet";
    sheet.shape = BodyShape::Membrane;
    sheet.layers = 1;
    sheet.min = Eigen::Vector3f(3, 3, 6);
    sheet.max = Eigen::Vector3f(9, 9, 6);
    sheet.holdUntil = 100.0f;
    world.bodies.push_back(sheet);
    world.collisions.fluidContact = contact;
    Simulation sim(world);
    ParticleSet& p = sim.particles();
    size_t fluid = p.size();
    for (size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == 0) fluid = i;
    ASSERT_LT(fluid, p.size());
    p.vz[fluid] = -40.0f;
    const int64_t id = p.id[fluid];
    for (int step = 0; step < 40; ++step) sim.step(0.005f);
    float z = 0.0f;
    for (size_t i = 0; i < sim.particles().size(); ++i)
      if (sim.particles().id[i] == id) z = sim.particles().z[i];
    if (contact > 0.0f) {
      EXPECT_GT(z, 6.0f + 0.5f * 0.5f * 0.99f) << "kept a body radius above the sheet";
      EXPECT_GT(sim.bodies()->stats().collisionsResolved, 0u);
    } else {
      EXPECT_LT(z, 6.0f) << "passed through without the fluid contact";
    }
  }
}

// Archimedes: a 3 m box dropped into a tank floats with the submerged fraction of its particles
// within 0.1 of its specific gravity, averaged over t = 7 .. 12 s (the fluid of scenes/box.json:
// the paper's parameters except k_press 2000 and h = 2 l, with the volume density sum and
// Monaghan's pressure force; docs/design/physics.md has the paper's forms for comparison). The box has
// 6 particle layers, so fractions come in steps of 1/6.
// Each case runs with the paper's WCSPH, and with DFSPH and IISPH with boundary-particle walls and a
// hydrostatic start.
class Archimedes : public ::testing::TestWithParam<std::tuple<float, std::string>> {};

TEST_P(Archimedes, SubmergedFractionFollowsSpecificGravity) {
  const auto [gravity, solver] = GetParam();
  SimParams p;
  p.fluid.supportRadius = 2.0f;  // as scenes/box.json: with 1.5 l the coarse fluid holds a body like a crystal
  p.fluid.pressureStiffness = 2000.0f;
  p.fluid.pressureForce = PressureForce::Monaghan1992;
  p.fluid.densitySum = DensitySum::Volume;
  p.fluid.solver = solver;
  if (solver != "wcsph") {
    p.container.wallDensity = WallDensity::BoundaryParticles;
    p.fluid.initialState = InitialState::Hydrostatic;
  }
  p.container.max = Eigen::Vector3f(14, 14, 12);
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(14, 14, 6)});
  p.bodies.push_back(boxSceneBody({5.5f, 5.5f, 6.5f}, {8.5f, 8.5f, 9.5f}, gravity));  // dropped from just above the water
  Simulation sim(p);
  double sum = 0.0;
  int samples = 0;
  for (int k = 1; k <= 12; ++k) {
    sim.advanceTo(k);
    if (k > 6) {
      sum += submergedFraction(sim.particles(), p.fluid.spacing);
      ++samples;
    }
  }
  const double fraction = sum / samples;  // averaged over t = 7 .. 12 s
  EXPECT_NEAR(fraction, gravity, 0.1) << "specific gravity " << gravity;
}

// DFSPH: with the fluid's Jacobi relaxation the box's particles (half the fluid spacing, 8 times
// the neighbours) made the iteration diverge and sg 0.7 and 0.9 became non-finite; the relaxation
// now scales with the neighbour count (sim/solvers/dfsph/dfsph.cpp).
INSTANTIATE_TEST_SUITE_P(SpecificGravity, Archimedes,
                         ::testing::Values(std::make_tuple(0.5f, std::string("wcsph")),
                                           std::make_tuple(0.7f, std::string("wcsph")),
                                           std::make_tuple(0.9f, std::string("wcsph")),
                                           std::make_tuple(0.5f, std::string("dfsph")),
                                           std::make_tuple(0.7f, std::string("dfsph")),
                                           std::make_tuple(0.9f, std::string("dfsph")),
                                           std::make_tuple(0.5f, std::string("iisph")),
                                           std::make_tuple(0.7f, std::string("iisph")),
                                           std::make_tuple(0.9f, std::string("iisph"))),
                         [](const auto& info) {
                           return std::get<1>(info.param) + "_sg" +
                                  std::to_string(int(std::lround(std::get<0>(info.param) * 10)));
                         });

// DFSPH, boundary-particle walls: a light box (sg 0.7) resting on the tank's floor under 6 m of
// water rises. No fluid lies under it, so only the wetted walls (sim/solvers/dfsph/dfsph.h: under a
// body particle a wall carries at least the surrounding fluid's hydrostatic pressure) give it the
// buoyancy of its bottom face; with the mirrored wall alone it stayed on the floor (box.json's
// released box did for 7 s).
TEST(WettedWalls, DfsphBuoyantBoxLeavesTheFloor) {
  SimParams p;
  p.fluid.supportRadius = 2.0f;
  p.fluid.densitySum = DensitySum::Volume;
  p.fluid.solver = "dfsph";
  p.fluid.initialState = InitialState::Hydrostatic;
  p.container.wallDensity = WallDensity::BoundaryParticles;
  p.container.max = Eigen::Vector3f(12, 12, 10);
  p.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(12, 12, 6)});
  p.bodies.push_back(boxSceneBody({4.5f, 4.5f, 0.0f}, {7.5f, 7.5f, 3.0f}, 0.7f));
  Simulation sim(p);
  const float start = pipeline::kindExtent(sim.particles(), 1).centre.z();
  sim.advanceTo(3.0);
  const pipeline::KindExtent e = pipeline::kindExtent(sim.particles(), 1);
  EXPECT_GT(e.centre.z(), start + 1.0f) << "rose from the floor";
}

// box.json under DFSPH run as `kurage sim` runs it (to each frame time at the scene's 24 fps),
// past its release on the floor at t = 15 s: with the mass form's pressure push beside the volume
// form's density rate, the constant-density solve diverged at a body particle on the floor (its
// pressure growing 2.5-fold an iteration) and the run stopped at t = 16.7 s with a non-finite
// velocity (sim/solvers/dfsph/dfsph.h).
TEST(BoxSequenceAsRun, DfsphStaysFiniteThroughTheReleaseOnTheFloor) {
  const pipeline::Scene scene = sceneUnderDfsph("box.json");
  Simulation sim(scene.sim);
  const int frames = int(std::lround(18.0 * scene.output.fps));
  for (int f = 1; f <= frames; ++f) ASSERT_NO_THROW(sim.advanceTo(scene.output.frameTime(f))) << "frame " << f;
  const ParticleSet& p = sim.particles();
  for (size_t i = 0; i < p.size(); ++i) ASSERT_TRUE(std::isfinite(p.vx[i] + p.vy[i] + p.vz[i])) << i;
  EXPECT_GT(pipeline::kindExtent(p, 1).min.z(), 0.5f) << "risen off the floor by t = 18 s";
}

// The paper's Fig. 3 with scenes/box.json: the state at the end of each phase of its force schedule.
// The scene as written (the paper's WCSPH), or under DFSPH with boundary-particle walls and a
// hydrostatic start: the telescopic bodies' tests run with both solvers (issue 13).
class WithSolver : public ::testing::TestWithParam<std::string> {
protected:
  pipeline::Scene scene(const char* name) const {
    return GetParam() == "dfsph" ? sceneUnderDfsph(name) : sceneFile(name);
  }
};

using BoxSequence = WithSolver;
TEST_P(BoxSequence, FollowsThePaper) {
  const pipeline::Scene scene = this->scene("box.json");
  Simulation sim(scene.sim);
  const float l = scene.sim.fluid.spacing;
  auto state = [&](double t) {
    sim.advanceTo(t);
    return std::make_pair(submergedFraction(sim.particles(), l), pipeline::kindExtent(sim.particles(), 1));
  };
  const auto [floating, floatingBox] = state(6.0);
  EXPECT_GT(floating, 0.5) << "floats";
  EXPECT_LT(floating, 0.9) << "floats";
  const auto [contracted, contractedBox] = state(14.0);
  // Boundary particles count in a body particle's density, so the box rests about a spacing
  // above the floor instead of against it.
  EXPECT_LT(contractedBox.min.z(), (GetParam() == "dfsph" ? 1.25f : 1.0f) * l) << "at the bottom under contraction";
  const auto [released, releasedBox] = state(22.0);
  EXPECT_GT(releasedBox.centre.z(), contractedBox.centre.z() + 0.8) << "risen after release";
  EXPECT_LT(released, 0.95) << "back at the surface after release";
  const auto [expanded, expandedBox] = state(30.0);
  EXPECT_LT(expanded, floating - 0.1) << "rides higher under expansion";
  const auto [settled, settledBox] = state(38.0);
  EXPECT_NEAR(settled, floating, 0.1) << "floats again after release";
  EXPECT_EQ(sim.bodies()->stats().capHits, 0u);
}

// The paper's Fig. 2: with the stretch-following density the membrane holds the poured fluid;
// the conventional mass-spring model lets it slip through.
//
// How it holds (docs/design/physics.md, "Why the solved coupling loses the membrane's contrast under DFSPH"): under WCSPH the poured
// fluid on the sheet has no pressure of its own (its particles lie loose, below rest density) and
// the telescopic sheet, whose rest density fell as it stretched, carries it with its own pressure
// (measured at 16 s: 39 kPa, the 90th percentile of the loaded sheet, against 0.8 kPa for the
// conventional sheet; the fluid's median 0).
using Membrane = WithSolver;
TEST_P(Membrane, TelescopicDensityHoldsTheFluidTheConventionalModelLeaks) {
  std::map<bool, double> leaked;
  std::map<bool, pipeline::MembraneLoad> load;
  for (const bool telescopic : {true, false}) {
    pipeline::Scene scene = this->scene(telescopic ? "membrane.json" : "membrane_conventional.json");
    Simulation sim(scene.sim);
    sim.advanceTo(scene.output.duration);
    const ParticleSet& p = sim.particles();
    load[telescopic] = pipeline::membraneLoad(p, 1, scene.sim.fluid.supportRadiusMetres());
    const pipeline::MembraneLeak leak = pipeline::membraneLeak(p, 1, scene.sim.fluid.spacing);
    ASSERT_GT(leak.fluid, 50u);
    leaked[telescopic] = double(leak.leaked) / double(leak.fluid);
  }
  EXPECT_LT(leaked[true], 0.1) << "telescopic density";
  EXPECT_GT(leaked[false], 0.5) << "conventional mass-spring model";
  EXPECT_GT(load[true].sheetPressure90, 10.0 * load[false].sheetPressure90) << "the telescopic sheet carries the fluid";
  EXPECT_GT(load[true].fluidParticles, 20u);
  EXPECT_LT(load[true].fluidPressure50, 0.05 * load[true].sheetPressure90) << "the fluid on it has no pressure";
}

// What a solver of the bodies' density leaves out (BodySystem::markUnsolved): the particles a pin
// holds, and those of a telescopic body stretched until their rest density is under a quarter of
// their initial one (about 1.6 times in every direction).
TEST(Unsolved, HeldAndTornBodyParticlesAreMarked) {
  SimParams world = emptyWorld();
  BodyParams box = boxBody(Eigen::Vector3f(4, 4, 4), Eigen::Vector3f(8, 8, 8));
  box.telescopicDensity = true;
  box.pins.push_back({SelectionKind::Region, Eigen::Vector3f(3.9f, 3.9f, 3.9f), Eigen::Vector3f(4.6f, 8.1f, 8.1f)});
  world.bodies.push_back(box);
  for (const float stretch : {1.0f, 1.5f, 1.7f}) {
    ParticleSet p;
    int64_t nextId = 0;
    BodySystem bodies(world, p, nextId);
    ASSERT_TRUE(bodies.mayLeaveParticlesUnsolved());
    bodies.index(p);
    for (size_t i = 0; i < p.size(); ++i) {  // stretched uniformly about the box's centre
      p.x[i] = 6.0f + stretch * (p.x[i] - 6.0f);
      p.y[i] = 6.0f + stretch * (p.y[i] - 6.0f);
      p.z[i] = 6.0f + stretch * (p.z[i] - 6.0f);
    }
    bodies.updateRestDensity(p);
    std::vector<uint8_t> state;
    bodies.markUnsolved(p, 0.0, state);
    ASSERT_EQ(state.size(), p.size());
    const auto held = std::count(state.begin(), state.end(), uint8_t(kHeld));
    const auto torn = std::count(state.begin(), state.end(), uint8_t(kTorn));
    EXPECT_GT(held, 0) << stretch;
    EXPECT_EQ(torn, stretch > 1.6f ? ptrdiff_t(p.size()) - held : 0) << stretch;
  }
  // A body with neither pins nor telescopic density has nothing to mark.
  world.bodies[0].telescopicDensity = false;
  world.bodies[0].pins.clear();
  ParticleSet p;
  int64_t nextId = 0;
  const BodySystem plain(world, p, nextId);
  EXPECT_FALSE(plain.mayLeaveParticlesUnsolved());
}

// A body coupled as the fluid's boundary (BodyCoupling::Boundary): every particle no unknown of the
// solves (kBoundary; a held one kHeld), each with a patch of itself and its spring neighbours,
// the patches symmetric and the shares m_i / (the patch's mass), masses unequal (a heavier part).
TEST(BoundaryBodies, MarkedAndPatchedBySprings) {
  SimParams world = emptyWorld();
  world.fluid.solver = "dfsph";
  world.fluid.densitySum = DensitySum::Volume;
  BodyParams box = boxBody(Eigen::Vector3f(4, 4, 4), Eigen::Vector3f(7, 7, 7));
  box.coupling = BodyCoupling::Boundary;
  box.pins.push_back({SelectionKind::Region, Eigen::Vector3f(3.9f, 3.9f, 3.9f), Eigen::Vector3f(4.6f, 7.1f, 7.1f)});
  box.parts.push_back({"heavy", {SelectionKind::Region, Eigen::Vector3f(5.9f, 3.9f, 3.9f), Eigen::Vector3f(7.1f, 7.1f, 7.1f)}, 3.0f});
  world.bodies.push_back(box);
  world.bodies.push_back(boxBody(Eigen::Vector3f(8, 8, 8), Eigen::Vector3f(10, 10, 10)));  // solved, unpinned
  ParticleSet p;
  int64_t nextId = 0;
  BodySystem bodies(world, p, nextId);
  ASSERT_TRUE(bodies.hasBoundaryBodies());
  ASSERT_TRUE(bodies.mayLeaveParticlesUnsolved());
  bodies.index(p);
  bodies.updateRestDensity(p);
  std::vector<uint8_t> state;
  bodies.markUnsolved(p, 0.0, state);
  BoundaryBodies patches;
  bodies.boundaryPatches(p, patches);
  ASSERT_EQ(patches.offsets.size(), p.size() + 1);
  size_t held = 0;
  std::set<float> masses;
  for (size_t i = 0; i < p.size(); ++i) {
    const bool first = p.kind[i] == 1;
    EXPECT_EQ(patches.sample[i], first ? 1 : 0) << i;
    if (!first) {
      EXPECT_EQ(state[i], kSolved) << i;
      EXPECT_EQ(patches.offsets[i + 1], patches.offsets[i]) << "no patch outside a boundary body";
      continue;
    }
    held += state[i] == kHeld;
    EXPECT_TRUE(state[i] == kBoundary || state[i] == kHeld) << i;
    const uint32_t* begin = patches.patch.data() + patches.offsets[i];
    const uint32_t* end = patches.patch.data() + patches.offsets[i + 1];
    ASSERT_GT(end - begin, 1) << "itself and its spring neighbours";
    EXPECT_EQ(*begin, i) << "itself first";
    double mass = 0.0;
    for (const uint32_t* q = begin; q != end; ++q) {
      mass += p.mass[*q];
      EXPECT_EQ(p.kind[*q], 1);
      const uint32_t* back = patches.patch.data() + patches.offsets[*q];
      const uint32_t* backEnd = patches.patch.data() + patches.offsets[*q + 1];
      EXPECT_NE(std::find(back, backEnd, uint32_t(i)), backEnd) << "patches are symmetric";
    }
    EXPECT_NEAR(patches.share[i], p.mass[i] / mass, 1e-6);
    masses.insert(p.mass[i]);
  }
  EXPECT_GT(held, 0u);
  EXPECT_EQ(masses.size(), 2u) << "the part's particles are heavier";
  // Under a solver that cannot couple it so, the simulation refuses the body.
  world.fluid.solver = "wcsph";
  EXPECT_THROW(Simulation{world}, std::invalid_argument);
}

// A fluid block at 3 m/s about to hit a free box coupled as the fluid's boundary, without
// gravity, clear of the walls; the fluid's spacing l (the box's is half of it).
Simulation blockThrownAtABoundaryBody(float l = 1.0f) {
  SimParams world = emptyWorld();
  world.fluid.spacing = l;
  world.fluid.solver = "dfsph";
  world.fluid.densitySum = DensitySum::Volume;
  world.fluidBlocks.push_back({Eigen::Vector3f(2, 4, 4), Eigen::Vector3f(5, 8, 8)});
  BodyParams box = boxBody(Eigen::Vector3f(5.75f, 4.5f, 4.5f), Eigen::Vector3f(7.25f, 7.5f, 7.5f));
  box.coupling = BodyCoupling::Boundary;
  box.stiffness = 2000.0f;
  world.bodies.push_back(box);
  Simulation sim(world);
  ParticleSet& p = sim.particles();
  for (size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == 0) p.vx[i] = 3.0f;
  return sim;
}

// The coupling conserves linear momentum. The fluid's push on each sample and the sample's
// reaction are equal and opposite, and the reaction spread over the patch keeps its impulse.
TEST(BoundaryBodies, PressureReactionsConserveMomentum) {
  Simulation sim = blockThrownAtABoundaryBody();
  ParticleSet& p = sim.particles();
  auto momentum = [&](int kind) {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < p.size(); ++i)
      if (kind < 0 || p.kind[i] == kind) m += double(p.mass[i]) * Eigen::Vector3d(p.vx[i], p.vy[i], p.vz[i]);
    return m;
  };
  const Eigen::Vector3d start = momentum(-1);
  ASSERT_NO_THROW(sim.advanceTo(0.6));
  const pipeline::KindExtent fluid = pipeline::kindExtent(p, 0);
  ASSERT_GT(fluid.min.minCoeff(), 1.0f) << "clear of the walls";
  ASSERT_LT(fluid.max.maxCoeff(), 11.0f) << "clear of the walls";
  const Eigen::Vector3d end = momentum(-1);
  EXPECT_GT(momentum(1).x(), 0.1 * start.x()) << "the fluid pushed the body";
  EXPECT_LT((end - start).norm(), 1e-3 * start.norm());
}

// The patches gather in a fixed order: 1 and 2 threads agree bit for bit (at half the spacing,
// so that the particles span several of the solves' chunks).
TEST(BoundaryBodies, OneAndTwoThreadsGiveIdenticalParticles) {
  auto run = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Simulation sim = blockThrownAtABoundaryBody(0.5f);
    EXPECT_GT(sim.particles().size(), NeighborLists::kChunk);
    sim.advanceTo(0.6);
    return positionsById(sim.particles());
  };
  EXPECT_TRUE(run(1) == run(2));
}

// The paper's Fig. 2 under DFSPH: scenes/membrane_dfsph.json and its conventional twin, the sheet
// coupled as the fluid's boundary (BodyCoupling::Boundary, docs/design/physics.md "Bodies as the fluid's
// boundary"), the paper's body parameters (k = 30 N/m) and a support of 1.6 l. The fluid meets the
// sheet's particles by their volume m / rho0, which (10) grows as the sheet stretches: the
// telescopic sheet holds the poured fluid, the conventional one lets it slip through. Sampled
// every 16 / 2 / 1 / 0.5 / 0.25 / 0.1 / 1/24 / 0.05 s (the scene is chaotic): 0 and 54-61 of 85
// leak. No sheet particle is thrown (5.9 m/s at most, read every frame). With the reactions on
// the samples alone, not spread over their patches, seven of the eight telescopic runs stopped
// and the conventional sheet let every particle through.
TEST(MembraneUnderDfsph, TelescopicVolumeHoldsTheFluidTheConventionalModelLeaks) {
  std::map<bool, double> leaked;
  for (const bool telescopic : {true, false}) {
    const pipeline::Scene scene = sceneFile(telescopic ? "membrane_dfsph.json" : "membrane_dfsph_conventional.json");
    ASSERT_EQ(scene.sim.fluid.solver.name(), "dfsph");
    ASSERT_EQ(scene.sim.bodies[0].telescopicDensity, telescopic);
    Simulation sim(scene.sim);
    float fastest = 0.0f;  // the fastest sheet particle at any whole second
    for (int t = 1; t <= int(scene.output.duration); ++t) {
      ASSERT_NO_THROW(sim.advanceTo(t));
      const ParticleSet& p = sim.particles();
      for (size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == 1) fastest = std::max(fastest, std::sqrt(p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]));
    }
    const pipeline::MembraneLeak leak = pipeline::membraneLeak(sim.particles(), 1, scene.sim.fluid.spacing);
    ASSERT_GT(leak.fluid, 50u);
    leaked[telescopic] = double(leak.leaked) / double(leak.fluid);
    EXPECT_LT(fastest, 10.0f) << "no sheet particle thrown";
  }
  EXPECT_LT(leaked[true], 0.1) << "telescopic density";
  EXPECT_GT(leaked[false], 0.5) << "conventional mass-spring model";
}

// membrane.json (the sheet's particles unknowns of the solves) under DFSPH (boundary-particle
// walls, hydrostatic start) runs its 16 s. It went non-finite at t = 8-9 s: the solves pushed the
// held rim, whose warm-started pressure grew step after step (8 MPa), and then a torn-off
// particle, its rest density under a quarter of its initial one, was given a pressure without
// bound (sim/solvers/dfsph/dfsph.h). With this coupling the leak test is not met (34 of 85 get through,
// 49 with the conventional model; docs/notebook/pressure_solvers.md), so only that the run
// completes with finite particles inside the tank is asserted; the leak is printed. The leak test
// under DFSPH is the one above, with the sheet coupled as the fluid's boundary.
TEST(MembraneUnderDfsph, RunsItsSixteenSeconds) {
  const pipeline::Scene scene = sceneUnderDfsph("membrane.json");
  Simulation sim(scene.sim);
  ASSERT_NO_THROW(sim.advanceTo(scene.output.duration));
  const ParticleSet& p = sim.particles();
  const Eigen::Vector3f& lo = scene.sim.container.min;
  const Eigen::Vector3f& hi = scene.sim.container.max;
  for (size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector3f x(p.x[i], p.y[i], p.z[i]);
    ASSERT_TRUE(x.allFinite() && std::isfinite(p.vx[i] + p.vy[i] + p.vz[i])) << "particle " << p.id[i];
    ASSERT_TRUE((x.array() >= lo.array() - 1e-3f).all() && (x.array() <= hi.array() + 1e-3f).all())
        << "particle " << p.id[i] << " outside the tank";
  }
  EXPECT_GT(test::dfsphStats(sim).torn.steps, 0u) << "the sheet tears: what the run survives";
  // Why it leaks (docs/design/physics.md, "Why the solved coupling loses the membrane's contrast under DFSPH"): the fluid on the sheet
  // is a liquid whose pressure holds its own weight (measured 15 kPa, median, at 16 s; under WCSPH
  // 0), which presses it through the stretched sheet's holes.
  const pipeline::MembraneLoad load = pipeline::membraneLoad(p, 1, scene.sim.fluid.supportRadiusMetres());
  EXPECT_GT(load.fluidPressure50, 5000.0) << "a pressurised liquid on the sheet";
}

const auto kSolverName = [](const auto& info) { return info.param; };
INSTANTIATE_TEST_SUITE_P(Solver, BoxSequence, ::testing::Values("wcsph", "dfsph"), kSolverName);
// The leak test of membrane.json (its sheet's particles unknowns of the solves) runs with WCSPH;
// under DFSPH it is MembraneUnderDfsph above, on scenes/membrane_dfsph.json.
INSTANTIATE_TEST_SUITE_P(Solver, Membrane, ::testing::Values("wcsph"), kSolverName);

TEST(StepPhases, OnlyWhatTheSceneCallsForRun) {
  SimParams fluidOnly;
  fluidOnly.container.max = Eigen::Vector3f(6, 6, 6);
  fluidOnly.fluidBlocks.push_back({Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(6, 6, 3)});
  Simulation fluid(fluidOnly);
  fluid.advanceTo(0.2);
  EXPECT_EQ(fluid.bodies(), nullptr) << "no spring data without bodies";
  for (StepPhase s : {StepPhase::TelescopicDensity, StepPhase::Springs, StepPhase::Muscles, StepPhase::Pins, StepPhase::Collisions,
                  StepPhase::Emitters, StepPhase::Sinks})
    EXPECT_FALSE(fluid.stats().phaseRan(s)) << phaseName(s);
  for (StepPhase s : {StepPhase::Sort, StepPhase::Density, StepPhase::Pressure, StepPhase::Forces, StepPhase::Integrate, StepPhase::Walls})
    EXPECT_TRUE(fluid.stats().phaseRan(s)) << phaseName(s);

  SimParams bodyOnly = emptyWorld();
  bodyOnly.bodies.push_back(boxBody({4, 4, 4}, {6, 6, 6}));
  bodyOnly.bodies.back().telescopicDensity = false;
  Simulation body(bodyOnly);
  body.advanceTo(0.2);
  for (StepPhase s : {StepPhase::Springs, StepPhase::Collisions}) EXPECT_TRUE(body.stats().phaseRan(s)) << phaseName(s);
  for (StepPhase s : {StepPhase::TelescopicDensity, StepPhase::Muscles, StepPhase::Pins, StepPhase::Emitters})
    EXPECT_FALSE(body.stats().phaseRan(s)) << phaseName(s);
}
