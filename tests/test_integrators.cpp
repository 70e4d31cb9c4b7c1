// The integrators' options against analytic answers: environment sampling with multiple
// importance sampling (the same mean as BSDF sampling alone, with far less variance under a sky
// with a bright patch), the whitted integrator (exact Lambert under a sun, a glass slab's
// Fresnel transmission with its internal reflections, a far ground under a uniform sky exactly
// its albedo, no dependence on seed or thread count, adaptive anti-aliasing's extra samples only
// at an edge and not at a filtered checker's, a sun glint in one sample clamped below white while
// the sun seen by the camera is not),
// adaptive sampling (no more than min_samples where there is no noise, the asked-for error
// where there is), and the denoiser (a noise-free checkerboard unchanged, a noisy plain ground's
// error cut threefold).
#include "furnace_scene.h"
#include "render/image.h"
#include "render/materials.h"
#include "render/renderer.h"
#include "render/sampling.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <utility>

namespace kr = kurage::render;
using Eigen::Vector3f;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// A plain ground seen from straight above, lit only by an equirectangular sky of radiance 0.2
// with a patch of radiance 40 about 40 degrees above the horizon (a soft "sun" of about 4.5e-3
// sr): BSDF sampling finds the patch rarely, sampling the sky by luminance finds it every time.
kr::RenderScene patchSky() {
  auto sky = std::make_shared<kr::Image>(64, 32, Eigen::Vector4f(0.2f, 0.2f, 0.2f, 1));
  for (int y = 11; y < 13; ++y)
    for (int x = 40; x < 42; ++x) sky->at(x, y) = Eigen::Vector4f(40, 40, 40, 1);
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Image;
  scene.environment.image = sky;
  scene.sun.irradiance = Vector3f::Zero();
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = {0.5f, 0.5f, 0.5f};
  scene.camera.position = {0, 0, 5};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.up = {0, 1, 0};
  scene.camera.verticalFovDegrees = 30.0f;
  return scene;
}

// Irradiance of a horizontal surface under the environment: the integral of L cos(theta) over
// the upper hemisphere, by the midpoint rule on a grid 16 times finer than the image (each
// image pixel is constant, so only the smooth sin cos factor is approximated).
float skyIrradiance(const kr::Environment& e) {
  const int w = 1024, h = 512;
  double sum = 0.0;
  Vector3f t, b;
  for (int y = 0; y < h / 2; ++y) {
    const double theta = kPi * (y + 0.5) / h;
    for (int x = 0; x < w; ++x) {
      const double phi = 2.0 * kPi * ((x + 0.5) / w - 0.5);
      const Vector3f d(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                       float(std::cos(theta)));
      sum += kr::environmentRadiance(e, d).x() * std::cos(theta) * std::sin(theta);
    }
  }
  return float(sum * 2.0 * kPi * kPi / (double(w) * h));
}

struct PixelStats {
  double mean = 0.0, variance = 0.0;  // of the red channel over all pixels
};

PixelStats stats(const kr::Image& image) {
  PixelStats s;
  const int n = image.width() * image.height();
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) s.mean += image.at(x, y).x();
  s.mean /= n;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) s.variance += std::pow(image.at(x, y).x() - s.mean, 2);
  s.variance /= (n - 1);
  return s;
}

// A closed box mesh (12 triangles, counter-clockwise seen from outside) from its centre, the
// half-extents along its local axes, and a rotation.
kr::TriangleMesh box(const Vector3f& centre, const Vector3f& half, const Eigen::Matrix3f& rotation) {
  kr::TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.positions.push_back(centre + rotation * Vector3f((i & 1 ? 1 : -1) * half.x(), (i & 2 ? 1 : -1) * half.y(),
                                                          (i & 4 ? 1 : -1) * half.z()));
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

// The ground (albedo 0.5) under the mesh `water` (n = 1.33, no absorption), the sun (E = 2) at
// `degrees` from the vertical, no sky, the camera 5 m above looking straight down.
kr::RenderScene groundUnderWater(const kr::TriangleMesh& water, float degrees, float fovDegrees) {
  const float theta = degrees * kPi / 180.0f;
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.environment.zenith = Vector3f::Zero();
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = {0.5f, 0.5f, 0.5f};
  scene.sun.direction = {std::sin(theta), 0, -std::cos(theta)};
  scene.sun.irradiance = {2, 2, 2};
  kr::Material material;
  material.type = kr::MaterialType::Dielectric;
  material.ior = 1.33f;
  material.absorption = Vector3f::Zero();
  scene.meshes.push_back({&water, material});
  scene.camera.position = {0, 0, 5};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.up = {0, 1, 0};
  scene.camera.verticalFovDegrees = fovDegrees;
  return scene;
}

// A ground of albedo a (a checker of cells `checker` metres with b, or plain where 0) lit only by
// a point sun of irradiance 1 straight overhead, seen from 20 m above (0.3, 0.1), the image's
// height `across` metres there and slanted (up = (0.2, 1, 0)).
kr::RenderScene groundUnderOverheadSun(float checker, float a, float b, float across) {
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.environment.zenith = Vector3f::Zero();
  scene.sun.direction = {0, 0, -1};
  scene.sun.angularDiameterDegrees = 0.0f;
  scene.sun.irradiance = Vector3f::Ones();
  scene.ground.checkerSize = checker;
  scene.ground.albedoA = Vector3f::Constant(a);
  scene.ground.albedoB = Vector3f::Constant(b);
  scene.camera.position = {0.3f, 0.1f, 20};
  scene.camera.lookAt = {0.3f, 0.1f, 0};
  scene.camera.up = {0.2f, 1, 0};
  scene.camera.verticalFovDegrees = 2.0f * std::atan(0.5f * across / 20.0f) * 180.0f / kPi;
  return scene;
}

}  // namespace

TEST(EnvironmentSampling, SameMeanAsBsdfSamplingWithFarLessVariance) {
  // Every pixel of the plain ground has the same expected value, albedo / pi * E, so the spread
  // over the pixels is the estimator's own variance. Each mean must lie within 5 standard errors
  // of the analytic value; sampling the sky must cut the variance at least tenfold.
  const kr::RenderScene scene = patchSky();
  kr::RenderSettings settings;
  settings.width = 48;
  settings.height = 48;
  settings.samplesPerPixel = 4;
  settings.maxDepth = 1;
  const float expected = 0.5f / kPi * skyIrradiance(scene.environment);
  settings.environmentSampling = false;
  const PixelStats bsdf = stats(kr::renderFrame(scene, settings));
  settings.environmentSampling = true;
  const PixelStats mis = stats(kr::renderFrame(scene, settings));
  const double n = settings.width * settings.height;
  EXPECT_NEAR(bsdf.mean, expected, 5.0 * std::sqrt(bsdf.variance / n)) << "BSDF sampling alone";
  EXPECT_NEAR(mis.mean, expected, 5.0 * std::sqrt(mis.variance / n) + 1e-4) << "sky sampled with MIS";
  EXPECT_LT(mis.variance, bsdf.variance / 10.0) << "variance " << mis.variance << " vs " << bsdf.variance;
}

