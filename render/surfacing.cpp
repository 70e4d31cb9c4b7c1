// Metaball level sets with OpenVDB: field summation, narrow-band SDF construction, meshing and
// .vdb file I/O. See surfacing.h for the field, the method in brief and its accuracy.
//
// 1. Summation (sumField): particles are binned by blocks of 4^3 voxels around their nearest
//    voxel, then every 8^3 leaf that any particle's support can reach is filled independently
//    (in parallel) by gathering from the particles of the bins within reach, in a fixed order,
//    whole rows of 8 voxels at a time. No atomics, no per-thread grids: the sums are bit for bit
//    the same for any thread count. Anisotropic kernels (render/anisotropy.h) go the same way:
//    the blobs' centres are binned, and each blob adds s (1 - d^T M d)^2 over the rows of its
//    bounding box (splatEllipsoid), a quadratic in z along each row.
// 2. Surface samples (findCrossings), per leaf: voxels where f - T changes sign towards a face
//    neighbour get a distance estimate min(t, Newton), with t the nearest crossing along an axis
//    (linear interpolation of f) and Newton = |f - T| / |grad f| (central differences); voxels
//    with no crossing get the Newton estimate when it is below one voxel. Points on the surface:
//    every edge crossing, and the Newton foot point x -+ Newton * grad f / |grad f|.
// 3. Narrow band (narrowBand), per leaf around the leaves with samples: each voxel's distance is
//    the smallest of its own estimate and its distances to the surface points within halfWidth
//    voxels (splatted, whole rows at a time), signed by f - T (negative where f > T). Voxels
//    beyond halfWidth stay inactive at +-background, and the signed flood fill gives the leaves
//    left out their inside or outside value. Minima do not depend on the order, so this step is
//    thread-count independent too.
// 4. The clip to a box (intersectWithBox, surfacing.h) is a separate pass over a finished level
//    set, leaf by leaf.
// Its speed: `kurage bench surface` (docs/results/performance.md).
#include "render/surfacing.h"

#include "render/level_set_impl.h"

#include <Eigen/LU>

#include <openvdb/openvdb.h>
#include <openvdb/io/Stream.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>
#include <istream>
#include <ostream>

