#include "pipeline/render_scene.h"
#include "pipeline/io/files.h"
#include "pipeline/sim_frame.h"

#include "render/image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace kurage::pipeline {

render::TriangleMesh tankMesh(const Scene& scene, const Eigen::Vector3f& eye) {
  const sim::ContainerParams& box = scene.sim.container;
  const float top = scene.render.tank.height > 0.0f ? box.min.z() + scene.render.tank.height : box.max.z();
  render::TriangleMesh mesh;
  for (int axis = 0; axis < 2; ++axis)
    for (int side = 0; side < 2; ++side) {
      const float c = side == 0 ? box.min[axis] : box.max[axis];
      const bool seenFromInside = side == 0 ? eye[axis] > c : eye[axis] < c;
      if (!seenFromInside) continue;
      const int other = 1 - axis;
      const int base = int(mesh.positions.size());
      for (const auto& [u, z] : {std::pair{box.min[other], box.min.z()}, std::pair{box.max[other], box.min.z()},
                                 std::pair{box.max[other], top}, std::pair{box.min[other], top}}) {
        Eigen::Vector3f v;
        v[axis] = c;
        v[other] = u;
        v.z() = z;
        mesh.positions.push_back(v);
      }
      mesh.triangles.emplace_back(base, base + 1, base + 2);
      mesh.triangles.emplace_back(base, base + 2, base + 3);
    }
  return mesh;
}

render::CurveSet faucetTubes(const Scene& scene) {
  render::CurveSet set;
  set.material = scene.render.faucets.material;
  set.objectId = kObjectTank;
  const sim::ContainerParams& box = scene.sim.container;
  const float top = scene.render.tank.height > 0.0f ? box.min.z() + scene.render.tank.height : box.max.z();
  for (const sim::EmitterParams& e : scene.sim.emitters) {
    const Eigen::Vector3f d = e.direction.normalized();
    const float radius = kFaucetRadiusScale * e.radius;
    // The end cap (a half sphere of the pipe's radius) reaches the nozzle's disc.
    const Eigen::Vector3f mouth = e.position - radius * d;
    // Back along the jet until the pipe clears the tank's rim (at least two radii), then up.
    const float clear = top + 2.0f * radius;
    const float back = d.z() < 0.0f ? std::max(2.0f * radius, (clear - mouth.z()) / -d.z()) : 2.0f * radius;
    const Eigen::Vector3f elbow = mouth - back * d;
    render::Tube tube;
    tube.points = {mouth, elbow, elbow + Eigen::Vector3f(0, 0, std::max(clear - elbow.z(), 0.0f) + kFaucetRise)};
    tube.radii.assign(tube.points.size(), radius);
    set.tubes.push_back(std::move(tube));
  }
  return set;
}

render::RenderScene makeRenderScene(const Scene& scene, double time) {
  const RenderParams& p = scene.render;
  render::RenderScene out;
  out.camera = render::cameraAt(p.camera, p.cameraKeys, time);
  out.sun = p.sun;
  out.rectLights = p.areaLights;
  out.ground = p.ground;
  out.clip = p.clip;
  out.environment.type = p.environment.type;
  out.environment.zenith = p.environment.zenith;
  out.environment.horizon = p.environment.horizon;
  out.environment.up = Eigen::Vector3f::UnitZ();
  out.environment.intensity = p.environment.intensity;
  out.environment.rotationDegrees = p.environment.rotation;
  if (p.tank.enabled) {
    auto tank = std::make_shared<render::TriangleMesh>(tankMesh(scene, out.camera.position));
    if (!tank->triangles.empty()) {
      out.staticMeshes.push_back({tank.get(), p.tank.material, kObjectTank});
      out.ownedMeshes.push_back(std::move(tank));
    }
  }
  if (p.faucets.enabled && !scene.sim.emitters.empty()) out.curves.push_back(faucetTubes(scene));
  if (p.environment.type == render::EnvironmentType::Image) {
    requireRegularFile(p.environment.image);  // libpng opens it itself: a FIFO would block
    out.environment.image = std::make_shared<const render::Image>(render::readPng(p.environment.image));
  }
  return out;
}

std::vector<std::string> objectNames(const Scene& scene) {
  std::vector<std::string> names{"sky", "ground", "area_light", "tank"};
  for (const std::string& kind : kindNames(scene)) names.push_back(kind);
  return names;
}

bool hasChains(const Scene& scene) {
  return std::any_of(scene.sim.bodies.begin(), scene.sim.bodies.end(),
                     [](const sim::BodyParams& b) { return b.shape == sim::BodyShape::Chain; });
}