TEST(EnvironmentSampling, DiffuseSphereInUniformSkyKeepsItsAlbedo) {
  // The furnace with the sky sampled as a light: the MIS estimator is no longer noise-free, but
  // its mean over the sphere's pixels is the albedo (5 standard errors).
  kr::RenderScene scene = kurage::test::furnaceScene(20.0f);  // the sphere fills the view
  kr::Material diffuse;
  diffuse.albedo = {0.6f, 0.6f, 0.6f};
  scene.spheres.push_back({{{0, 0, 0}}, {}, 1.0f, diffuse});
  kr::RenderSettings settings;
  settings.width = 32;
  settings.height = 32;
  settings.samplesPerPixel = 8;
  settings.maxDepth = 4;
  const PixelStats s = stats(kr::renderFrame(scene, settings));
  EXPECT_NEAR(s.mean, 0.6, 5.0 * std::sqrt(s.variance / (32.0 * 32.0)) + 1e-4);
  EXPECT_GT(s.variance, 0.0);  // the sky really was sampled (BSDF sampling alone has none here)
}

TEST(Whitted, DiffuseGroundUnderSunIsAlbedoTimesIrradianceCosOverPi) {
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.environment.zenith = Vector3f::Zero();
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = {0.3f, 0.6f, 0.9f};
  scene.sun.direction = {1, 0, -2};
  scene.sun.irradiance = {2.0f, 1.5f, 1.0f};
  scene.sun.angularDiameterDegrees = 0.53f;  // whitted takes the centre direction: hard
  scene.camera.position = {0, 0, 5};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.up = {0, 1, 0};
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.width = 16;
  settings.height = 16;
  settings.samplesPerPixel = 4;
  const kr::Image image = kr::renderFrame(scene, settings);
  const Vector3f expected = scene.ground.albedoA.cwiseProduct(scene.sun.irradiance) * (2.0f / std::sqrt(5.0f) / kPi);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      ASSERT_LT((image.at(x, y).head<3>() - expected).cwiseAbs().maxCoeff(), 1e-5f * expected.maxCoeff())
          << x << "," << y << ": " << image.at(x, y).head<3>().transpose();
}

TEST(Whitted, FarGroundUnderAUniformSkyIsAlbedoTimesRadianceEverywhere) {
  // A plain ground (albedo 0.5) under a uniform sky of radiance 1, no sun, seen at a grazing
  // angle out to about 20 km: every sky direction of every ground pixel reaches the sky, so each
  // pixel is exactly 0.5. A shading point computed a rounding error below the ground (which grows
  // with distance) must not find the ground in the way of its own sky rays.
  kr::RenderScene scene = kurage::test::furnaceScene(40.0f);
  scene.ground.enabled = true;
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = Vector3f::Constant(0.5f);
  scene.camera.position = {3, -7, 27};
  scene.camera.lookAt = {3.1f, 60, 0};
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.width = 64;
  settings.height = 48;
  settings.samplesPerPixel = 1;
  settings.whitted.skyDirections = 8;
  settings.transparentBackground = true;  // alpha tells the ground from the sky
  const kr::Image image = kr::renderFrame(scene, settings);
  int ground = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      if (image.at(x, y).w() == 0.0f) continue;  // the sky
      ++ground;
      ASSERT_NEAR(image.at(x, y).x(), 0.5f, 1e-5f) << "pixel " << x << "," << y;
    }
  EXPECT_GT(ground, settings.width * settings.height / 2);
}

TEST(Whitted, GlassSlabTransmitsFresnelSeriesWithAbsorption) {
  // A slab of glass (n = 1.5, thickness d, absorption sigma) in front of an area light of
  // radiance 1, seen through its face at 0 and at 40 degrees (the exit ray is parallel to the
  // camera ray and still meets the light). The light seen through it is the sum over the even
  // numbers of internal reflections, T = (1 - F)^2 a / (1 - F^2 a^2), a = exp(-sigma d / cos t),
  // F the Fresnel reflectance at the angle of incidence (the same inside, at the refraction
  // angle t). The tree keeps every branch of weight >= 1e-3: the neglected rest is below 1e-5.
  // The rays start 1e-4 x the scene's size (5.4 m) off each surface, so the path inside is
  // shorter by about 1e-3 m: a relative excess of sigma * 1e-3 = 4e-4, hence the tolerance.
  for (const float degrees : {0.0f, 40.0f}) {
    const float angle = degrees * kPi / 180.0f;
    const float d = 0.5f, sigma = 0.4f;
    const Eigen::Matrix3f rotation = Eigen::AngleAxisf(angle, Vector3f::UnitZ()).toRotationMatrix();
    const kr::TriangleMesh slab = box({0, 0, 0}, {5, d / 2, 5}, rotation);
    kr::RenderScene scene;
    scene.environment.type = kr::EnvironmentType::Uniform;
    scene.environment.zenith = Vector3f::Zero();
    scene.sun.irradiance = Vector3f::Zero();
    scene.ground.enabled = false;
    scene.rectLights.push_back({{-50, 10, -50}, {100, 0, 0}, {0, 0, 100}, {1, 1, 1}});  // faces -y
    kr::Material glass;
    glass.type = kr::MaterialType::Dielectric;
    glass.ior = 1.5f;
    glass.absorption = {sigma, sigma, sigma};
    scene.meshes.push_back({&slab, glass});
    scene.camera.position = {0, -5, 0};
    scene.camera.lookAt = {0, 0, 0};
    scene.camera.up = {0, 0, 1};
    scene.camera.verticalFovDegrees = 2.0f;
    kr::RenderSettings settings;
    settings.integrator = kr::IntegratorType::Whitted;
    settings.width = 5;
    settings.height = 5;
    settings.samplesPerPixel = 1;
    settings.maxDepth = 16;
    const kr::Image image = kr::renderFrame(scene, settings);
    const float cosI = std::cos(angle);
    const float sinT = std::sin(angle) / 1.5f, cosT = std::sqrt(1.0f - sinT * sinT);
    const float F = kr::fresnelDielectric(cosI, 1.0f, 1.5f);
    const float a = std::exp(-sigma * d / cosT);
    const float expected = (1 - F) * (1 - F) * a / (1 - F * F * a * a);
    EXPECT_NEAR(image.at(2, 2).x(), expected, 4e-4f * expected) << degrees << " degrees, F = " << F;
  }
}

