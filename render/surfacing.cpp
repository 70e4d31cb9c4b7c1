// Metaball level sets with OpenVDB: field summation, narrow-band SDF conversion, meshing and
// .vdb file I/O. See surfacing.h for the field and the conventions.
//
// How the field is summed (buildMetaballLevelSet): particles are binned by the 8^3 leaf that
// holds their nearest voxel, then every leaf that any particle's support can reach is filled
// independently (in parallel) by gathering from the particles of the neighbouring bins, in a
// fixed order. There are no atomics and no per-thread grids, so the result is bit for bit the
// same for any thread count.
//
// The field is then turned into a narrow-band SDF by fast sweeping (tools::fogToSdf) restricted
// to a band of voxels around the inside boundary, trimmed to |d| < halfWidth * voxelSize, and
// the inactive interior is flood-filled with -background.
#include "render/surfacing.h"

#include "render/level_set_impl.h"

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tree/LeafManager.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <system_error>

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

struct SummedField {
  openvdb::FloatGrid::Ptr field;     // f, background 0, active where f > 0
  openvdb::MaskTree::Ptr inside;     // voxels where f > T
};

// Sums the metaball field f into a sparse grid.
SummedField sumField(const std::vector<Eigen::Vector3f>& positions, const MetaballParams& params) {
  const double h = params.voxelSize;
  const double invH = 1.0 / h;
  const double r = static_cast<double>(params.radius) * invH;  // support radius in voxels
  const float invR2 = static_cast<float>(1.0 / (r * r));
  const float strength = params.strength;
  // Reach of a bin in leaves: a particle is within half a voxel of a voxel of its bin.
  const int reach = static_cast<int>(std::ceil((r + 0.5) / kLeafDim));

  // 1. Bin: key of the leaf holding each particle's nearest voxel; sort (key, index).
  const size_t n = positions.size();
  std::vector<std::pair<uint64_t, uint32_t>> order(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3f& p = positions[i];
      int64_t leaf[3];
      for (int a = 0; a < 3; ++a) {
        const double q = std::floor(static_cast<double>(p[a]) * invH + 0.5);
        if (!std::isfinite(q)) throw std::invalid_argument("metaball: particle position is not finite");
        leaf[a] = static_cast<int64_t>(std::floor(q / kLeafDim));
        if (std::abs(leaf[a]) >= kKeyLimit - reach - 1) {
          throw std::invalid_argument("metaball: particle position too far from the origin for the voxel size");
        }
      }
      order[i] = {packLeafKey(leaf[0], leaf[1], leaf[2]), static_cast<uint32_t>(i)};
    }
  });
  tbb::parallel_sort(order.begin(), order.end());

  // Particle positions relative to their bin's leaf origin are formed per target leaf in double;
  // keep them in sorted order for locality.
  std::vector<openvdb::Vec3d> q(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3f& p = positions[order[i].second];
      q[i] = openvdb::Vec3d(p.x() * invH, p.y() * invH, p.z() * invH);
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

  // 2. Target leaves: every bin dilated by the reach.
  std::vector<uint64_t> targets;
  targets.reserve(binKeys.size() * 8);
  for (const uint64_t key : binKeys) {
    const Coord o = unpackLeafOrigin(key);
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz)
          targets.push_back(packLeafKey(o.x() / kLeafDim + dx, o.y() / kLeafDim + dy, o.z() / kLeafDim + dz));
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
    binLo[b] = lo - openvdb::Vec3d(r);
    binHi[b] = hi + openvdb::Vec3d(r);
  });

  // 3. Fill every target leaf by gathering from the neighbouring bins (fixed order). Also
  // record which voxels are inside (f > T).
  std::vector<std::unique_ptr<FloatLeaf>> leaves(targets.size());
  std::vector<std::unique_ptr<MaskLeaf>> insideLeaves(targets.size());
  const float threshold = params.threshold;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, targets.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
    std::array<float, FloatLeaf::SIZE> field;
    float wx[kLeafDim], wy[kLeafDim], wz[kLeafDim];
    for (size_t t = range.begin(); t != range.end(); ++t) {
      field.fill(0.0f);
      const Coord origin = unpackLeafOrigin(targets[t]);
      const openvdb::Vec3d o(origin.x(), origin.y(), origin.z());
      const openvdb::Vec3d oEnd = o + openvdb::Vec3d(kLeafDim - 1);
      for (int dx = -reach; dx <= reach; ++dx)
        for (int dy = -reach; dy <= reach; ++dy)
          for (int dz = -reach; dz <= reach; ++dz) {
            const uint64_t key = packLeafKey(origin.x() / kLeafDim + dx, origin.y() / kLeafDim + dy,
                                             origin.z() / kLeafDim + dz);
            const auto it = std::lower_bound(binKeys.begin(), binKeys.end(), key);
            if (it == binKeys.end() || *it != key) continue;
            const size_t b = static_cast<size_t>(it - binKeys.begin());
            if (binLo[b].x() > oEnd.x() || binLo[b].y() > oEnd.y() || binLo[b].z() > oEnd.z() ||
                binHi[b].x() < o.x() || binHi[b].y() < o.y() || binHi[b].z() < o.z()) {
              continue;
            }
            for (size_t i = binBegin[b]; i < binBegin[b + 1]; ++i) {
              const openvdb::Vec3d rel = q[i] - o;  // particle in leaf-local voxel units
              int lo[3], hi[3];
              bool overlaps = true;
              for (int a = 0; a < 3; ++a) {
                lo[a] = std::max(0, static_cast<int>(std::ceil(rel[a] - r)));
                hi[a] = std::min(kLeafDim - 1, static_cast<int>(std::floor(rel[a] + r)));
                overlaps = overlaps && lo[a] <= hi[a];
              }
              if (!overlaps) continue;
              const float px = static_cast<float>(rel[0]), py = static_cast<float>(rel[1]),
                          pz = static_cast<float>(rel[2]);
              for (int x = lo[0]; x <= hi[0]; ++x) wx[x] = (x - px) * (x - px) * invR2;
              for (int y = lo[1]; y <= hi[1]; ++y) wy[y] = (y - py) * (y - py) * invR2;
              for (int z = lo[2]; z <= hi[2]; ++z) wz[z] = (z - pz) * (z - pz) * invR2;
              for (int x = lo[0]; x <= hi[0]; ++x)
                for (int y = lo[1]; y <= hi[1]; ++y) {
                  const float dxy = wx[x] + wy[y];
                  if (dxy >= 1.0f) continue;
                  float* row = &field[static_cast<size_t>((x << (2 * kLeafLog2)) | (y << kLeafLog2))];
                  for (int z = lo[2]; z <= hi[2]; ++z) {
                    // Adding an exact 0 outside the support keeps the sum unchanged.
                    const float w = std::max(0.0f, 1.0f - (dxy + wz[z]));
                    row[z] += strength * w * w;
                  }
                }
            }
          }
      std::unique_ptr<FloatLeaf> leaf;
      std::unique_ptr<MaskLeaf> inside;
      for (openvdb::Index v = 0; v < FloatLeaf::SIZE; ++v) {
        if (field[v] <= 0.0f) continue;
        if (!leaf) leaf = std::make_unique<FloatLeaf>(origin, 0.0f, false);
        leaf->setValueOn(v, field[v]);
        if (field[v] > threshold) {
          if (!inside) inside = std::make_unique<MaskLeaf>(origin, false);
          inside->setValueOn(v);
        }
      }
      leaves[t] = std::move(leaf);
      insideLeaves[t] = std::move(inside);
    }
  });

  SummedField out;
  out.field = openvdb::FloatGrid::create(0.0f);
  out.field->setTransform(openvdb::math::Transform::createLinearTransform(h));
  out.inside = std::make_shared<openvdb::MaskTree>(false);
  for (size_t t = 0; t < targets.size(); ++t) {
    if (leaves[t]) out.field->tree().addLeaf(leaves[t].release());  // the tree takes ownership
    if (insideLeaves[t]) out.inside->addLeaf(insideLeaves[t].release());
  }
  return out;
}