std::vector<ChainOrder> chainOrder(const Scene& scene, const ParticleFrame& frame) {
  // Body b's particles have kind b + 1. sim::BodySystem gives each body's particles consecutive
  // ids in the order sim/body_shapes.cpp makes its points, and a chain's points go from its start
  // (where it hangs) to its end, so ordering a chain's particles by id gives the chain order.
  // (The cache comes sorted by id; a simulation's own particles are sorted by grid cell.)
  std::vector<std::vector<std::pair<int64_t, size_t>>> byBody(scene.sim.bodies.size());
  for (size_t i = 0; i < frame.size(); ++i) {
    const int32_t kind = frame.kind[i];
    if (kind >= 1 && size_t(kind) <= byBody.size() && scene.sim.bodies[size_t(kind - 1)].shape == sim::BodyShape::Chain)
      byBody[size_t(kind - 1)].emplace_back(frame.id[i], i);
  }
  std::vector<ChainOrder> chains;
  for (size_t b = 0; b < byBody.size(); ++b) {
    if (byBody[b].empty()) continue;
    std::sort(byBody[b].begin(), byBody[b].end());
    ChainOrder chain;
    chain.kind = int(b + 1);
    for (const auto& [id, i] : byBody[b]) chain.indices.push_back(i);
    chains.push_back(std::move(chain));
  }
  return chains;
}

render::CurveSet chainTubes(const Scene& scene, const ParticleFrame& frame) {
  render::CurveSet set;
  set.material = scene.render.chainMaterial;
  const ChainRadiusParams& radius = scene.render.chainRadius;
  for (const ChainOrder& chain : chainOrder(scene, frame)) {
    if (chain.indices.size() < 2) continue;
    render::Tube tube;
    for (size_t k = 0; k < chain.indices.size(); ++k) {
      const size_t i = chain.indices[k];
      const Eigen::Vector3f p(frame.px[i], frame.py[i], frame.pz[i]);
      if (!tube.points.empty() && p == tube.points.back()) continue;
      tube.points.push_back(p);
      tube.radii.push_back(radius.root + (radius.tip - radius.root) * float(k) / float(chain.indices.size() - 1));
    }
    tube.objectId = objectIdOfKind(chain.kind);
    if (tube.points.size() >= 2) set.tubes.push_back(std::move(tube));
  }
  return set;
}

Eigen::Vector3f colourRamp(float t) {
  // Five stops close to matplotlib's viridis.
  static const std::array<Eigen::Vector3f, 5> stops{Eigen::Vector3f(0.267f, 0.005f, 0.329f),
                                                    Eigen::Vector3f(0.229f, 0.322f, 0.546f),
                                                    Eigen::Vector3f(0.128f, 0.567f, 0.551f),
                                                    Eigen::Vector3f(0.369f, 0.789f, 0.383f),
                                                    Eigen::Vector3f(0.993f, 0.906f, 0.144f)};
  if (!(t > 0.0f)) return stops.front();
  if (t >= 1.0f) return stops.back();
  const float x = t * float(stops.size() - 1);
  const size_t i = std::min(size_t(x), stops.size() - 2);
  const float s = x - float(i);
  return (1.0f - s) * stops[i] + s * stops[i + 1];
}

render::SphereSet particleSpheres(const Scene& scene, const ParticleFrame& frame) {
  const ParticleDisplayParams& d = scene.render.particles;
  render::SphereSet set;
  set.radius = d.radius > 0.0f ? d.radius : 0.4f * scene.sim.fluid.spacing;
  set.material.type = render::MaterialType::Diffuse;
  const size_t n = frame.size();
  set.centres.reserve(n);
  set.colours.reserve(n);
  std::vector<float> values(n, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    set.centres.emplace_back(frame.px[i], frame.py[i], frame.pz[i]);
    if (d.colourBy == ParticleColouring::Speed)
      values[i] = Eigen::Vector3f(frame.vx[i], frame.vy[i], frame.vz[i]).norm();
    else if (d.colourBy == ParticleColouring::RestDensityFactor)
      values[i] = frame.restDensityFactor.size() == n ? frame.restDensityFactor[i] : 1.0f;
  }
  float lo = d.rangeMin, hi = d.rangeMax;
  if (!(hi > lo) && n > 0) {
    lo = *std::min_element(values.begin(), values.end());
    hi = *std::max_element(values.begin(), values.end());
  }
  static const std::array<Eigen::Vector3f, 6> kindColours{
      Eigen::Vector3f(0.15f, 0.4f, 0.85f), Eigen::Vector3f(0.9f, 0.35f, 0.2f), Eigen::Vector3f(0.3f, 0.75f, 0.3f),
      Eigen::Vector3f(0.9f, 0.75f, 0.15f), Eigen::Vector3f(0.65f, 0.3f, 0.8f), Eigen::Vector3f(0.85f, 0.85f, 0.85f)};
  for (size_t i = 0; i < n; ++i) {
    if (d.colourBy == ParticleColouring::Kind)
      set.colours.push_back(kindColours[size_t(std::max(0, frame.kind[i])) % kindColours.size()]);
    else
      set.colours.push_back(colourRamp(hi > lo ? (values[i] - lo) / (hi - lo) : 0.5f));
  }
  return set;
}

}  // namespace kurage::pipeline