namespace kurage::render {

LevelSet::LevelSet() : impl(std::make_unique<Impl>()) {}
LevelSet::~LevelSet() = default;
LevelSet::LevelSet(LevelSet&&) noexcept = default;
LevelSet& LevelSet::operator=(LevelSet&&) noexcept = default;

bool LevelSet::empty() const { return !impl || !impl->grid || impl->grid->activeVoxelCount() == 0; }

float LevelSet::voxelSize() const {
  if (!impl || !impl->grid) return 0.0f;
  return static_cast<float>(impl->grid->voxelSize()[0]);
}

float LevelSet::sample(const Eigen::Vector3f& worldPosition) const {
  if (!impl || !impl->grid) return std::numeric_limits<float>::infinity();
  const openvdb::FloatGrid& grid = *impl->grid;
  const openvdb::Vec3d index = grid.worldToIndex(openvdb::Vec3d(worldPosition.x(), worldPosition.y(), worldPosition.z()));
  return openvdb::tools::BoxSampler::sample(grid.getConstAccessor(), index);
}

size_t LevelSet::activeVoxelCount() const {
  return (impl && impl->grid) ? static_cast<size_t>(impl->grid->activeVoxelCount()) : 0;
}

size_t LevelSet::memoryBytes() const { return (impl && impl->grid) ? static_cast<size_t>(impl->grid->memUsage()) : 0; }

namespace {

using openvdb::Coord;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using MaskLeaf = openvdb::MaskTree::LeafNodeType;
constexpr int kLeafDim = static_cast<int>(FloatLeaf::DIM);          // 8
constexpr int kLeafLog2 = static_cast<int>(FloatLeaf::LOG2DIM);     // 3
constexpr int kKeyBits = 21;                                        // per axis, leaf units
constexpr int64_t kKeyLimit = int64_t(1) << (kKeyBits - 1);         // |leaf coord| < 2^20

// Packs a leaf coordinate (in leaf units) into a 63-bit key whose order is lexicographic (x, y, z).
uint64_t packLeafKey(int64_t x, int64_t y, int64_t z) {
  const auto u = [](int64_t v) { return static_cast<uint64_t>(v + kKeyLimit); };
  return (u(x) << (2 * kKeyBits)) | (u(y) << kKeyBits) | u(z);
}

// The integer coordinates packed by packLeafKey.
std::array<int64_t, 3> unpackKey(uint64_t key) {
  const uint64_t mask = (uint64_t(1) << kKeyBits) - 1;
  const auto s = [](uint64_t v) { return static_cast<int64_t>(v) - kKeyLimit; };
  return {s((key >> (2 * kKeyBits)) & mask), s((key >> kKeyBits) & mask), s(key & mask)};
}

// Particles are binned by blocks of 4^3 voxels: half a leaf, so that a leaf gathers from little
// more than the particles whose support reaches it.
constexpr int kBinDim = 4;

// Four floats as one SSE/NEON register (GCC and Clang vector extension).
typedef float Float4 __attribute__((vector_size(16)));

// Adds s max(0, w)^2 to a row of 8 voxels, w given as two 4-wide vectors (the metaball kernel's
// falloff, (1 - d^2/R^2)^2, for spheres and ellipsoids alike).
inline void addFalloffRow(float* row, Float4 w0, Float4 w1, float strength) {
  const Float4 zero = {0.0f, 0.0f, 0.0f, 0.0f};
  w0 = w0 > zero ? w0 : zero;
  w1 = w1 > zero ? w1 : zero;
  Float4 r0, r1;
  std::memcpy(&r0, row, sizeof r0);
  std::memcpy(&r1, row + 4, sizeof r1);
  r0 += strength * w0 * w0;
  r1 += strength * w1 * w1;
  std::memcpy(row, &r0, sizeof r0);
  std::memcpy(row + 4, &r1, sizeof r1);
}

int64_t floorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

Coord unpackLeafOrigin(uint64_t key) {
  const uint64_t mask = (uint64_t(1) << kKeyBits) - 1;
  const auto s = [](uint64_t v) { return static_cast<int32_t>(static_cast<int64_t>(v) - kKeyLimit); };
  return Coord(s((key >> (2 * kKeyBits)) & mask) * kLeafDim, s((key >> kKeyBits) & mask) * kLeafDim,
               s(key & mask) * kLeafDim);
}

void checkParams(const MetaballParams& p) {
  const bool ok = std::isfinite(p.radius) && p.radius > 0 && std::isfinite(p.voxelSize) && p.voxelSize > 0 &&
                  std::isfinite(p.strength) && p.strength > 0 && std::isfinite(p.threshold) && p.threshold > 0 &&
                  p.threshold < p.strength && std::isfinite(p.halfWidth) && p.halfWidth >= 1;
  if (!ok) {
    throw std::invalid_argument("metaball parameters out of range (need radius, voxelSize > 0, "
                                "0 < threshold < strength, halfWidth >= 1)");
  }
}

openvdb::FloatGrid::Ptr emptyLevelSetGrid(double voxelSize, float halfWidth) {
  auto grid = openvdb::FloatGrid::create(static_cast<float>(voxelSize * halfWidth));
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

// The metaball field on the leaves (8^3 voxels) that any particle's support reaches, stored
// densely in OpenVDB's voxel order (offset = x * 64 + y * 8 + z). Leaves where f is 0 at every
// voxel are left out; f is 0 in every leaf left out.
struct SummedField {
  std::vector<uint64_t> keys;  // sorted leaf keys (packLeafKey)
  std::vector<float> values;   // keys.size() * 512 values of f
  const float* leaf(uint64_t key) const {
    const auto it = std::lower_bound(keys.begin(), keys.end(), key);
    return (it == keys.end() || *it != key) ? nullptr : &values[size_t(it - keys.begin()) * FloatLeaf::SIZE];
  }
};

// A particle's ellipsoid in voxel units: d^T M d < 1 (M symmetric, six entries xx, xy, xz, yy, yz,
// zz) and the half extents of its bounding box, sqrt((M^-1)_aa).
struct VoxelEllipsoid {
  float m[6];
  float extent[3];
};

// Adds s (1 - d^T M d)^2 (where d^T M d < 1) of one ellipsoidal blob at `rel` (leaf-local voxel
// units) to the leaf's field, whole rows of 8 as two 4-wide vectors, as the spheres' loop does.
void splatEllipsoid(float* field, const openvdb::Vec3d& rel, const VoxelEllipsoid& e, float strength) {
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, static_cast<int>(std::ceil(rel[a] - e.extent[a])));
    hi[a] = std::min(kLeafDim - 1, static_cast<int>(std::floor(rel[a] + e.extent[a])));
    if (lo[a] > hi[a]) return;
  }
  const float px = static_cast<float>(rel[0]), py = static_cast<float>(rel[1]), pz = static_cast<float>(rel[2]);
  const float mxx = e.m[0], mxy = e.m[1], mxz = e.m[2], myy = e.m[3], myz = e.m[4], mzz = e.m[5];
  float dz[kLeafDim];
  for (int z = 0; z < kLeafDim; ++z) dz[z] = float(z) - pz;
  Float4 dz0, dz1;
  std::memcpy(&dz0, &dz[0], sizeof dz0);
  std::memcpy(&dz1, &dz[4], sizeof dz1);
  for (int x = lo[0]; x <= hi[0]; ++x) {
    const float dx = float(x) - px;
    for (int y = lo[1]; y <= hi[1]; ++y) {
      const float dy = float(y) - py;
      // q(dz) = c0 + c1 dz + mzz dz^2 along the row; skip rows whose minimum is outside.
      const float c0 = mxx * dx * dx + 2.0f * mxy * dx * dy + myy * dy * dy;
      const float c1 = 2.0f * (mxz * dx + myz * dy);
      if (c0 - c1 * c1 / (4.0f * mzz) >= 1.0f) continue;
      float* row = &field[static_cast<size_t>((x << (2 * kLeafLog2)) | (y << kLeafLog2))];
      addFalloffRow(row, 1.0f - (c0 + dz0 * (c1 + mzz * dz0)), 1.0f - (c0 + dz1 * (c1 + mzz * dz1)), strength);
    }
  }
}

// Sums the metaball field f. `shapes` (world, 1/m^2, one per position) gives each blob's
// ellipsoid (MetaballKernel::Anisotropic); empty: spheres of radius R times `scales` (one per
// position, in (0, kMaxRadiusScale]; empty: all 1). With shapes, `scales` (already applied to
// the shapes) only sets the reach.
SummedField sumField(const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Matrix3f>& shapes,
                     const std::vector<float>& scales, const MetaballParams& params) {
  const double h = params.voxelSize;
  const double invH = 1.0 / h;
  const double r = static_cast<double>(params.radius) * invH;  // support radius in voxels
  const float invR2 = static_cast<float>(1.0 / (r * r));
  const float strength = params.strength;
  // The largest support (voxels): R times the largest scale above 1, else R.
  const double rMax = r * std::max(1.0, scales.empty() ? 1.0 : double(*std::max_element(scales.begin(), scales.end())));
  // Reach in voxels: a particle is within half a voxel of a voxel of its bin.
  const int reach = static_cast<int>(std::ceil(rMax + 0.5));
  const int64_t binLimit = kKeyLimit / 2 - reach - 2;  // so that leaf keys stay in range too

  // 1. Bin: key of the bin holding each particle's nearest voxel; sort (key, index).
  const size_t n = positions.size();
  std::vector<std::pair<uint64_t, uint32_t>> order(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3f& p = positions[i];
      int64_t bin[3];
      for (int a = 0; a < 3; ++a) {
        const double q = std::floor(static_cast<double>(p[a]) * invH + 0.5);
        if (!std::isfinite(q)) throw std::invalid_argument("metaball: particle position is not finite");
        if (std::abs(q) >= double(binLimit) * kBinDim) {
          throw std::invalid_argument("metaball: particle position too far from the origin for the voxel size");
        }
        bin[a] = floorDiv(static_cast<int64_t>(q), kBinDim);
      }
      order[i] = {packLeafKey(bin[0], bin[1], bin[2]), static_cast<uint32_t>(i)};
    }
  });
  tbb::parallel_sort(order.begin(), order.end());

  // Particle positions relative to their bin's leaf origin are formed per target leaf in double;
  // keep them in sorted order for locality.
  std::vector<openvdb::Vec3d> q(n);
  std::vector<VoxelEllipsoid> ellipsoids(shapes.empty() ? 0 : n);
  // Per-particle support radius (voxels) and 1 / radius^2, in sorted order; a scale of 1 gives
  // exactly r and invR2.
  std::vector<double> radii(scales.empty() ? 0 : n);
  std::vector<float> invRadii2(scales.empty() ? 0 : n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3f& p = positions[order[i].second];
      q[i] = openvdb::Vec3d(p.x() * invH, p.y() * invH, p.z() * invH);
      if (!scales.empty()) {
        radii[i] = r * static_cast<double>(scales[order[i].second]);
        invRadii2[i] = static_cast<float>(1.0 / (radii[i] * radii[i]));
      }
      if (shapes.empty()) continue;
      const Eigen::Matrix3d m = shapes[order[i].second].cast<double>() * (h * h);
      const Eigen::Matrix3d inverse = m.inverse();
      VoxelEllipsoid& e = ellipsoids[i];
      const float entries[6] = {float(m(0, 0)), float(m(0, 1)), float(m(0, 2)), float(m(1, 1)), float(m(1, 2)), float(m(2, 2))};
      std::copy_n(entries, 6, e.m);
      // Never past the sphere of the largest radius, which the bins' reach assumes.
      for (int a = 0; a < 3; ++a) e.extent[a] = float(std::min(std::sqrt(std::max(inverse(a, a), 0.0)), rMax));
    }
  });

  std::vector<uint64_t> binKeys;
  std::vector<size_t> binBegin;  // binBegin[b] .. binBegin[b + 1]
  for (size_t i = 0; i < n; ++i) {
    if (i == 0 || order[i].first != order[i - 1].first) {
      binKeys.push_back(order[i].first);
      binBegin.push_back(i);
    }
  }
  binBegin.push_back(n);
  order.clear();
  order.shrink_to_fit();

  // 2. Target leaves: the leaves that meet a bin's voxels dilated by the reach.
  std::vector<uint64_t> targets;
  targets.reserve(binKeys.size() * 8);
  for (const uint64_t key : binKeys) {
    const std::array<int64_t, 3> b = unpackKey(key);
    int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = floorDiv(b[a] * kBinDim - reach, kLeafDim);
      hi[a] = floorDiv(b[a] * kBinDim + kBinDim - 1 + reach, kLeafDim);
    }
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) targets.push_back(packLeafKey(x, y, z));
  }
  tbb::parallel_sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());

  // Bounding box of each bin's particles, to skip bins out of reach of a target leaf.
  std::vector<openvdb::Vec3d> binLo(binKeys.size()), binHi(binKeys.size());
  tbb::parallel_for(size_t(0), binKeys.size(), [&](size_t b) {
    openvdb::Vec3d lo = q[binBegin[b]], hi = lo;
    for (size_t i = binBegin[b] + 1; i < binBegin[b + 1]; ++i) {
      lo = openvdb::math::minComponent(lo, q[i]);
      hi = openvdb::math::maxComponent(hi, q[i]);
    }
    binLo[b] = lo - openvdb::Vec3d(rMax);
    binHi[b] = hi + openvdb::Vec3d(rMax);
  });

  // 3. Fill every target leaf by gathering from the neighbouring bins (fixed order). Also
  // record which voxels are inside (f > T).
  std::vector<float> values(targets.size() * FloatLeaf::SIZE);
  std::vector<char> nonZero(targets.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, targets.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
    float wx[kLeafDim], wy[kLeafDim], wz[kLeafDim];
    for (size_t t = range.begin(); t != range.end(); ++t) {
      float* field = &values[t * FloatLeaf::SIZE];
      std::fill(field, field + FloatLeaf::SIZE, 0.0f);
      const Coord origin = unpackLeafOrigin(targets[t]);
      const openvdb::Vec3d o(origin.x(), origin.y(), origin.z());
      const openvdb::Vec3d oEnd = o + openvdb::Vec3d(kLeafDim - 1);
      // The bins whose voxels dilated by the reach meet this leaf, in key order: for each
      // (x, y) column of bins, the z range is contiguous in the sorted keys.
      int64_t binFirst[3], binLast[3];
      const int32_t oc[3] = {origin.x(), origin.y(), origin.z()};
      for (int a = 0; a < 3; ++a) {
        binFirst[a] = floorDiv(int64_t(oc[a]) - reach, kBinDim);
        binLast[a] = floorDiv(int64_t(oc[a]) + kLeafDim - 1 + reach, kBinDim);
      }
      for (int64_t bx = binFirst[0]; bx <= binLast[0]; ++bx)
        for (int64_t by = binFirst[1]; by <= binLast[1]; ++by) {
          const uint64_t last = packLeafKey(bx, by, binLast[2]);
          for (auto it = std::lower_bound(binKeys.begin(), binKeys.end(), packLeafKey(bx, by, binFirst[2]));
               it != binKeys.end() && *it <= last; ++it) {
            const size_t b = static_cast<size_t>(it - binKeys.begin());
            if (binLo[b].x() > oEnd.x() || binLo[b].y() > oEnd.y() || binLo[b].z() > oEnd.z() ||
                binHi[b].x() < o.x() || binHi[b].y() < o.y() || binHi[b].z() < o.z()) {
              continue;
            }
            for (size_t i = binBegin[b]; i < binBegin[b + 1]; ++i) {
              const openvdb::Vec3d rel = q[i] - o;  // particle in leaf-local voxel units
              if (!ellipsoids.empty()) {
                splatEllipsoid(field, rel, ellipsoids[i], strength);
                continue;
              }
              const double ri = radii.empty() ? r : radii[i];
              const float invRi2 = radii.empty() ? invR2 : invRadii2[i];
              int lo[3], hi[3];
              bool overlaps = true;
              for (int a = 0; a < 3; ++a) {
                lo[a] = std::max(0, static_cast<int>(std::ceil(rel[a] - ri)));
                hi[a] = std::min(kLeafDim - 1, static_cast<int>(std::floor(rel[a] + ri)));
                overlaps = overlaps && lo[a] <= hi[a];
              }
              if (!overlaps) continue;
              const float px = static_cast<float>(rel[0]), py = static_cast<float>(rel[1]),
                          pz = static_cast<float>(rel[2]);
              for (int x = lo[0]; x <= hi[0]; ++x) wx[x] = (x - px) * (x - px) * invRi2;
              for (int y = lo[1]; y <= hi[1]; ++y) wy[y] = (y - py) * (y - py) * invRi2;
              // Whole rows of 8 as two 4-wide vectors: outside the support w is an exact 0,
              // and adding it keeps the sum unchanged. (The same operations on every lane, so
              // the sums do not depend on the vector width.)
              for (int z = 0; z < kLeafDim; ++z) wz[z] = (z - pz) * (z - pz) * invRi2;
              Float4 wz0, wz1;
              std::memcpy(&wz0, &wz[0], sizeof wz0);
              std::memcpy(&wz1, &wz[4], sizeof wz1);
              for (int x = lo[0]; x <= hi[0]; ++x)
                for (int y = lo[1]; y <= hi[1]; ++y) {
                  const float dxy = wx[x] + wy[y];
                  if (dxy >= 1.0f) continue;
                  float* row = &field[static_cast<size_t>((x << (2 * kLeafLog2)) | (y << kLeafLog2))];
                  addFalloffRow(row, 1.0f - (dxy + wz0), 1.0f - (dxy + wz1), strength);
                }
            }
          }
        }
      nonZero[t] = std::any_of(field, field + FloatLeaf::SIZE, [](float v) { return v > 0.0f; });
    }
  });

  SummedField out;
  const size_t kept = size_t(std::count(nonZero.begin(), nonZero.end(), char(1)));
  out.keys.reserve(kept);
  out.values.resize(kept * FloatLeaf::SIZE);
  for (size_t t = 0; t < targets.size(); ++t) {
    if (!nonZero[t]) continue;
    std::copy_n(&values[t * FloatLeaf::SIZE], FloatLeaf::SIZE, &out.values[out.keys.size() * FloatLeaf::SIZE]);
    out.keys.push_back(targets[t]);
  }
  return out;
}

