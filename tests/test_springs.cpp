// The telescopic body's springs (sim/springs.h): network construction, force (7) against the
// analytic two-body oscillator, damping, and the stretch ratio (8)-(10).
#include "sim/springs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace kurage::sim;

namespace {

std::vector<Eigen::Vector3f> lattice(int n, float spacing) {
  std::vector<Eigen::Vector3f> points;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) points.emplace_back(spacing * Eigen::Vector3f(float(i), float(j), float(k)));
  return points;
}

ParticleSet particlesAt(const std::vector<Eigen::Vector3f>& points, float mass) {
  ParticleSet p;
  for (size_t k = 0; k < points.size(); ++k)
    p.add(points[k].x(), points[k].y(), points[k].z(), 0, 0, 0, 1000.0f, mass, int64_t(k), 1);
  return p;
}

std::vector<int64_t> iota(size_t n) {
  std::vector<int64_t> ids(n);
  for (size_t k = 0; k < n; ++k) ids[k] = int64_t(k);
  return ids;
}

// Symplectic Euler with springs only.
void step(const SpringNetwork& net, float k, float d, float dt, ParticleSet& p, const std::vector<uint32_t>& index) {
  std::fill(p.ax.begin(), p.ax.end(), 0.0f);
  std::fill(p.ay.begin(), p.ay.end(), 0.0f);
  std::fill(p.az.begin(), p.az.end(), 0.0f);
  addSpringAccelerations(net, k, d, dt, p, index);
  for (size_t i = 0; i < p.size(); ++i) {
    p.vx[i] += p.ax[i] * dt; p.vy[i] += p.ay[i] * dt; p.vz[i] += p.az[i] * dt;
    p.x[i] += p.vx[i] * dt; p.y[i] += p.vy[i] * dt; p.z[i] += p.vz[i] * dt;
  }
}

double energy(const ParticleSet& p, float k, float restLength) {
  const double length = std::hypot(double(p.x[0] - p.x[1]), double(p.y[0] - p.y[1]), double(p.z[0] - p.z[1]));
  double e = 0.5 * k * (length - restLength) * (length - restLength);
  for (size_t i = 0; i < 2; ++i) e += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
  return e;
}

}  // namespace

TEST(SpringNetwork, JoinsEveryPairWithinTheRadiusWithItsInitialLength) {
  // 3 x 3 x 3 lattice of spacing 0.5, radius 0.75: face neighbours (0.5) and face diagonals
  // (0.707), not body diagonals (0.866): 54 + 72 = 126 springs; the centre has 18.
  const auto points = lattice(3, 0.5f);
  const SpringNetwork net = SpringNetwork::connect(points, iota(points.size()), 0.75f);
  EXPECT_EQ(net.springCount(), 126u);
  EXPECT_EQ(net.degree(13), 18u);
  EXPECT_EQ(net.degree(0), 6u);  // a corner: 3 faces + 3 diagonals
  for (const SpringNetwork::End* s = net.begin(13); s != net.end(13); ++s)
    EXPECT_NEAR(s->restLength, (points[13] - points[size_t(s->other)]).norm(), 1e-6f);
}

TEST(SpringForce, TwoParticlesOscillateAtTheAnalyticFrequency) {
  const float k = 30.0f, m = 0.125f, r0 = 0.5f;  // the paper's membrane spring, a 0.5 m particle
  ParticleSet p = particlesAt({{0, 0, 0}, {r0, 0, 0}}, m);
  const SpringNetwork net = SpringNetwork::connect({{0, 0, 0}, {r0, 0, 0}}, {0, 1}, 0.6f);
  p.x[1] = r0 + 0.05f;  // stretched by 10 %
  std::vector<uint32_t> index;
  indexParticlesById(p, index);
  const double omega = std::sqrt(2.0 * k / m), period = 2 * std::numbers::pi / omega;
  const float dt = float(period / 2000.0);
  const double e0 = energy(p, k, r0);
  double maxDrift = 0.0;
  // Time of the upward zero crossings of the extension, interpolated within the step.
  std::vector<double> crossings;
  double previous = p.x[1] - p.x[0] - r0, t = 0.0;
  for (int n = 0; n < 2000 * 100 + 10; ++n) {
    step(net, k, 0.0f, dt, p, index);
    t += dt;
    const double extension = p.x[1] - p.x[0] - r0;
    if (previous < 0.0 && extension >= 0.0) crossings.push_back(t - dt * extension / (extension - previous));
    previous = extension;
    maxDrift = std::max(maxDrift, std::fabs(energy(p, k, r0) - e0) / e0);
  }
  ASSERT_GE(crossings.size(), 100u);
  const double measured = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  EXPECT_NEAR(measured, period, 0.01 * period);
  EXPECT_LT(maxDrift, 0.01) << "energy drift over 100 periods";
}

TEST(SpringForce, DamperNeverAddsEnergy) {
  // With the damper, the energy at the same phase of successive oscillations (each maximum of
  // the extension) strictly decreases, and never exceeds the initial energy.
  const float k = 30.0f, m = 0.125f, r0 = 0.5f, d = 0.5f;
  ParticleSet p = particlesAt({{0, 0, 0}, {r0, 0, 0}}, m);
  const SpringNetwork net = SpringNetwork::connect({{0, 0, 0}, {r0, 0, 0}}, {0, 1}, 0.6f);
  p.x[1] = r0 + 0.05f;
  std::vector<uint32_t> index;
  indexParticlesById(p, index);
  const float dt = float(2 * std::numbers::pi / std::sqrt(2.0 * k / m) / 2000.0);
  const double e0 = energy(p, k, r0);
  std::vector<double> atMaxima;
  double before = 0.05, current = 0.05;
  for (int n = 0; n < 20000; ++n) {
    step(net, k, d, dt, p, index);
    const double next = p.x[1] - p.x[0] - r0;
    if (current > before && current >= next && current > 0) atMaxima.push_back(energy(p, k, r0));
    before = current;
    current = next;
    ASSERT_LE(energy(p, k, r0), e0 * (1 + 1e-6));
  }
  ASSERT_GE(atMaxima.size(), 3u);
  for (size_t i = 1; i < atMaxima.size(); ++i) EXPECT_LT(atMaxima[i], atMaxima[i - 1]);
}

TEST(LengthRatio, IsOneAtRestAndOneOverSWhenScaled) {
  const auto points = lattice(4, 0.5f);
  const SpringNetwork net = SpringNetwork::connect(points, iota(points.size()), 1.05f);
  for (float s : {1.0f, 1.7f, 0.5f}) {
    std::vector<Eigen::Vector3f> scaled;
    for (const auto& q : points) scaled.push_back(s * q);
    const ParticleSet p = particlesAt(scaled, 0.1f);
    std::vector<uint32_t> index;
    indexParticlesById(p, index);
    for (size_t i = 0; i < p.size(); ++i) {
      EXPECT_NEAR(lengthRatio(net, p, index, i), 1.0f / s, 1e-6f) << "scale " << s << ", particle " << i;
      // (10) L^dens = (L^leng)^3: a body stretched by s has its rest density divided by s^3.
      EXPECT_NEAR(std::pow(lengthRatio(net, p, index, i), 3.0f), 1.0f / (s * s * s), 1e-5f);
    }
  }
}
