// The white furnace of the renderer's analytic tests: a uniform sky of radiance 1 all round, no
// sun, no ground, and a camera 4 m from the origin looking at it along +y. An object at the
// origin lit only by this sky reflects exactly its albedo (test_render_validation.cpp).
#pragma once

#include "render/renderer.h"

namespace kurage::test {

inline render::RenderScene furnaceScene(float verticalFovDegrees) {
  render::RenderScene scene;
  scene.environment.type = render::EnvironmentType::Uniform;
  scene.environment.zenith = {1, 1, 1};
  scene.sun.irradiance = Eigen::Vector3f::Zero();
  scene.ground.enabled = false;
  scene.camera.position = {0, -4, 0};
  scene.camera.lookAt = {0, 0, 0};
  scene.camera.up = {0, 0, 1};
  scene.camera.verticalFovDegrees = verticalFovDegrees;
  return scene;
}

}  // namespace kurage::test