TEST(Whitted, SunLightsTheFloorUnderFlatWaterThroughSnellsWindow) {
  // The ground under a flat layer of water (n = 1.33, no absorption), the sun at theta from the
  // vertical, no sky, the camera straight above. Physically the beam crosses the same horizontal
  // area in the water as above it: the floor's irradiance is E cos(theta) (1 - F(theta)). The
  // tracer does not scale radiance at refractions (materials.cpp), so what the camera receives
  // through the surface, (1 - F(0)) rho E cos(theta) (1 - F(theta)) / (pi n^2), needs the 1/n^2 at
  // the shadow ray's exit (etendue: the camera's path out of the water would carry it). The
  // unbent shadow ray stands for the refracted beam: its Fresnel factor is the air side's, at
  // theta. At 60 degrees the unbent ray meets the surface from below at more than the critical
  // angle (48.8 degrees): a Fresnel factor taken on the water's side would be total internal
  // reflection, a black floor.
  for (const float degrees : {10.0f, 35.0f, 60.0f}) {  // (overhead, the camera would see the sun mirrored)
    const float theta = degrees * kPi / 180.0f;
    const kr::TriangleMesh water = box({0, 0, 0}, {50, 50, 1}, Eigen::Matrix3f::Identity());  // z in [-1, 1]
    kr::RenderScene scene = groundUnderWater(water, degrees, 1.0f);
    kr::RenderSettings settings;
    settings.integrator = kr::IntegratorType::Whitted;
    settings.width = 3;
    settings.height = 3;
    settings.samplesPerPixel = 1;
    settings.maxDepth = 8;
    const kr::Image image = kr::renderFrame(scene, settings);
    const float expected = (1 - kr::fresnelDielectric(1.0f, 1.0f, 1.33f)) * 0.5f * 2.0f * std::cos(theta) *
                           (1 - kr::fresnelDielectric(std::cos(theta), 1.0f, 1.33f)) / (kPi * 1.33f * 1.33f);
    EXPECT_NEAR(image.at(1, 1).x(), expected, 1e-4f * expected) << degrees << " degrees";
    // The same layer lifted off the ground (z in [1, 3]): the ground is in the air, so the n^2 of
    // the shadow ray's entry cancels the one of its exit, and the layer lets (1 - F(theta))^2 of
    // the sun through (its internal reflections, F^2 of that, left out). The camera's path through
    // both faces keeps (1 - F0)^2 / (1 - F0^2) (the tree sums the reflections between them).
    const kr::TriangleMesh lifted = box({0, 0, 2}, {50, 50, 1}, Eigen::Matrix3f::Identity());
    scene.meshes.front().mesh = &lifted;
    const float f0 = kr::fresnelDielectric(1.0f, 1.0f, 1.33f);
    const float ft = kr::fresnelDielectric(std::cos(theta), 1.0f, 1.33f);
    const float throughAir =
        (1 - f0) * (1 - f0) / (1 - f0 * f0) * 0.5f * 2.0f * std::cos(theta) * (1 - ft) * (1 - ft) / kPi;
    EXPECT_NEAR(kr::renderFrame(scene, settings).at(1, 1).x(), throughAir, 1e-3f * throughAir)
        << degrees << " degrees, lifted";
  }
}

TEST(TransmissiveShadows, SameMeanAsExactTransportUnderFlatWater) {
  // The path tracer on the floor under flat water (as above), the sun 10 degrees wide so that
  // exact transport finds it: with transmissive_shadows false the floor is lit only by diffuse
  // bounces whose refracted path leaves the water into the sun's disk (caustics, exact, noisy);
  // with true by the unbent shadow ray and its n^2 rule. The two image means must agree within
  // 4 standard errors. Measured: 0.1840 / 0.1828 at 35 degrees, 0.1080 / 0.1052 at 60 (standard
  // errors 0.0019 and 0.0014). Before the shadow ray took the air's side's Fresnel factor and the
  // 1/n^2 for the sun as for the sky, it read about n^2 = 1.77 times too bright at 35 degrees
  // and black at 60 (total internal reflection of the unbent ray).
  for (const float degrees : {35.0f, 60.0f}) {
    const kr::TriangleMesh water = box({0, 0, 0}, {50, 50, 1}, Eigen::Matrix3f::Identity());
    kr::RenderScene scene = groundUnderWater(water, degrees, 5.0f);
    scene.sun.angularDiameterDegrees = 10.0f;
    PixelStats estimate[2];
    for (const bool transmissive : {true, false}) {
      kr::RenderSettings settings;
      settings.width = 32;
      settings.height = 32;
      settings.samplesPerPixel = transmissive ? 64 : 4096;
      settings.maxDepth = 8;
      settings.environmentSampling = false;
      settings.transmissiveShadows = transmissive;
      estimate[transmissive] = stats(kr::renderFrame(scene, settings));
    }
    const double standardError = std::sqrt((estimate[0].variance + estimate[1].variance) / 1024.0);
    EXPECT_NEAR(estimate[1].mean, estimate[0].mean, 4.0 * standardError) << degrees << " degrees";
    EXPECT_GT(estimate[0].mean, 0.05) << "exact transport found the sun";
  }
}

TEST(Sampling, CosineDirectionFromItsLocalPartsIsTheWholeWarpBitForBit) {
  // Whitted warps its fixed sky points once (cosineHemisphereLocal) and turns them about each
  // normal (fromLocal); that must be, float for float, the warp the images were made with.
  for (const Vector3f& axis : {Vector3f(0, 0, 1), Vector3f(0, 0, -1), Vector3f(0.3f, -0.5f, 0.81f), Vector3f(-0.9f, 0.2f, -0.1f)}) {
    const Vector3f n = axis.normalized();
    Vector3f t, b;
    kr::orthonormalBasis(n, t, b);
    for (int i = 0; i < 64; ++i) {
      const float u1 = (float(i) + 0.5f) / 64.0f, u2 = kr::radicalInverse2(uint32_t(i));
      const float r = std::sqrt(u1), phi = 2.0f * kPi * u2, z = std::sqrt(std::max(0.0f, 1.0f - u1));
      const Vector3f whole = (r * std::cos(phi) * t + r * std::sin(phi) * b + z * n).normalized();
      ASSERT_EQ(kr::fromLocal(kr::cosineHemisphereLocal(u1, u2), t, b, n), whole) << "point " << i;
      ASSERT_EQ(kr::sampleCosineHemisphere(n, u1, u2), whole) << "point " << i;
    }
  }
}

