// Anisotropic kernels for metaball surfaces (Yu & Turk 2013, "Reconstructing surfaces of
// particle-based fluids using anisotropic kernels", ACM TOG 32(1)): each particle's blob is
// stretched into an ellipsoid that follows the spread of its neighbours, so that a sheet of
// particles (a jellyfish's bell, two layers thick) gives a thin wall instead of a fat one, and a
// flat free surface stays flat.
//
// For particle i, with the neighbours j within r = neighbourRadius * R (world space, metres, j = i
// included) and the weights w_ij = 1 - (|x_i - x_j| / r)^3 (Yu & Turk's):
//   weighted mean   x_i^w = sum_j w_ij x_j / sum_j w_ij
//   covariance      C_i   = sum_j w_ij (x_j - x_i^w)(x_j - x_i^w)^T / sum_j w_ij
//   C_i = Q diag(s_1, s_2, s_3) Q^T with s_1 >= s_2 >= s_3 (eigenvalues: variances, m^2)
//   clamped         s~_k  = max(s_k, s_1 / maxStretch)   (Yu & Turk's k_r)
// The kernel is the ellipsoid with axes Q e_k and radii a_k = max(R s~_k / s~_1, min(d_i, R)),
// d_i the distance from i to its nearest neighbour: the longest axis keeps the isotropic radius R,
// and no axis is thinner than the particles' own spacing. (The variances' ratio alone flattens a
// sheet of two or three layers, one spacing apart, to axes of about R / 3 across it, too thin to
// join the layers: the wall splits into two sheets with a slit between them, the deeper the more
// the sheet is stretched in its plane. A particle stands for about a spacing cube of matter, so a blob one
// spacing thick joins the layers and leaves a single-layer sheet as thin as k_r allows when the
// spacing is at most R / k_r.) (Yu & Turk scale the radii by a constant k_s times the variances
// instead; tying the longest axis to R keeps a particle in the bulk of a fluid at the isotropic
// metaball, so that R and T keep their meaning, and leaves no absolute constant to tune.) A
// particle with fewer than minNeighbours neighbours (spray, a lone particle) keeps the sphere
// of radius R (Yu & Turk's k_n = 1 in units of R). The blob's centre moves towards the weighted
// mean by `smoothing` (Yu & Turk's lambda; 0 keeps the particles where they are):
//   centre_i = (1 - smoothing) x_i + smoothing x_i^w.
// The field of a kernel at x is s (1 - d^T M d)^2 for d^T M d < 1 with d = x - centre and
// M = Q diag(1 / a_k^2) Q^T (1/m^2); it lies within the ball of radius R about the centre.
//
// Limits: the covariance is of the positions only (no masses or densities); neighbours are found
// on a uniform grid of cell r, so a cluster far denser than the spacing costs accordingly. The
// kernels do not depend on the thread count (every particle's sums run over its neighbours in a
// fixed order).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace kurage::render {

struct AnisotropyParams {
  float neighbourRadius = 1.0f;  // r, in units of the metaball radius R
  float maxStretch = 4.0f;       // k_r: the longest axis is at most this many times the shortest
  int minNeighbours = 8;         // fewer neighbours (the particle itself included): a sphere
  float smoothing = 0.0f;        // lambda in [0, 1]
};

struct EllipsoidKernel {
  Eigen::Vector3f centre;  // world, metres
  Eigen::Matrix3f shape;   // M: the blob is d^T M d < 1 (1/m^2, symmetric positive definite)
};

// One kernel per particle, in input order. `radius` is R (metres, > 0). Throws
// std::invalid_argument for parameters out of range (radius or neighbourRadius <= 0,
// maxStretch < 1, smoothing outside [0, 1]).
std::vector<EllipsoidKernel> anisotropicKernels(const std::vector<Eigen::Vector3f>& positions, float radius,
                                                const AnisotropyParams& params);

}  // namespace kurage::render
