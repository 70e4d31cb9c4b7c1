// Surface materials and their scattering: what the integrators (integrators/) ask of a surface.
//
//   diffuse      Lambert reflection, f = albedo / pi.
//   dielectric   a smooth interface between air (IOR 1) and a medium of index `ior`: exact
//                unpolarised Fresnel reflectance F, reflection with probability F, refraction
//                (Snell) with probability 1 - F, each with weight 1, so no energy is lost at the
//                interface. Inside, light is attenuated by Beer-Lambert absorption
//                exp(-absorption * distance) (applied by the tracer). Water: ior 1.33.
//   translucent  a tinted soft body: a smooth Fresnel-reflecting interface (probability F,
//                weight 1) whose transmitted light is scattered diffusely into the other side
//                (probability 1 - F, weight `albedo` = the tint). Closed surfaces of it glow
//                through like wax or gel; with albedo 1 it loses no energy.
//   mirror       a smooth conductor: perfect reflection with colour `albedo` (the reflectance).
// Any of them may carry a 3-D checker texture on `albedo` (floors, tank walls).
//
// Conventions: directions are unit vectors pointing away from the surface (wo towards the
// viewer, wi towards the light); `ng` is the geometric normal pointing out of the object (for
// dielectrics: from the medium into the air); `ns` the shading normal on the same side as `ng`
// (from vertex normals or the level set gradient, for smooth shading).
#pragma once

#include <Eigen/Core>

namespace kurage::render {

enum class MaterialType { Diffuse, Dielectric, Translucent, Mirror };

struct Material {
  MaterialType type = MaterialType::Diffuse;
  Eigen::Vector3f albedo{0.8f, 0.8f, 0.8f};   // diffuse reflectance, translucent tint, mirror reflectance; [0,1]
  float ior = 1.33f;                           // index of refraction (dielectric, translucent)
  Eigen::Vector3f absorption{0.0f, 0.0f, 0.0f};  // 1/m, Beer-Lambert coefficient inside (dielectric, translucent)
  // A 3-D checker texture for diffuse surfaces: cells of checkerSize metres alternate between
  // albedo and albedoB (by the parity of floor(x/s) + floor(y/s) + floor(z/s)); 0 = plain.
  float checkerSize = 0.0f;
  Eigen::Vector3f albedoB{0.4f, 0.4f, 0.4f};
  bool operator==(const Material&) const = default;
};

// The albedo at world point p: `albedo` or, with a checker, albedo/albedoB by cell parity.
Eigen::Vector3f checkerAlbedo(const Material& m, const Eigen::Vector3f& albedo, const Eigen::Vector3f& p);

// Box-filtered checkers (Pharr, Jakob & Humphreys, Physically Based Rendering, 4th ed., sec.
// 10.5.3 "Checkerboard", after Peachey's closed form): the mean of the square wave (-1)^floor(x)
// over [x0, x1] (x in cells), from its antiderivative; the point value where x1 - x0 < 1e-9.
// Exact for any width; the mean is 0 over whole pairs of cells.
double checkerWaveMean(double x0, double x1);

// The two checker albedos mixed by a mean parity P in [-1, 1] (the product of the axes'
// checkerWaveMean): (1 + P)/2 a + (1 - P)/2 b, a where P = 1, b where P = -1.
Eigen::Vector3f checkerBlend(double parity, const Eigen::Vector3f& a, const Eigen::Vector3f& b);

// checkerAlbedo averaged over the axis-aligned box centred on p with full widths `width` (metres,
// >= 0 per axis): the parity sign is the product of one square wave per axis, so its mean over a
// box is the product of the axes' means P, and the albedo checkerBlend(P, albedo, albedoB).
// A zero width gives checkerAlbedo.
Eigen::Vector3f checkerAlbedoFiltered(const Material& m, const Eigen::Vector3f& albedo, const Eigen::Vector3f& p,
                                      const Eigen::Vector3f& width);

// Unpolarised Fresnel reflectance of a smooth interface; cosI = cos of the incidence angle
// (> 0) on the side with index etaI, the other side has etaT. 1 under total internal reflection.
float fresnelDielectric(float cosI, float etaI, float etaT);

// Whether the material has a non-delta lobe, i.e. whether next-event estimation applies.
inline bool hasDiffuseLobe(MaterialType t) { return t == MaterialType::Diffuse || t == MaterialType::Translucent; }

// BSDF times |cos(wi, ns)| for the non-delta lobe (zero for delta lobes), `albedo` being the
// material's albedo or a texture value at the point.
Eigen::Vector3f evaluateDiffuseLobe(const Material& m, const Eigen::Vector3f& albedo, const Eigen::Vector3f& wo,
                                    const Eigen::Vector3f& wi, const Eigen::Vector3f& ns, const Eigen::Vector3f& ng);

// The solid-angle pdf with which sampleMaterial returns wi through the non-delta lobe (0 for
// delta lobes and for directions that lobe never produces): cos / pi for diffuse, (1 - F) cos / pi
// on the far side for translucent. For multiple importance sampling with the lights.
float diffuseLobePdf(const Material& m, const Eigen::Vector3f& wo, const Eigen::Vector3f& wi,
                     const Eigen::Vector3f& ns, const Eigen::Vector3f& ng);

struct ScatterSample {
  Eigen::Vector3f direction;  // wi, unit
  Eigen::Vector3f weight;     // f |cos| / pdf
  bool specular = false;      // a delta lobe was sampled
  bool transmitted = false;   // wi is on the other side of the surface from wo
};

// Samples an outgoing direction with three uniform numbers in [0,1). Returns false when the
// path should end (e.g. a diffuse sample that would go below the geometric surface).
bool sampleMaterial(const Material& m, const Eigen::Vector3f& albedo, const Eigen::Vector3f& wo,
                    const Eigen::Vector3f& ns, const Eigen::Vector3f& ng, float u1, float u2, float u3,
                    ScatterSample& sample);

}  // namespace kurage::render
