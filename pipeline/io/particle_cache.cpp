// Particle caches as OpenVDB point data grids. See particle_cache.h for the file layout.
//
// Exact positions: OpenVDB stores a point as its voxel (integer) plus an offset from the voxel
// centre. With a power-of-two voxel size v, world -> index (p / v), the offset (p / v - ijk)
// and index -> world ((ijk + offset) * v) are all exact in double precision, and the offset of
// a float p fits a float exactly (it keeps at most p's 24 significant bits), so with the
// NullCodec the float written is the float read back (the reader takes care of -0.0).
#include "pipeline/io/particle_cache.h"

#include "pipeline/io/files.h"

#include <openvdb/openvdb.h>
#include <openvdb/io/Stream.h>
#include <openvdb/points/PointAttribute.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointDataGrid.h>

#include <algorithm>
#include <optional>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace kurage::pipeline {

namespace {

namespace vp = openvdb::points;

constexpr const char* kGridName = "particles";
constexpr double kPointsPerVoxel = 8.0;

// Our own errors, already naming the path; everything else is wrapped into one of these.
struct CacheError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path, const std::string& why) {
  throw CacheError(what + " " + path.string() + ": " + why);
}

// Power-of-two voxel size with about kPointsPerVoxel points per voxel of the bounding box, large
// enough that every index coordinate fits comfortably in an int32.
double chooseVoxelSize(const ParticleFrame& frame) {
  const size_t n = frame.size();
  if (n == 0) return 1.0;
  double lo[3] = {frame.px[0], frame.py[0], frame.pz[0]};
  double hi[3] = {lo[0], lo[1], lo[2]};
  double maxAbs = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double p[3] = {frame.px[i], frame.py[i], frame.pz[i]};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
      maxAbs = std::max(maxAbs, std::abs(p[a]));
    }
  }
  // Volume of the box, each side at least a tiny fraction of the largest, so that flat or
  // degenerate sets still get a sensible size.
  const double largest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-6});
  double volume = 1.0;
  for (int a = 0; a < 3; ++a) volume *= std::max(hi[a] - lo[a], largest * 1e-3);
  const double ideal = std::cbrt(volume * kPointsPerVoxel / static_cast<double>(n));
  int exponent = static_cast<int>(std::lround(std::log2(ideal)));
  exponent = std::clamp(exponent, -12, 24);  // OpenVDB refuses scales below ~1.4e-5
  // Index coordinates stay below 2^28 in magnitude.
  while (maxAbs / std::ldexp(1.0, exponent) >= std::ldexp(1.0, 28)) ++exponent;
  return std::ldexp(1.0, exponent);
}

void checkFrame(const std::filesystem::path& path, const ParticleFrame& f) {
  const size_t n = f.size();
  if (f.py.size() != n || f.pz.size() != n || f.vx.size() != n || f.vy.size() != n || f.vz.size() != n ||
      f.id.size() != n || f.kind.size() != n || (!f.restDensityFactor.empty() && f.restDensityFactor.size() != n)) {
    fail("cannot write particles to", path, "arrays of different lengths");
  }
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(f.px[i]) || !std::isfinite(f.py[i]) || !std::isfinite(f.pz[i])) {
      fail("cannot write particles to", path, "particle " + std::to_string(f.id[i]) + " has a non-finite position");
    }
  }
  for (const std::string& name : f.kindNames) {
    if (name.find(',') != std::string::npos) fail("cannot write particles to", path, "kind name '" + name + "' has a comma");
  }
}

std::string joinKinds(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) out += (i ? "," : "") + names[i];
  return out;
}

