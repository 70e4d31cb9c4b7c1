// The jellyfish (issue 6, scenes/jellyfish.json): the bell swims by jet propulsion, each
// contraction narrows its margin, and the scene's first seconds stay stable. The full 30 s run's
// figures come from `kurage run` itself (run.json, bodies.csv; docs/STABILITY.md "The jellyfish").
//
// Measures (pipeline/measures.h ShellWall): the bell's centre of mass (mass-weighted: a part may be heavier);
// the margin radius, the mean distance of the last ring of latitude (both layers) from its own
// centroid; fluid inside the wall, a fluid particle with a particle of the inner layer and one of
// the outer layer within one body spacing on opposite sides of it.
#include "pipeline/measures.h"
#include "pipeline/scene.h"
#include "sim/bodies.h"
#include "sim/simulation.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace kurage;

namespace {

pipeline::Scene jellyfishScene() { return pipeline::loadScene(test::sourceDir() / "scenes/jellyfish.json"); }

struct SwimRun {
  double rise = 0.0;               // centre of mass, from the first pulse's start to the fifth's end
  std::vector<double> peakRatios;  // per pulse: smallest margin radius / radius at rest
  double mostTilt = 0.0;           // degrees
};

// The scene's bell alone (no arms, no faucets) in still water, with or without its pulses.
SwimRun fivePulses(bool pulses) {
  pipeline::Scene scene = jellyfishScene();
  sim::SimParams& p = scene.sim;
  p.emitters.clear();
  p.bodies.resize(1);
  const sim::ForceCurve force = p.bodies[0].muscles.at(0).force;
  if (!pulses) p.bodies[0].muscles.clear();
  sim::Simulation s(p);
  const pipeline::ShellWall wall(p.bodies[0], 1, s.particles(), p.fluid.spacing);
  const double rest = wall.marginRadius(s.particles());
  s.advanceTo(force.start);
  const double z0 = wall.centre(s.particles()).z();
  SwimRun run;
  for (int k = 0; k < 5; ++k) {
    double smallest = 1e30;
    for (int n = 1; n <= int(std::lround(force.period / 0.05)); ++n) {
      s.advanceTo(force.start + k * force.period + n * 0.05);
      smallest = std::min(smallest, wall.marginRadius(s.particles()));
      run.mostTilt = std::max(run.mostTilt, wall.tiltDegrees(s.particles()));
    }
    run.peakRatios.push_back(smallest / rest);
  }
  run.rise = wall.centre(s.particles()).z() - z0;
  return run;
}

}  // namespace

// The bell is bottom-heavy (its margin ring is a heavier part) and its ring muscle has a righting
// reflex: over the five pulses it must also stay upright, where a uniform bell without the reflex
// tipped past 90 degrees (docs/PHYSICS.md "The jellyfish").
TEST(Jellyfish, FivePulsesLiftTheBellOneRadiusAboveTheUnpulsedBellAndNarrowItsMargin) {
  const pipeline::Scene scene = jellyfishScene();
  const double radius = scene.sim.bodies[0].innerRadius;
  const SwimRun pulsed = fivePulses(true);
  const SwimRun still = fivePulses(false);
  std::printf("rise over five pulses: pulsed %.2f m, unpulsed %.2f m (bell radius %.2f m); most tilt %.0f deg\n",
              pulsed.rise, still.rise, radius, pulsed.mostTilt);
  EXPECT_GE(pulsed.rise - still.rise, radius);
  ASSERT_EQ(pulsed.peakRatios.size(), 5u);
  for (size_t k = 0; k < 5; ++k) {
    std::printf("pulse %zu: margin radius at peak contraction %.2f of rest\n", k + 1, pulsed.peakRatios[k]);
    EXPECT_LT(pulsed.peakRatios[k], 0.9) << "pulse " << k + 1;
  }
  ASSERT_EQ(still.peakRatios.size(), 5u);
  for (size_t k = 0; k < 5; ++k)
    EXPECT_GT(still.peakRatios[k], pulsed.peakRatios[k] + 0.15) << "without pulses the margin stays wider, pulse " << k + 1;
  EXPECT_LT(pulsed.mostTilt, 60.0) << "the swimming bell does not tip over";
}