namespace {

// A long opaque wall h high, 0.1 m thick, along y from x = 0.
kr::TriangleMesh wallMesh(float h) {
  return box({0.05f, 0, 0.5f * h}, {0.05f, 100, 0.5f * h}, Eigen::Matrix3f::Identity());
}

// The ground (albedo 1) beside `wall` under a uniform sky of radiance 1, no sun, seen from 20 m
// straight above x = -1.1 m: `width` pixels span 2 m in x, `height` rows at the same pitch.
kr::RenderScene wallScene(const kr::TriangleMesh& wall, int width, int height) {
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.environment.zenith = Vector3f::Ones();
  scene.sun.irradiance = Vector3f::Zero();
  scene.ground.checkerSize = 0.0f;
  scene.ground.albedoA = Vector3f::Ones();
  scene.meshes.push_back({&wall, kr::Material{}});
  scene.camera.position = {-1.1f, 0, 20};
  scene.camera.lookAt = {-1.1f, 0, 0};
  scene.camera.up = {0, 1, 0};
  scene.camera.verticalFovDegrees = 2.0f * std::atan(float(height) / (20.0f * float(width))) * 180.0f / kPi;
  return scene;
}

}  // namespace

TEST(Whitted, SkyDirectionsDifferFromSampleToSampleOfAPixel) {
  // The ground (albedo 1) under a uniform sky of radiance 1 beside a long opaque wall 1 m high,
  // seen from straight above along a row of 64 pixels from d = 0.1 to 2.1 m off the wall. The wall
  // hides (1 - d / sqrt(d^2 + h^2)) / 2 of the sky's projected solid angle, so the ground shows
  // (1 + d / sqrt(d^2 + h^2)) / 2. Each of a pixel's samples takes its own sky_directions of one
  // Hammersley set of sky_directions x samples points: 4 directions at 16 samples follow the curve
  // as 64 would. With one sample, every pixel uses the same 4 directions, so the estimate steps in
  // quarters and the wall's sky shadow is a set of hard copies of it.
  const float h = 1.0f;
  const kr::TriangleMesh wall = wallMesh(h);
  const int width = 64;
  const kr::RenderScene scene = wallScene(wall, width, 1);
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.whitted.skyDirections = 4;
  settings.whitted.adaptive.enabled = false;  // every pixel its samples
  settings.width = width;
  settings.height = 1;
  const auto rmsError = [&](int samples) {
    settings.samplesPerPixel = samples;
    const kr::Image image = kr::renderFrame(scene, settings);
    double sum = 0.0;
    for (int i = 0; i < width; ++i) {
      const float d = 2.1f - 2.0f * (float(i) + 0.5f) / float(width);  // distance from the wall, m
      sum += std::pow(image.at(i, 0).x() - 0.5f * (1.0f + d / std::sqrt(d * d + h * h)), 2);
    }
    return std::sqrt(sum / width);
  };
  const double one = rmsError(1), sixteen = rmsError(16);
  EXPECT_LT(sixteen, 0.02);
  EXPECT_LT(sixteen, one / 3.0);
}

TEST(CheckerFilter, BoxMeanIsTheSquareWavesMeanAndVanishesOverWholePairsOfCells) {
  // checkerWaveMean against the mean of (-1)^floor(x) at 200,000 midpoints of the interval, on
  // intervals across zero, inside one cell, and over whole pairs of cells (mean 0).
  for (const auto& [x0, x1] : {std::pair{-2.3, 0.7}, std::pair{0.2, 0.9}, std::pair{1.25, 1.75}, std::pair{-7.6, 4.1},
                               std::pair{3.5, 3.5 + 1e-3}, std::pair{0.5, 4.5}}) {
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += std::fmod(std::abs(std::floor(x0 + (x1 - x0) * (i + 0.5) / n)), 2.0) == 0.0 ? 1 : -1;
    EXPECT_NEAR(kr::checkerWaveMean(x0, x1), sum / n, 1e-4) << x0 << " .. " << x1;
  }
  EXPECT_NEAR(kr::checkerWaveMean(0.5, 4.5), 0.0, 1e-12);
  EXPECT_EQ(kr::checkerWaveMean(-0.5, -0.5), -1.0);
  kr::Material m;
  m.checkerSize = 0.5f;
  m.albedoB = {0.1f, 0.2f, 0.3f};
  const Vector3f p(0.3f, -0.8f, 1.1f);
  EXPECT_EQ(kr::checkerAlbedoFiltered(m, m.albedo, p, Vector3f::Zero()), kr::checkerAlbedo(m, m.albedo, p));
  // a box one cell pair wide on any axis: the even and odd cells' mean
  const Vector3f mean = 0.5f * (m.albedo + m.albedoB);
  EXPECT_LT((kr::checkerAlbedoFiltered(m, m.albedo, p, {0, 1.0f, 0}) - mean).cwiseAbs().maxCoeff(), 1e-6f);
}

TEST(Whitted, FilteredCheckersAverageCellsSmallerThanAPixelWithFewSamples) {
  // A checker ground of 6 cm cells seen from 10 m straight above, 8.4 cm a pixel (1.4 cells: point
  // samples alias into a moire), under a sun and a uniform sky. With its checkers box-filtered
  // over the pixel's ray cone, whitted at 1 and 4 samples is within a third of the error point
  // samples leave, against the frame point-sampled at 256 samples (16 samples a cell).
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.ground.checkerSize = 0.06f;
  scene.camera.position = {0.013f, 0.029f, 10};
  scene.camera.lookAt = {0.013f, 0.029f, 0};
  scene.camera.up = {0, 1, 0};
  scene.camera.verticalFovDegrees = 30.0f;
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.whitted.skyDirections = 1;
  settings.whitted.adaptive.enabled = false;  // every pixel its samples
  settings.width = 64;
  settings.height = 64;
  const auto render = [&](int samples, bool filter) {
    settings.samplesPerPixel = samples;
    settings.whitted.filterTextures = filter;
    return kr::renderFrame(scene, settings);
  };
  const kr::Image truth = render(256, false);
  const auto rmse = [&](const kr::Image& image) {
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) sum += (image.at(x, y) - truth.at(x, y)).head<3>().squaredNorm() / 3.0;
    return std::sqrt(sum / (image.width() * image.height()));
  };
  for (int samples : {1, 4}) {
    const double point = rmse(render(samples, false)), filtered = rmse(render(samples, true));
    EXPECT_LT(filtered, point / 3.0) << samples << " samples: point-sampled " << point;
  }
}