// The surface near the voxels of one leaf: the voxels next to it with their own distance
// estimates, and points on it (index space).
struct SurfaceSamples {
  std::vector<std::pair<uint16_t, float>> voxels;  // (offset in the leaf, distance in voxels)
  std::vector<std::array<float, 3>> points;
};

// The crossings of every leaf of the summed field: a voxel is at the surface when f - T changes
// sign between it and a face neighbour. Along axis a the crossing lies t_a voxels away
// (t_a = (f - T) / (f - f_neighbour), linear interpolation, the nearer side when both cross);
// treating the surface as a plane through those crossings gives the distance
// d = 1 / sqrt(sum_a 1 / t_a^2) and the nearest point x + d^2 sum_a sign_a / t_a e_a (exact for a
// plane, as in the initialisation of fast marching).
constexpr float kNewtonReach = 1.0f;  // voxels

std::vector<SurfaceSamples> findCrossings(const SummedField& field, float threshold) {
  std::vector<SurfaceSamples> crossings(field.keys.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, field.keys.size(), 8), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t l = range.begin(); l != range.end(); ++l) {
      const float* f = &field.values[l * FloatLeaf::SIZE];
      const Coord origin = unpackLeafOrigin(field.keys[l]);
      const int64_t lx = origin.x() / kLeafDim, ly = origin.y() / kLeafDim, lz = origin.z() / kLeafDim;
      // The six face-neighbour leaves (null where the field is 0).
      const float* lower[3] = {field.leaf(packLeafKey(lx - 1, ly, lz)), field.leaf(packLeafKey(lx, ly - 1, lz)),
                               field.leaf(packLeafKey(lx, ly, lz - 1))};
      const float* upper[3] = {field.leaf(packLeafKey(lx + 1, ly, lz)), field.leaf(packLeafKey(lx, ly + 1, lz)),
                               field.leaf(packLeafKey(lx, ly, lz + 1))};
      constexpr int kStride[3] = {kLeafDim * kLeafDim, kLeafDim, 1};
      for (int v = 0; v < int(FloatLeaf::SIZE); ++v) {
        const int c[3] = {v >> (2 * kLeafLog2), (v >> kLeafLog2) & (kLeafDim - 1), v & (kLeafDim - 1)};
        const float fv = f[v] - threshold;
        const bool inside = fv > 0.0f;
        float gradient[3], nearest = 2.0f;
        for (int a = 0; a < 3; ++a) {
          float neighbour[2];
          for (int side = -1; side <= 1; side += 2) {
            float fn;
            const int n = c[a] + side;
            if (n >= 0 && n < kLeafDim) {
              fn = f[v + side * kStride[a]];
            } else {
              const float* other = side < 0 ? lower[a] : upper[a];
              fn = other ? other[v + side * kStride[a] - side * kLeafDim * kStride[a]] : 0.0f;
            }
            fn -= threshold;
            neighbour[(side + 1) / 2] = fn;
            if ((fn > 0.0f) == inside) continue;
            const float t = fv / (fv - fn);  // in [0, 1): fv and fn differ in sign (or fv = 0)
            nearest = std::min(nearest, t);
            if (inside) {  // each crossing once: seen from its inside end
              std::array<float, 3> point = {float(origin.x() + c[0]), float(origin.y() + c[1]), float(origin.z() + c[2])};
              point[size_t(a)] += float(side) * t;
              crossings[l].points.push_back(point);
            }
          }
          gradient[a] = 0.5f * (neighbour[1] - neighbour[0]);
        }
        const float norm = std::sqrt(gradient[0] * gradient[0] + gradient[1] * gradient[1] + gradient[2] * gradient[2]);
        // One Newton step along the gradient, never farther than a crossing already found;
        // without a crossing on the six edges, only when it lands within kNewtonReach.
        const float newton = norm > 0.0f ? std::abs(fv) / norm : std::numeric_limits<float>::infinity();
        if (nearest > 1.0f && !(newton < kNewtonReach)) continue;
        const float distance = std::min(nearest, newton);
        crossings[l].voxels.emplace_back(uint16_t(v), distance);
        if (!(newton <= nearest)) continue;  // the crossings are nearer, and already points
        const float step = (inside ? -newton : newton) / norm;
        crossings[l].points.push_back({float(origin.x() + c[0]) + step * gradient[0],
                                       float(origin.y() + c[1]) + step * gradient[1],
                                       float(origin.z() + c[2]) + step * gradient[2]});
      }
    }
  });
  return crossings;
}

