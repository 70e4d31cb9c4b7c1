// SPH kernels of Mueller et al. 2003 (sim/kernels.h): normalisation, gradient, Laplacian.
#include "sim/kernels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

using namespace kurage::sim;

namespace {
// Integral of a radial function over the ball of radius h: int_0^h f(r) 4 pi r^2 dr (Simpson).
double integrateRadial(const std::function<double(double)>& f, double h) {
  const int n = 20000;
  const double dr = h / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double r = i * dr;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * f(r) * 4.0 * std::numbers::pi * r * r;
  }
  return sum * dr / 3.0;
}
}  // namespace

class KernelSupport : public ::testing::TestWithParam<float> {};

TEST_P(KernelSupport, Poly6IntegratesToOne) {
  const Poly6Kernel w(GetParam());
  EXPECT_NEAR(integrateRadial([&](double r) { return w(float(r)); }, w.h), 1.0, 1e-4);
}

TEST_P(KernelSupport, SpikyIntegratesToOne) {
  const SpikyKernel w(GetParam());
  EXPECT_NEAR(integrateRadial([&](double r) { return w(float(r)); }, w.h), 1.0, 1e-4);
}

TEST_P(KernelSupport, ViscosityIntegratesToOne) {
  const ViscosityKernel w(GetParam());
  // r^2 W(r) is bounded although W has an h/(2r) term; start just off zero.
  EXPECT_NEAR(integrateRadial([&](double r) { return r > 0 ? w(float(r)) : 0.0; }, w.h), 1.0, 1e-3);
}

TEST_P(KernelSupport, KernelsVanishOutsideSupportAndArePositiveInside) {
  const float h = GetParam();
  const Poly6Kernel poly6(h);
  const SpikyKernel spiky(h);
  const ViscosityKernel visc(h);
  for (float q : {0.01f, 0.3f, 0.7f, 0.99f}) {
    EXPECT_GT(poly6(q * h), 0.0f);
    EXPECT_GT(spiky(q * h), 0.0f);
    EXPECT_GT(visc(q * h), 0.0f);
    EXPECT_GT(visc.laplacian(q * h), 0.0f);
  }
  for (float q : {1.0f, 1.5f}) {
    EXPECT_EQ(poly6(q * h), 0.0f);
    EXPECT_EQ(spiky(q * h), 0.0f);
    EXPECT_EQ(visc(q * h), 0.0f);
    EXPECT_EQ(spiky.gradient(Eigen::Vector3f(q * h, 0, 0)).norm(), 0.0f);
    EXPECT_EQ(visc.laplacian(q * h), 0.0f);
  }
}

TEST_P(KernelSupport, SpikyGradientMatchesFiniteDifference) {
  const SpikyKernel w(GetParam());
  const double h = w.h;
  auto value = [&](const Eigen::Vector3d& p) { return double(w(float(p.norm()))); };
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.3, -0.5, 0.8).normalized(),
                                    Eigen::Vector3d(-1, 1, 1).normalized()}) {
    for (double q : {0.2, 0.5, 0.8}) {
      const Eigen::Vector3d p = q * h * dir;
      const double e = 1e-3 * h;
      Eigen::Vector3d fd;
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[a] = e;
        fd[a] = (value(p + d) - value(p - d)) / (2 * e);
      }
      const Eigen::Vector3d g = w.gradient(p.cast<float>()).cast<double>();
      EXPECT_NEAR((g - fd).norm() / fd.norm(), 0.0, 2e-3) << "q = " << q;
      EXPECT_LT(g.dot(dir), 0.0) << "the spiky kernel decreases outward";
    }
  }
}

TEST_P(KernelSupport, ViscosityLaplacianMatchesAnalyticFormula) {
  const ViscosityKernel w(GetParam());
  const double h = w.h;
  // The analytic Laplacian 45/(pi h^6) (h - r), and a numerical one of the kernel itself:
  // lap W = W'' + 2 W' / r for a radial function.
  for (double q : {0.2, 0.4, 0.6, 0.8}) {
    const double r = q * h;
    const double analytic = 45.0 / (std::numbers::pi * std::pow(h, 6)) * (h - r);
    EXPECT_NEAR(w.laplacian(float(r)), analytic, 1e-5 * analytic);
    const double e = 1e-3 * h;
    auto W = [&](double x) {  // evaluate in double for the finite difference
      const double s = x / h;
      return 15.0 / (2 * std::numbers::pi * h * h * h) * (-0.5 * s * s * s + s * s + 0.5 / s - 1.0);
    };
    EXPECT_NEAR(W(r), w(float(r)), 1e-4 * W(r));
    const double d1 = (W(r + e) - W(r - e)) / (2 * e);
    const double d2 = (W(r + e) - 2 * W(r) + W(r - e)) / (e * e);
    EXPECT_NEAR(d2 + 2 * d1 / r, analytic, 1e-3 * analytic);
  }
}

INSTANTIATE_TEST_SUITE_P(Radii, KernelSupport, ::testing::Values(0.1f, 1.5f, 2.0f));
