// Per-pixel layers of a frame besides its colour, for compositing (the OpenEXR output): what the
// camera ray through the pixel centre meets first. Row 0 is the top, as in Image.
//   depth     metres along the viewing direction (camera z) to the first hit; +inf where it hits
//             nothing
//   normal    world-space unit shading normal at that hit, facing the camera; 0 where nothing
//   albedo    the material's albedo there (white for clear dielectrics); 0 where nothing
//   objectId  which object: kObjectSky (0) where it meets nothing, kObjectGround, kObjectLight, or
//             the objectId the caller gave the mesh, sphere set or tube (>= kObjectFirst)
//   objectNames  what each id means, by id (filled by the caller; written into the EXR header)
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace kurage::render {

// Object ids of the layers. The tracer's objects carry their own (SceneObject::objectId, ...).
enum ObjectId : uint32_t { kObjectSky = 0, kObjectGround = 1, kObjectLight = 2, kObjectFirst = 3 };

struct FrameLayers {
  int width = 0, height = 0;
  std::vector<float> depth;
  std::vector<Eigen::Vector3f> normal;
  std::vector<Eigen::Vector3f> albedo;
  std::vector<uint32_t> objectId;
  std::vector<std::string> objectNames;  // by id; may be empty

  FrameLayers() = default;
  FrameLayers(int w, int h)
      : width(w), height(h), depth(size_t(w) * size_t(h), std::numeric_limits<float>::infinity()),
        normal(size_t(w) * size_t(h), Eigen::Vector3f::Zero()), albedo(size_t(w) * size_t(h), Eigen::Vector3f::Zero()),
        objectId(size_t(w) * size_t(h), 0u) {}
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
};

}  // namespace kurage::render