TEST(Whitted, ImageDependsOnNeitherSeedNorThreadCount) {
  kr::RenderScene scene;  // default gradient sky, sun, checker ground
  kr::Material water;
  water.type = kr::MaterialType::Dielectric;
  water.absorption = {0.3f, 0.1f, 0.05f};
  kr::Material body;
  body.type = kr::MaterialType::Translucent;
  body.albedo = {0.9f, 0.5f, 0.6f};
  scene.spheres.push_back({{{0, 0, 1}, {1.5f, 0.5f, 0.8f}}, {}, 0.8f, water});
  scene.spheres.push_back({{{-1.5f, 0.5f, 0.6f}}, {}, 0.6f, body});
  scene.rectLights.push_back({{-1, -1, 4}, {2, 0, 0}, {0, 2, 0}, {3, 3, 3}});
  scene.camera.position = {1, -6, 3};
  scene.camera.lookAt = {0, 0, 0.5f};
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.width = 53;  // not a multiple of the tile size
  settings.height = 37;
  settings.samplesPerPixel = 5;
  for (const bool adaptive : {false, true}) {
    settings.whitted.adaptive.enabled = adaptive;
    const auto render = [&](int threads, int seed, kr::RenderStats* stats = nullptr) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
      settings.seed = seed;
      return kr::renderFrame(scene, settings, stats);
    };
    kr::RenderStats oneStats, twoStats;
    const kr::Image one = render(1, 0, &oneStats);
    const kr::Image two = render(2, 0, &twoStats);
    const kr::Image seeded = render(2, 12345);
    int distinct = 0;
    for (int y = 0; y < one.height(); ++y)
      for (int x = 0; x < one.width(); ++x) {
        ASSERT_EQ(one.at(x, y), two.at(x, y)) << "pixel " << x << "," << y << (adaptive ? ", adaptive" : "");
        ASSERT_EQ(one.at(x, y), seeded.at(x, y)) << "pixel " << x << "," << y << (adaptive ? ", adaptive" : "");
        distinct += one.at(x, y) != one.at(0, 0);
      }
    EXPECT_GT(distinct, one.width() * one.height() / 4);  // something was rendered
    EXPECT_EQ(oneStats.pixelSamples, twoStats.pixelSamples);
    // adaptive: the first pass's 2 samples everywhere, 2 + 5 at the spheres' outlines
    const auto least = std::min_element(oneStats.pixelSamples.begin(), oneStats.pixelSamples.end());
    const auto most = std::max_element(oneStats.pixelSamples.begin(), oneStats.pixelSamples.end());
    EXPECT_EQ(*least, adaptive ? 2u : 5u);
    EXPECT_EQ(*most, adaptive ? 7u : 5u);
  }
}

TEST(Whitted, AdaptiveAntiAliasingSamplesTheEdgeAndLeavesFlatRegionsAtTheMinimum) {
  // A plain ground (albedo 0.2) and the top of a box (albedo 0.9, x > 0) seen from straight above,
  // lit by a sun overhead and nothing else: two flat values and one straight edge between them.
  // With 2 samples first and 16 where needed, the pixels the edge crosses well inside and their
  // neighbours across it take 2 + 16 samples, as the uniform 16-sample render's pixels; every
  // other pixel takes 2, as the uniform 2-sample render's.
  const kr::TriangleMesh top = box({5, 0, 0.5f}, {5, 10, 0.5f}, Eigen::Matrix3f::Identity());
  // over the box (its side wall hidden), the edge slanting across the image
  kr::RenderScene scene = groundUnderOverheadSun(0.0f, 0.2f, 0.2f, 2.0f);
  kr::Material white;
  white.albedo = Vector3f::Constant(0.9f);
  scene.meshes.push_back({&top, white});
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.width = 40;
  settings.height = 32;
  settings.whitted.adaptive.enabled = false;
  const auto render = [&](int samples, kr::RenderStats* stats = nullptr) {
    settings.samplesPerPixel = samples;
    return kr::renderFrame(scene, settings, stats);
  };
  const kr::Image two = render(2), sixteen = render(16);
  settings.whitted.adaptive = {true, 0.02f, 2};
  kr::RenderStats stats;
  const kr::Image adaptive = render(16, &stats);
  const float ground = kr::linearToSrgb(0.2f / kPi), white09 = kr::linearToSrgb(0.9f / kPi);
  int inside = 0, refined = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const float v = kr::linearToSrgb(sixteen.at(x, y).x());
      const bool onEdge = std::abs(v - ground) > 0.1f && std::abs(v - white09) > 0.1f;
      const uint32_t n = stats.pixelSamples[size_t(y * settings.width + x)];
      inside += onEdge ? 1 : 0;
      refined += n == 18 ? 1 : 0;
      if (onEdge) {
        EXPECT_EQ(n, 18u) << "edge pixel " << x << "," << y;
      }
      ASSERT_TRUE(n == 2 || n == 18) << n;
      EXPECT_EQ(adaptive.at(x, y), (n == 18 ? sixteen : two).at(x, y)) << "pixel " << x << "," << y;
    }
  EXPECT_GE(inside, settings.height / 3);  // the edge crosses the image
  EXPECT_LE(refined, 3 * settings.height);  // the edge's pixels and their neighbours, no more
  EXPECT_GE(refined, 2 * settings.height);
  EXPECT_EQ(stats.samples, uint64_t(2 * settings.width * settings.height + 16 * refined));
}

TEST(Whitted, AdaptiveAntiAliasingLeavesFilteredCheckerEdgesAtTheMinimum) {
  // A high-contrast checker ground (cells of 0.37 m, albedo 0.9 and 0.1) seen from above under a
  // sun overhead: the cone filter already averages each pixel's cells, so no pixel is refined and
  // the image is the uniform 2-sample render. Point-sampled, the checker's edges are refined.
  const kr::RenderScene scene = groundUnderOverheadSun(0.37f, 0.9f, 0.1f, 8.0f);
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.width = 40;
  settings.height = 32;
  for (const bool filter : {true, false}) {
    settings.whitted.filterTextures = filter;
    settings.whitted.adaptive.enabled = false;
    settings.samplesPerPixel = 2;
    const kr::Image two = kr::renderFrame(scene, settings);
    settings.samplesPerPixel = 16;
    settings.whitted.adaptive = {true, 0.02f, 2};
    kr::RenderStats stats;
    const kr::Image adaptive = kr::renderFrame(scene, settings, &stats);
    const auto refined = std::count(stats.pixelSamples.begin(), stats.pixelSamples.end(), 18u);
    if (filter) {
      EXPECT_EQ(refined, 0);
      for (int y = 0; y < settings.height; ++y)
        for (int x = 0; x < settings.width; ++x) ASSERT_EQ(adaptive.at(x, y), two.at(x, y)) << x << "," << y;
    } else {
      EXPECT_GT(refined, settings.width * settings.height / 4);  // about 4 cells' edges a row
    }
  }
}