Eigen::Vector3f toEigen(const openvdb::Vec3s& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

LevelSet buildMetaballLevelSet(const std::vector<Eigen::Vector3f>& positions, const MetaballParams& params) {
  checkParams(params);
  openvdb::initialize();
  if (positions.size() > std::numeric_limits<uint32_t>::max()) {
    throw std::invalid_argument("metaball: more than 2^32 particles");
  }
  LevelSet result;
  if (positions.empty()) {
    result.impl->grid = emptyLevelSetGrid(params.voxelSize, params.halfWidth);
    return result;
  }
  const float h = params.voxelSize;
  const float background = params.halfWidth * h;
  const SummedField summed = sumField(positions, params);  const openvdb::FloatGrid::Ptr& field = summed.field;
  // Restrict the sweep to a band around the surface: voxels within n (max-norm) of the inside
  // boundary. This activates the outside band beyond the field's support (value 0, which can
  // end closer to the surface than halfWidth) and drops the deep interior.
  {
    const int n = static_cast<int>(std::ceil(params.halfWidth)) + 1;
    openvdb::MaskTree outer(*summed.inside), inner(*summed.inside);
    openvdb::tools::dilateActiveValues(outer, n, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
    openvdb::tools::erodeActiveValues(inner, n, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
    field->tree().topologyUnion(outer);
    field->tree().topologyIntersection(outer);
    field->tree().topologyDifference(inner);
  }
    // Signed distance to f = T on the active voxels (negative where f > T), by fast sweeping.
  // (tools::levelSetRebuild, i.e. volumeToMesh + meshToVolume, misclassified the sign of a few
  // voxels near saddles of the summed field in the brute-force test, and was slower.)
  openvdb::FloatGrid::Ptr sdf = openvdb::tools::fogToSdf(*field, params.threshold, 1);  if (!sdf) {  // no voxel centre reaches the threshold: the surface is below the resolution
    result.impl->grid = emptyLevelSetGrid(h, params.halfWidth);
    return result;
  }
  // Keep the narrow band |d| < halfWidth * voxelSize; everything else becomes +-background.
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(sdf->tree());
  leaves.foreach([background](FloatLeaf& leaf, size_t) {
    for (auto it = leaf.beginValueOn(); it; ++it) {
      const float d = *it;
      if (d >= background) {
        leaf.setValueOff(it.pos(), background);
      } else if (d <= -background) {
        leaf.setValueOff(it.pos(), -background);
      }
    }
  });
 openvdb::tools::changeLevelSetBackground(sdf->tree(), background);
  openvdb::tools::signedFloodFill(sdf->tree());  // inactive interior -> -background
  openvdb::tools::pruneLevelSet(sdf->tree());
  sdf->setTransform(openvdb::math::Transform::createLinearTransform(h));
  sdf->setGridClass(openvdb::GRID_LEVEL_SET);  result.impl->grid = sdf;
  return result;
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

void writeLevelSets(const std::filesystem::path& path, const std::map<std::string, const LevelSet*>& grids,
                    double time, int frame) {
  openvdb::initialize();
  const std::filesystem::path tmp = path.string() + ".tmp";
  try {
    openvdb::GridPtrVec out;
    for (const auto& [name, levelSet] : grids) {
      openvdb::FloatGrid::Ptr grid;
      if (levelSet && levelSet->impl && levelSet->impl->grid) {
        grid = levelSet->impl->grid->copy();  // shares the tree; only the name differs
      } else {
        grid = emptyLevelSetGrid(1.0, 3.0f);
      }
      grid->setName(name);
      grid->setGridClass(openvdb::GRID_LEVEL_SET);
      out.push_back(grid);
    }
    openvdb::MetaMap meta;
    meta.insertMeta("kurage:time", openvdb::DoubleMetadata(time));
    meta.insertMeta("kurage:frame", openvdb::Int32Metadata(frame));
    openvdb::io::File file(tmp.string());
    file.write(out, meta);
    file.close();
    std::filesystem::rename(tmp, path);
  } catch (const std::exception& e) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("cannot write level sets to " + path.string() + ": " + e.what());
  }
}

std::map<std::string, LevelSet> readLevelSets(const std::filesystem::path& path, LevelSetFileInfo* info) {
  openvdb::initialize();
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error("cannot read level sets from " + path.string() + ": no such file");
  }
  std::map<std::string, LevelSet> result;
  try {
    openvdb::io::File file(path.string());
    file.open(/*delayLoad=*/false);  // read everything now: a truncated file must fail here
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    const openvdb::MetaMap::Ptr meta = file.getMetadata();
    file.close();
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
    }
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read level sets from " + path.string() + ": " + e.what());
  }
  return result;
}

std::map<std::string, LevelSet> readLevelSets(const std::filesystem::path& path) { return readLevelSets(path, nullptr); }

std::string openvdbVersion() { return OPENVDB_LIBRARY_VERSION_STRING; }

}  // namespace kurage::render