// The narrow band: every voxel within halfWidth voxels of a surface point (the foot points of
// the crossings) gets the distance to the nearest one, signed by f - T; voxels on the surface
// keep their own estimate when it is smaller. The leaves are those around the leaves with
// crossings; everything else is left to the signed flood fill.
openvdb::FloatGrid::Ptr narrowBand(const SummedField& field, const std::vector<SurfaceSamples>& crossings,
                                   const MetaballParams& params) {
  const float h = params.voxelSize;
  const float background = params.halfWidth * h;
  const float radius = params.halfWidth;  // voxels
  const float radius2 = radius * radius;
  const int reach = static_cast<int>(std::ceil((radius + 1.0f) / kLeafDim));

  std::vector<uint64_t> surfaceKeys;    // leaves with crossings, sorted
  std::vector<size_t> surfaceLeaf;      // their index in field.keys
  for (size_t l = 0; l < field.keys.size(); ++l)
    if (!crossings[l].voxels.empty()) surfaceKeys.push_back(field.keys[l]), surfaceLeaf.push_back(l);
  std::vector<uint64_t> targets;
  for (const uint64_t key : surfaceKeys) {
    const Coord o = unpackLeafOrigin(key);
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz)
          targets.push_back(packLeafKey(o.x() / kLeafDim + dx, o.y() / kLeafDim + dy, o.z() / kLeafDim + dz));
  }
  tbb::parallel_sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());

  std::vector<std::unique_ptr<FloatLeaf>> leaves(targets.size());
  const float threshold = params.threshold;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, targets.size(), 8), [&](const tbb::blocked_range<size_t>& range) {
    alignas(16) std::array<float, FloatLeaf::SIZE> dist2;
    float wx[kLeafDim], wy[kLeafDim], wz[kLeafDim];
    for (size_t t = range.begin(); t != range.end(); ++t) {
      dist2.fill(std::numeric_limits<float>::infinity());
      const Coord origin = unpackLeafOrigin(targets[t]);
      const int64_t lx = origin.x() / kLeafDim, ly = origin.y() / kLeafDim, lz = origin.z() / kLeafDim;
      const float* f = field.leaf(targets[t]);
      for (int dx = -reach; dx <= reach; ++dx)
        for (int dy = -reach; dy <= reach; ++dy)
          for (int dz = -reach; dz <= reach; ++dz) {
            const uint64_t key = packLeafKey(lx + dx, ly + dy, lz + dz);
            const auto it = std::lower_bound(surfaceKeys.begin(), surfaceKeys.end(), key);
            if (it == surfaceKeys.end() || *it != key) continue;
            const SurfaceSamples& samples = crossings[surfaceLeaf[size_t(it - surfaceKeys.begin())]];
            if (dx == 0 && dy == 0 && dz == 0)
              for (const auto& [offset, d] : samples.voxels) dist2[offset] = std::min(dist2[offset], d * d);
            for (const std::array<float, 3>& point : samples.points) {
              const float px = point[0] - float(origin.x()), py = point[1] - float(origin.y()),
                          pz = point[2] - float(origin.z());
              int lo[3], hi[3];
              bool overlaps = true;
              const float p[3] = {px, py, pz};
              for (int a = 0; a < 3; ++a) {
                lo[a] = std::max(0, static_cast<int>(std::ceil(p[a] - radius)));
                hi[a] = std::min(kLeafDim - 1, static_cast<int>(std::floor(p[a] + radius)));
                overlaps = overlaps && lo[a] <= hi[a];
              }
              if (!overlaps) continue;
              for (int x = lo[0]; x <= hi[0]; ++x) wx[x] = (float(x) - px) * (float(x) - px);
              for (int y = lo[1]; y <= hi[1]; ++y) wy[y] = (float(y) - py) * (float(y) - py);
              // Whole rows of 8: a voxel farther than the radius gets a true distance too, which
              // can only be >= the radius and so leaves it out of the band as before.
              for (int z = 0; z < kLeafDim; ++z) wz[z] = (float(z) - pz) * (float(z) - pz);
              Float4 wz0, wz1;
              std::memcpy(&wz0, &wz[0], sizeof wz0);
              std::memcpy(&wz1, &wz[4], sizeof wz1);
              for (int x = lo[0]; x <= hi[0]; ++x)
                for (int y = lo[1]; y <= hi[1]; ++y) {
                  const float dxy = wx[x] + wy[y];
                  if (dxy >= radius2) continue;
                  float* row = &dist2[static_cast<size_t>((x << (2 * kLeafLog2)) | (y << kLeafLog2))];
                  Float4 r0, r1;
                  std::memcpy(&r0, row, sizeof r0);
                  std::memcpy(&r1, row + 4, sizeof r1);
                  const Float4 d0 = dxy + wz0, d1 = dxy + wz1;
                  r0 = d0 < r0 ? d0 : r0;
                  r1 = d1 < r1 ? d1 : r1;
                  std::memcpy(row, &r0, sizeof r0);
                  std::memcpy(row + 4, &r1, sizeof r1);
                }
            }
          }
      auto leaf = std::make_unique<FloatLeaf>(origin, background, false);
      float* values = leaf->buffer().data();
      for (openvdb::Index v = 0; v < FloatLeaf::SIZE; ++v) {
        const bool inside = f && f[v] > threshold;
        const float d = std::sqrt(dist2[v]) * h;
        if (d < background) {
          values[v] = inside ? -d : d;
          leaf->setValueOn(v);
        } else {
          values[v] = inside ? -background : background;
        }
      }
      leaves[t] = std::move(leaf);
    }
  });
  auto grid = emptyLevelSetGrid(h, params.halfWidth);
  for (auto& leaf : leaves) grid->tree().addLeaf(leaf.release());  // the tree takes ownership
  return grid;
}