// A sun glint: flat water (n = 1.33) seen from straight above under an overhead sun of 0.53
// degrees, no sky. Only camera rays within 0.265 degrees of the vertical see the sun mirrored, a
// disc about the middle of the centre pixel (0.67 degrees) that 2 of its 8 samples hit; each one's
// reflected branch carries F(0) E / Omega, about 600. Clamped, the pixel stays at most
// clamp_secondary (the mirrored sun is all of a sample's light there); unclamped it saturates.
// A sun of 5 degrees, mirrored over the whole pixel, still makes it exactly the clamp: white.
TEST(Whitted, ASunGlintSeenByOneSampleIsClampedBelowWhite) {
  const kr::TriangleMesh water = box({0, 0, 0}, {50, 50, 1}, Eigen::Matrix3f::Identity());  // z in [-1, 1]
  kr::RenderScene scene = groundUnderWater(water, 0.0f, 10.0f);
  scene.sun.angularDiameterDegrees = 0.53f;
  scene.camera.position = {0.3f, 0.1f, 5};  // the centre's rays off the diagonal edge of the water's top
  scene.camera.lookAt = {0.3f, 0.1f, 0};
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.width = 15;
  settings.height = 15;
  settings.samplesPerPixel = 8;
  ASSERT_EQ(settings.whitted.clampSecondary, 1.0f);  // the default
  settings.whitted.clampSecondary = 0.0f;
  const kr::Image glint = kr::renderFrame(scene, settings);
  ASSERT_GT(glint.at(7, 7).head<3>().minCoeff(), 50.0f) << "the glint is there unclamped";
  settings.whitted.clampSecondary = 1.0f;
  const kr::Image clamped = kr::renderFrame(scene, settings);
  for (int y = 0; y < 15; ++y)
    for (int x = 0; x < 15; ++x) {
      EXPECT_LE(clamped.at(x, y).head<3>().maxCoeff(), 1.0f + 1e-6f) << x << "," << y;
      if (x != 7 || y != 7) {
        EXPECT_TRUE(clamped.at(x, y) == glint.at(x, y)) << x << "," << y << ": below the clamp";
      }
    }
  EXPECT_GT(clamped.at(7, 7).x(), clamped.at(6, 7).x()) << "still brighter than its neighbours";
  scene.sun.angularDiameterDegrees = 5.0f;
  const kr::Image wide = kr::renderFrame(scene, settings);
  EXPECT_NEAR(wide.at(7, 7).x(), 1.0f, 1e-6f);
  EXPECT_NEAR(wide.at(7, 7).z(), 1.0f, 1e-6f);
}

// The camera's own view of the sun's disc is direct light: the same with and without the clamp,
// E / Omega (Omega = 2 pi (1 - cos(0.265 degrees))).
TEST(Whitted, TheSunSeenByTheCameraIsNotClamped) {
  kr::RenderScene scene;
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.environment.zenith = Vector3f::Zero();
  scene.ground.enabled = false;
  scene.sun.direction = {0, 0, -1};
  scene.sun.irradiance = {2.6f, 2.5f, 2.3f};
  scene.sun.angularDiameterDegrees = 0.53f;
  scene.camera.position = {0, 0, 0};
  scene.camera.lookAt = {0, 0, 1};
  scene.camera.up = {0, 1, 0};
  scene.camera.verticalFovDegrees = 0.2f;
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.width = 5;
  settings.height = 5;
  settings.samplesPerPixel = 4;
  const kr::Image clamped = kr::renderFrame(scene, settings);
  settings.whitted.clampSecondary = 0.0f;
  const kr::Image exact = kr::renderFrame(scene, settings);
  const double omega = 2.0 * std::numbers::pi * (1.0 - std::cos(0.265 * std::numbers::pi / 180.0));
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      EXPECT_TRUE(clamped.at(x, y) == exact.at(x, y)) << x << "," << y;
      EXPECT_NEAR(clamped.at(x, y).x(), 2.6 / omega, 1e-2 * 2.6 / omega) << x << "," << y;  // float's 1 - cos
    }
}

TEST(Adaptive, TakesMinSamplesWithoutNoiseAndReachesTheErrorWithIt) {
  kr::RenderSettings settings;
  settings.width = 24;
  settings.height = 24;
  settings.maxDepth = 1;
  settings.environmentSampling = false;
  settings.adaptive.enabled = true;
  settings.adaptive.minSamples = 8;
  settings.adaptive.maxSamples = 4096;
  settings.adaptive.relativeError = 0.05f;
  const double pixels = settings.width * settings.height;
  // A hard sun on the plain ground, black sky: every path gives the same value.
  kr::RenderScene still = patchSky();
  still.environment.type = kr::EnvironmentType::Uniform;
  still.environment.zenith = Vector3f::Zero();
  still.sun.irradiance = {1, 1, 1};
  still.sun.angularDiameterDegrees = 0.0f;
  kr::RenderStats stillStats;
  kr::renderFrame(still, settings, &stillStats);
  EXPECT_EQ(stillStats.samples, uint64_t(8 * pixels));
  // The patch sky, sampled with MIS: noisy. Each pixel stops once the standard error of its
  // mean is 5 % of it; the spread of the pixels about the true value must then be about that
  // (up to 1.5 times: the error is itself estimated from the samples), and it took more samples.
  // (By BSDF sampling alone the patch is a rare event: 8 paths that all miss it show no variance
  // and the pixel stops, too dark. Adaptive sampling needs an estimator without rare events.)
  settings.environmentSampling = true;
  const kr::RenderScene noisy = patchSky();
  kr::RenderStats noisyStats;
  const PixelStats s = stats(kr::renderFrame(noisy, settings, &noisyStats));
  const double expected = 0.5 / kPi * skyIrradiance(noisy.environment);
  double squares = 0.0;
  const kr::Image image = kr::renderFrame(noisy, settings);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) squares += std::pow(image.at(x, y).x() - expected, 2);
  EXPECT_LT(std::sqrt(squares / pixels) / expected, 1.5 * 0.05);
  EXPECT_GT(noisyStats.samples, uint64_t(4 * 8 * pixels));  // at least 4 batches on average
  EXPECT_NEAR(s.mean, expected, 0.02 * expected);
}

