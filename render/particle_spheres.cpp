// OpenVDB's ParticlesToLevelSet behind a small header (it is the heaviest OpenVDB include).
#include "render/particle_spheres.h"

#include "render/level_set_impl.h"

#include <openvdb/tools/ParticlesToLevelSet.h>

#include <stdexcept>

namespace kurage::render {

namespace {

// The particle list interface ParticlesToLevelSet expects (see its header): world positions.
class ParticleList {
public:
  using PosType = openvdb::Vec3R;
  ParticleList(const std::vector<Eigen::Vector3f>& positions, double radius) : positions_(positions), radius_(radius) {}
  size_t size() const { return positions_.size(); }
  void getPos(size_t n, openvdb::Vec3R& xyz) const {
    const Eigen::Vector3f& p = positions_[n];
    xyz = openvdb::Vec3R(p.x(), p.y(), p.z());
  }
  void getPosRad(size_t n, openvdb::Vec3R& xyz, openvdb::Real& radius) const {
    getPos(n, xyz);
    radius = radius_;
  }

private:
  const std::vector<Eigen::Vector3f>& positions_;
  double radius_;
};

}  // namespace

LevelSet buildParticleSpheresLevelSet(const std::vector<Eigen::Vector3f>& positions, float radius, float voxelSize,
                                      float halfWidth) {
  if (!(radius > 0) || !(voxelSize > 0) || !(halfWidth >= 1))
    throw std::invalid_argument("particle spheres: need radius, voxelSize > 0 and halfWidth >= 1");
  openvdb::initialize();
  auto grid = openvdb::createLevelSet<openvdb::FloatGrid>(voxelSize, halfWidth);
  const ParticleList list(positions, radius);
  openvdb::tools::particlesToSdf(list, *grid);
  LevelSet result;
  result.impl->grid = grid;
  return result;
}

}  // namespace kurage::render