Eigen::Vector3f toEigen(const openvdb::Vec3s& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

LevelSet buildMetaballLevelSet(const std::vector<Eigen::Vector3f>& positions, const MetaballParams& params,
                               const std::function<bool()>& stop) {
  return buildMetaballLevelSet(positions, {}, params, stop);
}

LevelSet buildMetaballLevelSet(const std::vector<Eigen::Vector3f>& positions, const std::vector<float>& radiusScales,
                               const MetaballParams& params, const std::function<bool()>& stop) {
  const auto checkStop = [&stop] {
    if (stop && stop()) throw SurfacingStopped();
  };
  checkParams(params);
  openvdb::initialize();
  if (positions.size() > std::numeric_limits<uint32_t>::max()) {
    throw std::invalid_argument("metaball: more than 2^32 particles");
  }
  if (!radiusScales.empty() && radiusScales.size() != positions.size())
    throw std::invalid_argument("metaball: radius scales and positions differ in number");
  for (const float scale : radiusScales)
    if (!(scale > 0.0f && scale <= kMaxRadiusScale))
      throw std::invalid_argument("metaball: a radius scale outside (0, " + std::to_string(kMaxRadiusScale) + "]");
  LevelSet result;
  if (positions.empty()) {
    result.impl->grid = emptyLevelSetGrid(params.voxelSize, params.halfWidth);
    return result;
  }
  SummedField field;
  if (params.kernel == MetaballKernel::Anisotropic) {
    const std::vector<EllipsoidKernel> kernels = anisotropicKernels(positions, params.radius, params.anisotropy);
    std::vector<Eigen::Vector3f> centres(kernels.size());
    std::vector<Eigen::Matrix3f> shapes(kernels.size());
    for (size_t i = 0; i < kernels.size(); ++i) {
      centres[i] = kernels[i].centre, shapes[i] = kernels[i].shape;
      if (!radiusScales.empty() && radiusScales[i] != 1.0f) shapes[i] /= radiusScales[i] * radiusScales[i];
    }
    checkStop();
    field = sumField(centres, shapes, radiusScales, params);
  } else {
    field = sumField(positions, {}, radiusScales, params);
  }
  checkStop();
  const std::vector<SurfaceSamples> crossings = findCrossings(field, params.threshold);
  if (std::all_of(crossings.begin(), crossings.end(), [](const auto& c) { return c.voxels.empty(); })) {
    // No voxel centre reaches the threshold: the surface is below the resolution.
    result.impl->grid = emptyLevelSetGrid(params.voxelSize, params.halfWidth);
    return result;
  }
  checkStop();
  openvdb::FloatGrid::Ptr sdf = narrowBand(field, crossings, params);
  checkStop();
  openvdb::tools::signedFloodFill(sdf->tree());  // leaves left out -> +-background tiles
  openvdb::tools::pruneLevelSet(sdf->tree());
  result.impl->grid = sdf;
  return result;
}

std::vector<float> stretchRadiusScales(const std::vector<float>& restDensityFactors) {
  std::vector<float> scales(restDensityFactors.size(), 1.0f);
  bool grown = false;
  for (size_t i = 0; i < scales.size(); ++i) {
    const float factor = restDensityFactors[i];
    if (!(std::isfinite(factor) && factor > 0.0f))
      throw std::invalid_argument("metaball: a rest density factor not finite and > 0");
    if (factor >= 1.0f) continue;
    scales[i] = std::min(std::cbrt(1.0f / factor), kMaxRadiusScale);
    grown = grown || scales[i] > 1.0f;
  }
  if (!grown) scales.clear();
  return scales;
}

namespace {

// Exact signed distance from x to the axis-aligned box [lo, hi], negative inside (index space).
double boxSignedDistance(const openvdb::Vec3d& x, const openvdb::Vec3d& lo, const openvdb::Vec3d& hi) {
  double outside2 = 0.0, inside = -std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double d = std::max(lo[a] - x[a], x[a] - hi[a]);  // > 0 beyond a face of this axis
    if (d > 0.0) outside2 += d * d;
    inside = std::max(inside, d);
  }
  return outside2 > 0.0 ? std::sqrt(outside2) : inside;
}

}  // namespace