TEST(Denoise, ItsTapWeightExpMatchesStdExp) {
  double worst = 0.0;
  for (int k = 0; k <= 79999; ++k) {
    const float x = 0.001f * float(k);  // 0 .. 79.999
    const double exact = std::exp(-double(x));
    worst = std::max(worst, std::fabs(double(kr::expNegative(x)) - exact) / exact);
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_EQ(kr::expNegative(0.0f), 1.0f);
  EXPECT_EQ(kr::expNegative(80.0f), 0.0f);
  EXPECT_EQ(kr::expNegative(1e30f), 0.0f);
  EXPECT_EQ(kr::expNegative(std::numeric_limits<float>::infinity()), 0.0f);
  EXPECT_EQ(kr::expNegative(std::numeric_limits<float>::quiet_NaN()), 0.0f);
}

TEST(Denoise, LeavesANoiseFreeCheckerboardAsItWas) {
  // A checker ground under a uniform sky of radiance 1, by BSDF sampling alone: every path gives
  // the albedo, so the image is exact and has sharp edges. The denoiser divides the colour by the
  // albedo buffer (giving 1 everywhere, edge pixels included: both are averages of the same
  // samples), filters, and multiplies back: the image must come out unchanged. A filter that
  // smoothed the colour itself would blur every edge.
  kr::RenderScene scene = patchSky();
  scene.environment.type = kr::EnvironmentType::Uniform;
  scene.environment.zenith = {1, 1, 1};
  scene.ground.checkerSize = 0.5f;
  scene.ground.albedoA = {0.8f, 0.7f, 0.6f};
  scene.ground.albedoB = {0.1f, 0.2f, 0.3f};
  kr::RenderSettings settings;
  settings.width = 40;
  settings.height = 40;
  settings.samplesPerPixel = 4;
  settings.environmentSampling = false;
  const kr::Image plain = kr::renderFrame(scene, settings);
  settings.denoise.enabled = true;
  const kr::Image filtered = kr::renderFrame(scene, settings);
  int edges = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      ASSERT_LT((filtered.at(x, y) - plain.at(x, y)).cwiseAbs().maxCoeff(), 1e-5f) << x << "," << y;
      edges += x > 0 && (plain.at(x, y) - plain.at(x - 1, y)).cwiseAbs().maxCoeff() > 0.3f;
    }
  EXPECT_GT(edges, 40);  // the checkerboard is there
}

TEST(Denoise, ItsColourWidthNarrowsAsTheSamplesGrow) {
  // A lighting edge (a shadow's: the same albedo and normal on both sides, so only the colour
  // weight can keep it) between 0.5 and 0.8: at 4 samples per pixel such a step is within the
  // noise and the filter smooths it; at 1,024 the noise is 16 times smaller, so is the colour
  // width, and the edge stays. A fixed width would blur it at any sample count.
  const int w = 32, h = 8;
  kr::Image image(w, h);
  kr::FeatureBuffers features;
  features.width = w;
  features.height = h;
  features.albedo.assign(size_t(w * h), Eigen::Vector3f::Constant(0.5f));
  features.normal.assign(size_t(w * h), Eigen::Vector3f(0, 0, 1));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image.at(x, y) = Eigen::Vector4f(x < w / 2 ? 0.5f : 0.8f, x < w / 2 ? 0.5f : 0.8f, x < w / 2 ? 0.5f : 0.8f, 1.0f);
  kr::DenoiseSettings settings;
  settings.enabled = true;
  const auto step = [&](double spp) {
    const kr::Image out = kr::denoise(image, features, settings, spp);
    return out.at(w / 2, h / 2).x() - out.at(w / 2 - 1, h / 2).x();
  };
  EXPECT_LT(step(4.0), 0.5f * 0.3f) << "smoothed at 4 spp";
  EXPECT_GT(step(1024.0), 0.9f * 0.3f) << "kept at 1024 spp";
  EXPECT_THROW(kr::denoise(image, features, settings, 0.0), std::invalid_argument);
}

TEST(Denoise, KeepsTheSunsShadowEdgeSharp) {
  // The plain ground under the patch sky (noisy) and an overhead point sun, half of it in the
  // shadow of a slab above the camera: a hard lighting edge across the image. The sun's direct
  // light at the first diffuse vertex is left out of the filter and added back after it, so the
  // edge keeps its step while the sky's noise is smoothed: within 3 pixels of the edge the
  // filtered 4-spp frame must be nearly as close to a 1,024-spp frame as it is away from it
  // (1.8 times the RMSE; filtering the whole colour blurred the edge: 7.2 times).
  kr::RenderScene scene = patchSky();
  const kr::TriangleMesh slab = box({-10.5f, 0, 8}, {10, 10, 0.5f}, Eigen::Matrix3f::Identity());  // x < -0.5
  scene.meshes.push_back({&slab, kr::Material{}});
  scene.sun.irradiance = {1.5f, 1.5f, 1.5f};
  scene.sun.direction = {0, 0, -1};
  scene.sun.angularDiameterDegrees = 0.0f;
  kr::RenderSettings settings;
  settings.width = 64;
  settings.height = 32;
  settings.maxDepth = 1;
  settings.samplesPerPixel = 1024;
  const kr::Image reference = kr::renderFrame(scene, settings);
  settings.samplesPerPixel = 4;
  settings.denoise.enabled = true;
  const kr::Image filtered = kr::renderFrame(scene, settings);
  int edge = -1;  // the first lit column
  for (int x = 1; x < 64 && edge < 0; ++x)
    if (reference.at(x, 16).x() > 1.5f * reference.at(x - 1, 16).x()) edge = x;
  ASSERT_GT(edge, 8);
  ASSERT_LT(edge, 56);
  double near = 0.0, far = 0.0;
  int nNear = 0, nFar = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      const double d2 = std::pow(filtered.at(x, y).x() - reference.at(x, y).x(), 2);
      if (std::abs(x - edge) <= 3) near += d2, ++nNear;
      else far += d2, ++nFar;
    }
  near = std::sqrt(near / nNear);
  far = std::sqrt(far / nFar);
  EXPECT_LT(near, 3.0 * far) << "near the edge " << near << ", away from it " << far;
}

TEST(Denoise, RemovesMostOfTheNoiseOfAPlainGround) {
  // The plain ground under the patch sky, 2 paths per pixel: every pixel's true value is
  // albedo / pi * E. The filter must cut the RMSE about it at least threefold.
  const kr::RenderScene scene = patchSky();
  kr::RenderSettings settings;
  settings.width = 64;
  settings.height = 64;
  settings.samplesPerPixel = 2;
  settings.maxDepth = 1;
  const double expected = 0.5 / kPi * skyIrradiance(scene.environment);
  const auto rmse = [&](const kr::Image& image) {
    double squares = 0.0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) squares += std::pow(image.at(x, y).x() - expected, 2);
    return std::sqrt(squares / (64.0 * 64.0));
  };
  const double noisy = rmse(kr::renderFrame(scene, settings));
  settings.denoise.enabled = true;
  const double filtered = rmse(kr::renderFrame(scene, settings));
  EXPECT_LT(filtered, noisy / 3.0) << "noisy " << noisy << ", filtered " << filtered;
  EXPECT_GT(noisy, 0.05 * expected);  // there was noise to remove
}