TEST(Jellyfish, FirstSecondsOfTheSceneStayStable) {
  // scenes/jellyfish.json up to 6 s: the fluid settles around the held bell, the bell is released
  // at 3 s, the right faucet pours from 3 s, the first pulse contracts the margin at 4 s.
  const pipeline::Scene scene = jellyfishScene();
  sim::Simulation s(scene.sim);
  const pipeline::ShellWall wall(scene.sim.bodies[0], 1, s.particles(), scene.sim.fluid.spacing);
  const sim::ContainerParams& box = scene.sim.container;
  size_t mostInWall = 0;
  for (int n = 1; n <= 24; ++n) {
    ASSERT_NO_THROW(s.advanceTo(0.25 * n)) << "t = " << 0.25 * n;
    const sim::ParticleSet& p = s.particles();
    for (size_t i = 0; i < p.size(); ++i) {
      const Eigen::Vector3f x(p.x[i], p.y[i], p.z[i]), v(p.vx[i], p.vy[i], p.vz[i]);
      ASSERT_TRUE(x.allFinite() && v.allFinite()) << "particle " << p.id[i] << " at t = " << s.time();
      ASSERT_TRUE((x.array() >= box.min.array()).all() && (x.array() <= box.max.array()).all())
          << "particle " << p.id[i] << " outside the tank at t = " << s.time();
    }
    mostInWall = std::max(mostInWall, wall.fluidInsideWall(p));
  }
  EXPECT_EQ(mostInWall, 0u) << "fluid particles inside the bell's wall";
  EXPECT_GT(s.stats().emitted, 0u) << "the right faucet poured";
  EXPECT_GE(s.stats().minStep, scene.sim.timeStep.minStep);
  EXPECT_TRUE(s.stats().stageRan(sim::Stage::Muscles));
  // The cap is a reported figure, not a failure, but it must stay rare: a loop that stops at the
  // cap in more than 1 % of the steps leaves overlaps behind.
  EXPECT_LE(s.bodies()->stats().capHits * 100, s.stats().steps);
  std::printf("6 s: %llu steps, smallest %.4g s, collision cap hit in %llu steps, most passes %d\n",
              (unsigned long long)s.stats().steps, s.stats().minStep, (unsigned long long)s.bodies()->stats().capHits,
              s.bodies()->stats().mostPasses);
}

TEST(Jellyfish, ABottomHeavyBellBuiltTiltedRightsItselfInStillWater) {
  // The scene's bell alone, without pulses, built tilted 30 degrees and released at 3 s: its heavy
  // margin (the part) swings it back towards upright; the same bell of uniform specific gravity 1.1
  // has no righting moment.
  auto tiltAfter = [](bool bottomHeavy) {
    pipeline::Scene scene = jellyfishScene();
    sim::SimParams& p = scene.sim;
    p.emitters.clear();
    p.bodies.resize(1);
    sim::BodyParams& bell = p.bodies[0];
    bell.muscles.clear();
    const float a = 30.0f * std::numbers::pi_v<float> / 180.0f;
    bell.axis = Eigen::Vector3f(std::sin(a), 0.0f, std::cos(a));
    if (!bottomHeavy) {
      bell.parts.clear();
      bell.specificGravity = 1.1f;
    }
    sim::Simulation s(p);
    const pipeline::ShellWall wall(bell, 1, s.particles(), p.fluid.spacing);
    s.advanceTo(bell.holdUntil + 10.0);
    return wall.tiltDegrees(s.particles(), Eigen::Vector3d::UnitZ());
  };
  const double heavy = tiltAfter(true), uniform = tiltAfter(false);
  std::printf("10 s after release from 30 deg: bottom-heavy bell %.0f deg, uniform bell %.0f deg\n", heavy, uniform);
  // Measured: 18 against 28 degrees (the uniform bell is neutral: it stays near where it was put).
  EXPECT_LT(heavy, 0.7 * 30.0) << "rights itself by a third at least";
  EXPECT_LT(heavy, uniform - 5.0);
}