std::vector<std::string> splitKinds(const std::string& joined) {
  std::vector<std::string> out;
  if (joined.empty()) return out;
  size_t start = 0;
  while (true) {
    const size_t comma = joined.find(',', start);
    out.push_back(joined.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

void writeParticleFrame(const std::filesystem::path& path, const ParticleFrame& frame) {
  checkFrame(path, frame);
  openvdb::initialize();
  std::ostringstream bytes;
  try {
    const size_t n = frame.size();
    std::vector<openvdb::Vec3f> positions(n), velocities(n);
    for (size_t i = 0; i < n; ++i) {
      positions[i] = openvdb::Vec3f(frame.px[i], frame.py[i], frame.pz[i]);
      velocities[i] = openvdb::Vec3f(frame.vx[i], frame.vy[i], frame.vz[i]);
    }
    const openvdb::math::Transform::Ptr transform =
        openvdb::math::Transform::createLinearTransform(chooseVoxelSize(frame));

    const vp::PointAttributeVector<openvdb::Vec3f> positionWrapper(positions);
    const auto indexGrid = openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(positionWrapper, *transform);
    vp::PointDataGrid::Ptr grid =
        vp::createPointDataGrid<vp::NullCodec, vp::PointDataGrid>(*indexGrid, positionWrapper, *transform);
    grid->setName(kGridName);

    vp::PointDataTree& tree = grid->tree();
    const auto& indexTree = indexGrid->tree();
    vp::appendAttribute<openvdb::Vec3f, vp::NullCodec>(tree, "v");
    vp::populateAttribute(tree, indexTree, "v", vp::PointAttributeVector<openvdb::Vec3f>(velocities));
    vp::appendAttribute<int64_t>(tree, "id");
    vp::populateAttribute(tree, indexTree, "id", vp::PointAttributeVector<int64_t>(frame.id));
    vp::appendAttribute<int32_t>(tree, "kind");
    vp::populateAttribute(tree, indexTree, "kind", vp::PointAttributeVector<int32_t>(frame.kind));
    const std::vector<float> factor = frame.restDensityFactor.empty() ? std::vector<float>(n, 1.0f) : frame.restDensityFactor;
    vp::appendAttribute<float, vp::NullCodec>(tree, "rest_density_factor");
    vp::populateAttribute(tree, indexTree, "rest_density_factor", vp::PointAttributeVector<float>(factor));

    openvdb::MetaMap meta;
    meta.insertMeta("kurage:time", openvdb::DoubleMetadata(frame.time));
    meta.insertMeta("kurage:frame", openvdb::Int32Metadata(frame.frame));
    meta.insertMeta("kurage:kinds", openvdb::StringMetadata(joinKinds(frame.kindNames)));
    meta.insertMeta("kurage:stage", openvdb::StringMetadata("sim"));
    meta.insertMeta("kurage:scene_hash", openvdb::StringMetadata(frame.sceneHash));
    meta.insertMeta("kurage:checksum", openvdb::StringMetadata(std::string(kChecksumPlaceholder)));
    openvdb::io::Stream(bytes).write(openvdb::GridCPtrVec{grid}, meta);
    if (!bytes) fail("cannot write particles to", path, "serialisation failed");
  } catch (const CacheError&) {
    throw;
  } catch (const std::exception& e) {
    fail("cannot write particles to", path, e.what());
  }
  writeSealed(path, std::move(bytes).str());
}

ParticleFrame readParticleFrame(const std::filesystem::path& path, const FileStamp& expected) {
  openvdb::initialize();
  std::istringstream in(readVerified(path));  // the checksum is checked before OpenVDB parses

  vp::PointDataGrid::Ptr grid;
  openvdb::MetaMap::Ptr meta;
  try {
    openvdb::io::Stream file(in, /*delayLoad=*/false);
    meta = file.getMetadata();
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    if (!meta || !grids) fail("cannot read particles from", path, "not an OpenVDB stream");
    const auto stringMeta = [&meta](const char* key) {
      const auto value = meta->getMetadata<openvdb::StringMetadata>(key);
      return value ? value->value() : std::string("(none)");
    };
    const auto number = meta->getMetadata<openvdb::Int32Metadata>("kurage:frame");
    checkStamp({stringMeta("kurage:stage"), stringMeta("kurage:scene_hash"), number ? number->value() : -1}, expected,
               path);
    for (const openvdb::GridBase::Ptr& base : *grids)
      if (base && base->getName() == kGridName) grid = openvdb::gridPtrCast<vp::PointDataGrid>(base);
    if (!grid) fail("cannot read particles from", path, "no point data grid named 'particles'");
  } catch (const IoError&) {
    throw;
  } catch (const CacheError&) {
    throw;
  } catch (const std::exception& e) {
    fail("cannot read particles from", path, e.what());
  }
  if (!grid) fail("cannot read particles from", path, "grid 'particles' is not a point data grid");

  ParticleFrame frame;
  const auto time = meta->getMetadata<openvdb::DoubleMetadata>("kurage:time");
  const auto number = meta->getMetadata<openvdb::Int32Metadata>("kurage:frame");
  const auto kinds = meta->getMetadata<openvdb::StringMetadata>("kurage:kinds");
  if (!time || !number || !kinds) {
    fail("cannot read particles from", path, "missing file metadata kurage:time, kurage:frame or kurage:kinds");
  }
  frame.time = time->value();
  frame.frame = number->value();
  frame.kindNames = splitKinds(kinds->value());
  if (const auto hash = meta->getMetadata<openvdb::StringMetadata>("kurage:scene_hash")) frame.sceneHash = hash->value();

  struct Raw {
    float p[3], v[3];
    int64_t id;
    int32_t kind;
    float restDensityFactor;
  };
  std::vector<Raw> raw;
  const openvdb::math::Transform& xform = grid->transform();
  // Our own files use a uniform power-of-two scale: convert per component as ijk * v + offset * v
  // with the ijk term dropped when it is 0, so that -0.0 keeps its sign. Other transforms go
  // through OpenVDB's indexToWorld.
  const bool uniformScale = xform.mapType() == openvdb::math::UniformScaleMap::mapType();
  const double voxelSize = xform.voxelSize()[0];
  const auto toWorld = [&](const openvdb::Coord& ijk, const openvdb::Vec3f& offset) {
    if (!uniformScale) return openvdb::Vec3d(xform.indexToWorld(ijk.asVec3d() + openvdb::Vec3d(offset)));
    openvdb::Vec3d world;
    for (int a = 0; a < 3; ++a) {
      world[a] = ijk[a] == 0 ? double(offset[a]) * voxelSize : (double(ijk[a]) + double(offset[a])) * voxelSize;
    }
    return world;
  };
  try {
    for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
      const vp::AttributeSet::Descriptor& descriptor = leaf->attributeSet().descriptor();
      for (const char* name : {"P", "v", "id", "kind"}) {
        if (descriptor.find(name) == vp::AttributeSet::INVALID_POS) {
          fail("cannot read particles from", path, std::string("missing point attribute '") + name + "'");
        }
      }
      const vp::AttributeHandle<openvdb::Vec3f> position(leaf->constAttributeArray("P"));
      const vp::AttributeHandle<openvdb::Vec3f> velocity(leaf->constAttributeArray("v"));
      const vp::AttributeHandle<int64_t> id(leaf->constAttributeArray("id"));
      const vp::AttributeHandle<int32_t> kind(leaf->constAttributeArray("kind"));
      const bool hasFactor = descriptor.find("rest_density_factor") != vp::AttributeSet::INVALID_POS;
      std::optional<vp::AttributeHandle<float>> factor;
      if (hasFactor) factor.emplace(leaf->constAttributeArray("rest_density_factor"));
      for (auto index = leaf->beginIndexOn(); index; ++index) {
        const openvdb::Vec3d world = toWorld(index.getCoord(), position.get(*index));
        const openvdb::Vec3f v = velocity.get(*index);
        raw.push_back(Raw{{float(world[0]), float(world[1]), float(world[2])}, {v[0], v[1], v[2]}, id.get(*index),
                          kind.get(*index), factor ? factor->get(*index) : 1.0f});
      }
    }
  } catch (const CacheError&) {
    throw;
  } catch (const std::exception& e) {
    fail("cannot read particles from", path, e.what());
  }

  std::stable_sort(raw.begin(), raw.end(), [](const Raw& a, const Raw& b) { return a.id < b.id; });
  const size_t n = raw.size();
  for (auto* array : {&frame.px, &frame.py, &frame.pz, &frame.vx, &frame.vy, &frame.vz}) array->resize(n);
  frame.id.resize(n);
  frame.kind.resize(n);
  frame.restDensityFactor.resize(n);
  for (size_t i = 0; i < n; ++i) {
    frame.restDensityFactor[i] = raw[i].restDensityFactor;
    frame.px[i] = raw[i].p[0];
    frame.py[i] = raw[i].p[1];
    frame.pz[i] = raw[i].p[2];
    frame.vx[i] = raw[i].v[0];
    frame.vy[i] = raw[i].v[1];
    frame.vz[i] = raw[i].v[2];
    frame.id[i] = raw[i].id;
    frame.kind[i] = raw[i].kind;
  }
  return frame;
}

}  // namespace kurage::pipeline