TEST(FresnelSplitting, SameMeanWithLessNoiseOnAWaterSurface) {
  // A slab of water on the checker ground under the default sky, seen at 60 degrees from the
  // vertical, direct light only (max depth 1): each camera ray either mirrors the sky
  // (probability F) or enters the water, where the path ends. The noise of one render is
  // estimated from two seeds (half the mean squared difference); the two estimators' image means
  // must agree within 5 standard errors, and splitting must remove most of the variance (what is
  // left is the sky's and the checker's variation across a pixel). On the jellyfish frame at 4
  // spp splitting takes the noise from 0.107 to 0.073 RMSE (kurage bench render --variance).
  const kr::TriangleMesh slab = box({0, 0, 0.5f}, {20, 20, 0.5f}, Eigen::Matrix3f::Identity());
  kr::RenderScene scene;
  kr::Material water;
  water.type = kr::MaterialType::Dielectric;
  water.absorption = {0.2f, 0.05f, 0.02f};
  scene.meshes.push_back({&slab, water});
  scene.sun.irradiance = Vector3f::Zero();
  scene.camera.position = {0, -6, 4.5f};
  scene.camera.lookAt = {0, 0, 1};
  kr::RenderSettings settings;
  settings.width = 32;
  settings.height = 32;
  settings.samplesPerPixel = 4;
  settings.maxDepth = 1;
  const auto measure = [&](bool split, double& mean, double& variance) {
    settings.fresnelSplitting = split;
    settings.seed = 0;
    const kr::Image a = kr::renderFrame(scene, settings);
    settings.seed = 1;
    const kr::Image b = kr::renderFrame(scene, settings);
    mean = variance = 0.0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        mean += 0.5 * (a.at(x, y).y() + b.at(x, y).y()) / 1024.0;
        variance += 0.5 * std::pow(a.at(x, y).y() - b.at(x, y).y(), 2) / 1024.0;
      }
  };
  double chooseMean, chooseVariance, splitMean, splitVariance;
  measure(false, chooseMean, chooseVariance);
  measure(true, splitMean, splitVariance);
  EXPECT_NEAR(splitMean, chooseMean, 5.0 * std::sqrt((chooseVariance + splitVariance) / 2048.0));
  EXPECT_LT(splitVariance, chooseVariance / 3.0) << splitVariance << " vs " << chooseVariance;
}

TEST(Whitted, InterleavedSkyOnAnOpenCheckerPlaneConvergesToTheSameValue) {
  // A checker ground (0.2 and 0.8, cells of 4 pixels) seen from straight above under the gradient
  // sky alone, one sample of 2 sky directions. Without the sky filter every pixel sees the same 2
  // directions; with it each pixel of a 4 x 4 tile turns them its own way and the sky term is
  // averaged over the tile: the frame is then that of 256 directions to within a third of the
  // unfiltered error, in RMSE over the whole frame (a window cut by the border still holds every
  // elevation band) and at every pixel 2 or more from the border, checkers' edges included (the
  // albedo is divided out).
  kr::RenderScene scene;
  scene.sun.irradiance = Vector3f::Zero();
  scene.ground.checkerSize = 0.5f;
  scene.ground.albedoA = Vector3f::Constant(0.8f);
  scene.ground.albedoB = Vector3f::Constant(0.2f);
  scene.camera.position = {0.01f, 0.02f, 10};
  scene.camera.lookAt = {0.01f, 0.02f, 0};
  scene.camera.up = {0, 1, 0};
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.whitted.skyDirections = 2;
  settings.whitted.adaptive.enabled = false;
  settings.width = settings.height = 64;
  scene.camera.verticalFovDegrees = 2.0f * std::atan(4.0f / 10.0f) * 180.0f / kPi;  // 8 m, 4 pixels a cell
  const auto render = [&](int samples, bool filter) {
    settings.samplesPerPixel = samples;
    settings.whitted.skyFilter.enabled = filter;
    settings.whitted.skyFilter.tile = 4;
    return kr::renderFrame(scene, settings);
  };
  settings.whitted.skyDirections = 256;
  const kr::Image truth = render(1, false);
  settings.whitted.skyDirections = 2;
  const auto errors = [&](const kr::Image& image) {
    double sum = 0.0, most = 0.0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) {
        const double e = (image.at(x, y) - truth.at(x, y)).head<3>().cwiseAbs().maxCoeff();
        sum += e * e;
        if (x >= 2 && y >= 2 && x < image.width() - 2 && y < image.height() - 2) most = std::max(most, e);
      }
    return std::pair{std::sqrt(sum / (image.width() * image.height())), most};
  };
  const auto [plain, plainMost] = errors(render(1, false));
  const auto [filtered, filteredMost] = errors(render(1, true));
  EXPECT_LT(filtered, plain / 3.0) << "unfiltered " << plain;
  EXPECT_LT(filteredMost, plainMost / 3.0) << "unfiltered " << plainMost;
}

TEST(Whitted, InterleavedSkyFollowsAWallsSkyShadow) {
  // The wall of SkyDirectionsDifferFromSampleToSampleOfAPixel, 8 rows of pixels: at 1 sample of 4
  // sky directions the sky filter (4 x 4) follows the wall's sky shadow within a third of the
  // unfiltered error (the window reaches 2 pixels, 6 cm, across the curve).
  const float h = 1.0f;
  const kr::TriangleMesh wall = wallMesh(h);
  const int width = 64, height = 8;
  const kr::RenderScene scene = wallScene(wall, width, height);
  kr::RenderSettings settings;
  settings.integrator = kr::IntegratorType::Whitted;
  settings.whitted.skyDirections = 4;
  settings.whitted.adaptive.enabled = false;
  settings.samplesPerPixel = 1;
  settings.width = width;
  settings.height = height;
  const auto rmsError = [&](bool filter) {
    settings.whitted.skyFilter.enabled = filter;
    const kr::Image image = kr::renderFrame(scene, settings);
    double sum = 0.0;
    for (int y = 0; y < height; ++y)
      for (int i = 0; i < width; ++i) {
        const float d = 2.1f - 2.0f * (float(i) + 0.5f) / float(width);  // distance from the wall, m
        sum += std::pow(image.at(i, y).x() - 0.5f * (1.0f + d / std::sqrt(d * d + h * h)), 2);
      }
    return std::sqrt(sum / (width * height));
  };
  const double plain = rmsError(false), filtered = rmsError(true);
  EXPECT_LT(filtered, plain / 3.0) << "unfiltered " << plain;
}