void intersectWithBox(LevelSet& levelSet, const Eigen::Vector3f& boxMin, const Eigen::Vector3f& boxMax) {
  if (!((boxMin.array() <= boxMax.array()).all())) {
    throw std::invalid_argument("intersectWithBox: the box's min exceeds its max");
  }
  if (levelSet.empty()) return;
  openvdb::initialize();
  const openvdb::FloatGrid& old = *levelSet.impl->grid;
  const double h = old.voxelSize()[0];
  const float background = old.background();
  const double band = double(background) / h;  // half width, voxels
  // The box in index space (voxel centres are at integer coordinates).
  const openvdb::Vec3d lo = old.worldToIndex(openvdb::Vec3d(boxMin.x(), boxMin.y(), boxMin.z()));
  const openvdb::Vec3d hi = old.worldToIndex(openvdb::Vec3d(boxMax.x(), boxMax.y(), boxMax.z()));

  // Leaves that can hold voxels of the new band: the old band's leaves within the band of the box,
  // and the leaves along the box's faces (within the band of them) that the old level set has
  // inside (a tile below zero). Everything else ends up +-background after the flood fill.
  const openvdb::CoordBBox active = old.evalActiveVoxelBoundingBox();
  std::vector<Coord> origins;
  for (auto leaf = old.tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::CoordBBox b = leaf->getNodeBoundingBox();
    bool near = true;  // the leaf's voxels come within the band of the box's inside
    for (int a = 0; a < 3; ++a) near = near && b.max()[a] >= lo[a] - band && b.min()[a] <= hi[a] + band;
    if (near) origins.push_back(leaf->origin());
  }
  {
    Coord first, last;
    for (int a = 0; a < 3; ++a) {
      const double from = std::max(lo[a] - band, double(active.min()[a]) - kLeafDim);
      const double to = std::min(hi[a] + band, double(active.max()[a]) + kLeafDim);
      first[a] = int32_t(floorDiv(int64_t(std::floor(from)), kLeafDim));
      last[a] = int32_t(floorDiv(int64_t(std::ceil(to)), kLeafDim));
    }
    const auto accessor = old.getConstAccessor();
    for (int32_t x = first.x(); x <= last.x(); ++x)
      for (int32_t y = first.y(); y <= last.y(); ++y)
        for (int32_t z = first.z(); z <= last.z(); ++z) {
          const Coord origin(x * kLeafDim, y * kLeafDim, z * kLeafDim);
          if (old.tree().probeConstLeaf(origin)) continue;  // among the old band's leaves
          if (!(accessor.getValue(origin) < 0.0f)) continue;   // outside: stays outside
          // Inside the old level set: keep it when it reaches within the band of a face.
          bool deepInside = true;
          for (int a = 0; a < 3; ++a)
            deepInside = deepInside && origin[a] > lo[a] + band && origin[a] + kLeafDim - 1 < hi[a] - band;
          if (!deepInside) origins.push_back(origin);
        }
  }
  std::sort(origins.begin(), origins.end());

  std::vector<std::unique_ptr<FloatLeaf>> leaves(origins.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, origins.size(), 8), [&](const tbb::blocked_range<size_t>& range) {
    const auto accessor = old.getConstAccessor();
    for (size_t l = range.begin(); l != range.end(); ++l) {
      auto leaf = std::make_unique<FloatLeaf>(origins[l], background, false);
      bool any = false;
      for (openvdb::Index v = 0; v < FloatLeaf::SIZE; ++v) {
        const Coord ijk = leaf->offsetToGlobalCoord(v);
        const double box = boxSignedDistance(ijk.asVec3d(), lo, hi) * h;
        const float phi = std::max(accessor.getValue(ijk), float(box));
        if (std::abs(phi) < background) {
          leaf->setValueOn(v, phi);
          any = true;
        } else {
          leaf->setValueOff(v, phi < 0.0f ? -background : background);
        }
      }
      if (any) leaves[l] = std::move(leaf);
    }
  });
  auto grid = emptyLevelSetGrid(h, background / float(h));
  for (auto& leaf : leaves)
    if (leaf) grid->tree().addLeaf(leaf.release());
  openvdb::tools::signedFloodFill(grid->tree());
  openvdb::tools::pruneLevelSet(grid->tree());
  levelSet.impl->grid = grid;
}

TriangleMesh meshLevelSet(const LevelSet& levelSet) {
  TriangleMesh mesh;
  if (levelSet.empty()) return mesh;
  openvdb::initialize();
  const openvdb::FloatGrid& grid = *levelSet.impl->grid;

  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, 0.0);

  // OpenVDB's polygons wind clockwise seen from outside (the side the SDF gradient points to),
  // so every polygon is reversed here; test_surfacing checks the result against the normals.
  mesh.positions.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) mesh.positions[i] = toEigen(points[i]);
  mesh.triangles.reserve(triangles.size() + 2 * quads.size());
  const auto idx = [](openvdb::Index v) { return static_cast<int>(v); };
  for (const openvdb::Vec3I& t : triangles) mesh.triangles.emplace_back(idx(t[0]), idx(t[2]), idx(t[1]));
  for (const openvdb::Vec4I& q : quads) {
    mesh.triangles.emplace_back(idx(q[0]), idx(q[2]), idx(q[1]));
    mesh.triangles.emplace_back(idx(q[0]), idx(q[3]), idx(q[2]));
  }

  // Normals: normalised central differences of the trilinear SDF, one voxel wide.
  mesh.normals.resize(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
    const auto accessor = grid.getConstAccessor();
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const openvdb::Vec3d c = grid.worldToIndex(openvdb::Vec3d(points[i]));
      openvdb::Vec3d g;
      for (int a = 0; a < 3; ++a) {
        openvdb::Vec3d plus = c, minus = c;
        plus[a] += 0.5;
        minus[a] -= 0.5;
        g[a] = openvdb::tools::BoxSampler::sample(accessor, plus) - openvdb::tools::BoxSampler::sample(accessor, minus);
      }
      const double length = g.length();
      mesh.normals[i] = length > 0 ? Eigen::Vector3f(float(g[0] / length), float(g[1] / length), float(g[2] / length))
                                   : Eigen::Vector3f(0.0f, 0.0f, 1.0f);
    }
  });
  return mesh;
}

void writeLevelSets(std::ostream& out, const std::map<std::string, const LevelSet*>& grids,
                    const LevelSetFileInfo& info) {
  openvdb::initialize();
  openvdb::GridPtrVec vdbGrids;
  for (const auto& [name, levelSet] : grids) {
    openvdb::FloatGrid::Ptr grid;
    if (levelSet && levelSet->impl && levelSet->impl->grid) {
      grid = levelSet->impl->grid->copy();  // shares the tree; only the name differs
    } else {
      grid = emptyLevelSetGrid(1.0, 3.0f);
    }
    grid->setName(name);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    vdbGrids.push_back(grid);
  }
  openvdb::MetaMap meta;
  meta.insertMeta("kurage:time", openvdb::DoubleMetadata(info.time));
  meta.insertMeta("kurage:frame", openvdb::Int32Metadata(info.frame));
  for (const auto& [key, value] : info.tags) meta.insertMeta(key, openvdb::StringMetadata(value));
  openvdb::io::Stream(out).write(vdbGrids, meta);
  if (!out) throw std::runtime_error("cannot serialise level sets");
}

std::map<std::string, LevelSet> readLevelSets(std::istream& in, LevelSetFileInfo* info) {
  openvdb::initialize();
  std::map<std::string, LevelSet> result;
  openvdb::io::Stream stream(in, /*delayLoad=*/false);
  const openvdb::GridPtrVecPtr grids = stream.getGrids();
  const openvdb::MetaMap::Ptr meta = stream.getMetadata();
  if (!grids || !meta) throw std::runtime_error("not an OpenVDB stream");
  for (const openvdb::GridBase::Ptr& base : *grids) {
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) continue;
    LevelSet levelSet;
    levelSet.impl->grid = grid;
    result[grid->getName()] = std::move(levelSet);
  }
  if (info) {
    *info = LevelSetFileInfo{};
    if (const auto t = meta->getMetadata<openvdb::DoubleMetadata>("kurage:time")) info->time = t->value();
    if (const auto f = meta->getMetadata<openvdb::Int32Metadata>("kurage:frame")) info->frame = f->value();
    for (auto it = meta->beginMeta(); it != meta->endMeta(); ++it)
      if (const auto text = openvdb::StringMetadata::Ptr(openvdb::DynamicPtrCast<openvdb::StringMetadata>(it->second)))
        info->tags[it->first] = text->value();
  }
  return result;
}

std::string openvdbVersion() { return OPENVDB_LIBRARY_VERSION_STRING; }

}  // namespace kurage::render
