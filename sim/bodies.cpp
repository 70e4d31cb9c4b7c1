#include "sim/bodies.h"

#include "sim/solvers/pressure_solver.h"

#include "sim/fluid.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <limits>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace kurage::sim {

float ForceCurve::at(double t) const {
  if (type == CurveType::Keys) {
    if (keys.empty()) return 0.0f;
    if (t <= keys.front().time) return keys.front().value;
    for (size_t k = 1; k < keys.size(); ++k)
      if (t < keys[k].time) {
        const double u = (t - keys[k - 1].time) / (keys[k].time - keys[k - 1].time);
        return float(keys[k - 1].value + u * (keys[k].value - keys[k - 1].value));
      }
    return keys.back().value;
  }
  if (t < start || period <= 0.0f) return 0.0f;
  const double cycle = std::floor((t - start) / period);
  if (start + cycle * period >= end) return 0.0f;
  const double phase = t - start - cycle * period;  // s into this pulse
  const double on = double(duty) * period;
  if (phase >= on) return 0.0f;
  const double r = std::min(double(ramp), 0.5 * on);
  double shape = 1.0;
  if (r > 0.0) shape = std::min({1.0, phase / r, (on - phase) / r});
  return float(amplitude * shape);
}

namespace {

std::string str(float v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Calls f(a, b) for every pair of points closer than `radius` (a sweep along x).
template <class F>
void forPairsWithin(const std::vector<Eigen::Vector3f>& points, float radius, F&& f) {
  std::vector<uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return points[a].x() < points[b].x(); });
  for (size_t s = 0; s < order.size(); ++s)
    for (size_t t = s + 1; t < order.size(); ++t) {
      if (points[order[t]].x() - points[order[s]].x() >= radius) break;
      if ((points[order[t]] - points[order[s]]).squaredNorm() < radius * radius) f(order[s], order[t]);
    }
}

struct BuiltBodies {
  std::vector<BodyPoints> points;
  std::vector<int64_t> firstId;  // id of each body's first particle
  std::vector<SpringPair> pairs;
  size_t count = 0;
};

// Particles, ids and springs of every body (with muscle bits), and the problems found on the way.
BuiltBodies buildBodies(const SimParams& params, std::vector<BodyProblem>& problems) {
  BuiltBodies built;
  const float l = params.fluid.spacing;
  for (const BodyParams& body : params.bodies) {
    built.firstId.push_back(int64_t(built.count));
    built.points.push_back(bodyPoints(body, l));
    built.count += built.points.back().positions.size();
  }
  int muscleBit = 0;
  for (size_t b = 0; b < params.bodies.size(); ++b) {
    const BodyParams& body = params.bodies[b];
    const BodyPoints& pts = built.points[b];
    if (pts.positions.empty()) {
      problems.push_back({b, "", "the shape yields no particle at spacing " + str(body.spacingMetres(l)) + " m"});
      continue;
    }
    std::vector<int64_t> ids(pts.positions.size());
    std::iota(ids.begin(), ids.end(), built.firstId[b]);
    std::vector<SpringPair> pairs = springPairsWithin(pts.positions, ids, body.connectionRadius * l, uint16_t(b));
    // A chain hangs from the particles of `attach_to` within its connection radius of its start.
    if (body.shape == BodyShape::Chain) {
      const auto target = std::find_if(params.bodies.begin(), params.bodies.end(),
                                       [&](const BodyParams& o) { return o.name == body.attachTo && &o != &body; });
      if (body.attachTo.empty()) {
        // a free chain
      } else if (target == params.bodies.end()) {
        problems.push_back({b, "attach_to", "no other body is named \"" + body.attachTo + "\""});
      } else {
        const size_t t = size_t(target - params.bodies.begin());
        size_t joined = 0;
        for (size_t k = 0; k < built.points[t].positions.size(); ++k) {
          const float d = (built.points[t].positions[k] - pts.positions[0]).norm();
          if (d < body.connectionRadius * l && d > 0.0f) {
            pairs.push_back({built.firstId[b], built.firstId[t] + int64_t(k), d, uint16_t(b), 0});
            ++joined;
          }
        }
        if (!joined)
          problems.push_back({b, "attach_to", "no particle of \"" + body.attachTo + "\" lies within the connection radius " +
                                                  str(body.connectionRadius * l) + " m of the chain's start"});
      }
    }
    if (pairs.empty() && pts.positions.size() > 1) {
      problems.push_back({b, "connection_radius", "joins no spring: h_spr = " + str(body.connectionRadius * l) +
                                                      " m is below the particle spacing " + str(body.spacingMetres(l)) + " m"});
    } else if (pts.positions.size() > 1) {
      std::vector<uint8_t> joined(pts.positions.size(), 0);
      for (const SpringPair& p : pairs) {
        if (p.a >= built.firstId[b] && p.a < built.firstId[b] + int64_t(ids.size())) joined[size_t(p.a - built.firstId[b])] = 1;
        if (p.b >= built.firstId[b] && p.b < built.firstId[b] + int64_t(ids.size())) joined[size_t(p.b - built.firstId[b])] = 1;
      }
      const size_t lonely = size_t(std::count(joined.begin(), joined.end(), 0));
      if (lonely)
        problems.push_back({b, "connection_radius", "leaves " + std::to_string(lonely) + " particle(s) without a spring"});
    }
    for (size_t m = 0; m < body.muscles.size(); ++m, ++muscleBit) {
      const std::string field = "muscles[" + std::to_string(m) + "].springs";
      if (muscleBit >= SpringNetwork::kMaxMuscles) {
        problems.push_back({b, "muscles[" + std::to_string(m) + "]", "more than 32 muscles in the scene"});
        continue;
      }
      size_t members = 0;
      for (SpringPair& p : pairs) {
        const int64_t first = built.firstId[b], last = first + int64_t(ids.size());
        if (p.a < first || p.a >= last || p.b < first || p.b >= last) continue;  // attachment springs
        if (selected(body.muscles[m].springs, pts, size_t(p.a - first)) &&
            selected(body.muscles[m].springs, pts, size_t(p.b - first))) {
          p.muscles |= 1u << muscleBit;
          ++members;
        }
      }
      if (!members) problems.push_back({b, field, "selects no spring (both ends of a spring must be selected)"});
    }
    for (size_t k = 0; k < body.pins.size(); ++k) {
      size_t members = 0;
      for (size_t i = 0; i < pts.positions.size(); ++i) members += selected(body.pins[k], pts, i);
      if (!members) problems.push_back({b, "pins[" + std::to_string(k) + "]", "selects no particle"});
    }
    for (size_t k = 0; k < body.parts.size(); ++k) {
      size_t members = 0;
      for (size_t i = 0; i < pts.positions.size(); ++i) members += selected(body.parts[k].particles, pts, i);
      if (!members) problems.push_back({b, "parts[" + std::to_string(k) + "].particles", "selects no particle"});
    }
    built.pairs.insert(built.pairs.end(), pairs.begin(), pairs.end());
  }
  return built;
}

}  // namespace

std::vector<BodyProblem> checkBodies(const SimParams& params) {
  std::vector<BodyProblem> problems;
  const BuiltBodies built = buildBodies(params, problems);
  const float l = params.fluid.spacing;
  const ContainerParams& box = params.container;
  for (size_t b = 0; b < params.bodies.size(); ++b)
    for (const Eigen::Vector3f& q : built.points[b].positions)
      if ((q.array() < box.min.array()).any() || (q.array() > box.max.array()).any()) {
        std::ostringstream s;
        s << "a particle at [" << q.x() << ", " << q.y() << ", " << q.z() << "] lies outside the container";
        problems.push_back({b, "", s.str()});
        break;
      }
  // Bodies overlapping one another: particles closer than their mean diameter.
  std::vector<Eigen::Vector3f> all;
  std::vector<uint32_t> owner;
  float largest = 0.0f;
  for (size_t b = 0; b < params.bodies.size(); ++b) {
    for (const Eigen::Vector3f& q : built.points[b].positions) {
      all.push_back(q);
      owner.push_back(uint32_t(b));
    }
    largest = std::max(largest, params.bodies[b].spacingMetres(l));
  }
  std::vector<std::pair<uint32_t, uint32_t>> overlaps;
  forPairsWithin(all, largest, [&](uint32_t a, uint32_t c) {
    if (owner[a] == owner[c]) return;
    const float d = 0.5f * (params.bodies[owner[a]].spacingMetres(l) + params.bodies[owner[c]].spacingMetres(l));
    if ((all[a] - all[c]).norm() < 0.999f * d) overlaps.emplace_back(std::min(owner[a], owner[c]), std::max(owner[a], owner[c]));
  });
  std::sort(overlaps.begin(), overlaps.end());
  overlaps.erase(std::unique(overlaps.begin(), overlaps.end()), overlaps.end());
  for (const auto& [a, c] : overlaps)
    problems.push_back({c, "", "overlaps bodies[" + std::to_string(a) + "] (\"" + params.bodies[a].name +
                                   "\"): particles closer than their diameter at the start"});
  for (size_t b = 0; b < params.bodies.size(); ++b)
    for (size_t o = 0; o < b; ++o)
      if (params.bodies[o].name == params.bodies[b].name)
        problems.push_back({b, "name", "\"" + params.bodies[b].name + "\" is also the name of bodies[" + std::to_string(o) + "]"});
  return problems;
}

BodySystem::BodySystem(const SimParams& params, ParticleSet& particles, int64_t& nextId) {
  if (nextId != 0) throw std::invalid_argument("bodies: body particles must be created first");
  std::vector<BodyProblem> problems;
  BuiltBodies built = buildBodies(params, problems);
  if (!problems.empty())
    throw std::invalid_argument("bodies[" + std::to_string(problems[0].body) + "]" +
                                (problems[0].field.empty() ? "" : "." + problems[0].field) + ": " + problems[0].message);
  const float l = params.fluid.spacing, h = params.fluid.supportRadiusMetres();
  fluidContact_ = params.collisions.fluidContact;
  bodyOf_.reserve(built.count);
  for (size_t b = 0; b < params.bodies.size(); ++b) {
    const BodyParams& body = params.bodies[b];
    // Each phase's mass is calibrated at its own spacing and rest density (SPEC §1); a part with
    // its own specific gravity is a phase of its own (the mass is linear in the rest density).
    mass_.push_back(calibratedParticleMass(body.spacingMetres(l), h, body.restDensity(), densityKernelOf(params.fluid)));
    restDensity_.push_back(body.restDensity());
    double gravitySum = 0.0;
    telescopicBody_.push_back(body.telescopicDensity);
    telescopicMeasure_.push_back(body.telescopicMeasure);
    telescopic_ = telescopic_ || body.telescopicDensity;
    boundaryBody_.push_back(body.coupling == BodyCoupling::Boundary);
    boundaryCoupled_ = boundaryCoupled_ || body.coupling == BodyCoupling::Boundary;
    groups_.push_back({body.stiffness, body.damping, body.damper == Damper::Implicit});
    const BodyPoints& pts = built.points[b];
    for (size_t k = 0; k < pts.positions.size(); ++k) {
      const Eigen::Vector3f& q = pts.positions[k];
      float gravity = body.specificGravity;
      for (const BodyPart& part : body.parts)
        if (selected(part.particles, pts, k)) gravity = part.specificGravity;
      gravitySum += gravity;
      const float rho0 = 1000.0f * gravity, m = mass_[b] * (gravity / body.specificGravity);
      baseDensity_.push_back(rho0);
      particleMass_.push_back(m);
      particles.add(q.x(), q.y(), q.z(), 0, 0, 0, rho0, m, nextId++, int32_t(b + 1));
      bodyOf_.push_back(int32_t(b));
      diameter_.push_back(body.spacingMetres(l));
      contactScale_.push_back(body.fluidContactScale);
      bool pin = false;
      for (const Selection& s : body.pins) pin = pin || selected(s, pts, k);
      pinnedUntil_.push_back(pin ? std::numeric_limits<float>::infinity() : std::max(0.0f, body.holdUntil));
      if (pinnedUntil_.back() > 0.0f) {
        pinnedIds_.push_back(int64_t(bodyOf_.size() - 1));
        pinnedAt_.push_back(q);
      }
    }
    if (body.shape == BodyShape::Chain && body.bending > 0.0f)
      for (int64_t k = 1; k + 1 < int64_t(pts.positions.size()); ++k)
        bends_.push_back({built.firstId[b] + k - 1, built.firstId[b] + k, built.firstId[b] + k + 1, body.bending});
    for (const MuscleParams& m : body.muscles)
      muscles_.push_back({m.force, m.righting, m.ceiling, m.ceilingBand, m.ceilingLead, built.firstId[b],
                          int64_t(pts.positions.size()), {}});
    meanGravity_.push_back(pts.positions.empty() ? body.specificGravity : float(gravitySum / double(pts.positions.size())));
  }
  for (float s : contactScale_) maxContactScale_ = std::max(maxContactScale_, s);
  muscleForces_.assign(muscles_.size(), 0.0f);
  if (params.gravity.norm() > 0.0f) up_ = -params.gravity.normalized();
  muscleWeights_.resize(muscles_.size());
  weightPointers_.assign(muscles_.size(), nullptr);
  for (const SpringPair& pair : built.pairs)
    for (uint32_t bits = pair.muscles; bits; bits &= bits - 1) {
      Muscle& m = muscles_[size_t(std::countr_zero(bits))];
      if (m.righting > 0.0f) m.ring.insert(m.ring.end(), {pair.a, pair.b});
    }
  for (size_t m = 0; m < muscles_.size(); ++m) {
    if (!(muscles_[m].righting > 0.0f) || params.gravity.norm() == 0.0f) continue;
    std::vector<int64_t>& ring = muscles_[m].ring;
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    muscleWeights_[m].assign(built.count, 1.0f);
    weightPointers_[m] = muscleWeights_[m].data();
  }
  lengthRatio_.assign(built.count, 1.0f);
  springs_ = SpringNetwork::fromPairs(built.pairs);
  // Explicit stability of each particle's springs and dampers (Gershgorin bounds). The bending
  // term's stiffness matrix is k_b / 2 D^T D (D the second difference, |D^T D| <= 16): 8 k_b
  // shared among the three particles of each bend.
  std::vector<double> bendStiffness(built.count, 0.0);
  for (const Bend& bend : bends_)
    for (const int64_t id : {bend.prev, bend.mid, bend.next}) bendStiffness[size_t(id)] += 8.0 * bend.stiffness / 3.0;
  springStep_ = 0.0f;
  for (size_t id = 0; id < built.count; ++id) {
    double k = 0.0, d = 0.0;
    for (const SpringNetwork::End* s = springs_.begin(int64_t(id)); s != springs_.end(int64_t(id)); ++s) {
      k += groups_[s->group].stiffness;
      if (!groups_[s->group].implicitDamper) d += groups_[s->group].damping;
    }
    k += bendStiffness[id];
    const double m = particleMass_[id];
    double step = std::numeric_limits<double>::infinity();
    if (k > 0.0) step = std::min(step, std::sqrt(2.0 * m / k));
    if (d > 0.0) step = std::min(step, m / d);
    if (std::isfinite(step) && (springStep_ == 0.0f || step < springStep_)) springStep_ = float(step);
  }
  indexOfId_.assign(built.count, UINT32_MAX);
}

size_t BodySystem::memoryBytes() const {
  return springs_.memoryBytes() + indexOfId_.capacity() * 4 + bodyOf_.capacity() * 4 + diameter_.capacity() * 4 +
         contactScale_.capacity() * 4 +
         baseDensity_.capacity() * 4 + particleMass_.capacity() * 4 +
         lengthRatio_.capacity() * 4 + pinnedUntil_.capacity() * 4 + cells_.order.capacity() * sizeof(cells_.order[0]) +
         cells_.range.capacity() * sizeof(cells_.range[0]) +
         std::accumulate(muscleWeights_.begin(), muscleWeights_.end(), size_t(0),
                         [](size_t sum, const std::vector<float>& w) { return sum + w.capacity() * 4; });
}

void BodySystem::index(const ParticleSet& p) {
  const int64_t count = int64_t(indexOfId_.size());
  for (size_t i = 0; i < p.size(); ++i)
    if (p.id[i] < count) indexOfId_[size_t(p.id[i])] = uint32_t(i);
}

void BodySystem::updateRestDensity(ParticleSet& p) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, indexOfId_.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t id = r.begin(); id != r.end(); ++id) {
      const size_t b = size_t(bodyOf_[id]);
      if (!telescopicBody_[b]) continue;
      const size_t i = indexOfId_[id];
      const float leng = telescopicLengthRatio(telescopicMeasure_[b], lengthRatio(springs_, p, indexOfId_, i));  // (8)-(9)
      lengthRatio_[id] = leng;
      p.restDensity[i] = leng * leng * leng * baseDensity_[id];  // (10), rho0 <- L^dens rho0
    }
  });
}

void BodySystem::addSpringForces(ParticleSet& p, float dt) {
  addSpringAccelerations(springs_, groups_, dt, p, indexOfId_, predicted_);
  // Chains' bending (serial: a few hundred particles at most, in a fixed order).
  for (const Bend& bend : bends_) {
    const size_t a = indexOfId_[size_t(bend.prev)], i = indexOfId_[size_t(bend.mid)], c = indexOfId_[size_t(bend.next)];
    const Eigen::Vector3f L(p.x[a] - 2.0f * p.x[i] + p.x[c], p.y[a] - 2.0f * p.y[i] + p.y[c],
                            p.z[a] - 2.0f * p.z[i] + p.z[c]);
    const Eigen::Vector3f f = bend.stiffness * L;
    p.ax[i] += f.x() / p.mass[i]; p.ay[i] += f.y() / p.mass[i]; p.az[i] += f.z() / p.mass[i];
    p.ax[a] -= 0.5f * f.x() / p.mass[a]; p.ay[a] -= 0.5f * f.y() / p.mass[a]; p.az[a] -= 0.5f * f.z() / p.mass[a];
    p.ax[c] -= 0.5f * f.x() / p.mass[c]; p.ay[c] -= 0.5f * f.y() / p.mass[c]; p.az[c] -= 0.5f * f.z() / p.mass[c];
  }
}

void BodySystem::addMuscleForces(ParticleSet& p, double t) {
  bool any = false;
  for (size_t m = 0; m < muscles_.size(); ++m) {
    muscleForces_[m] = muscles_[m].force.at(t);
    if (muscleForces_[m] != 0.0f && muscles_[m].ceilingBand > 0.0f) {
      // The depth reflex: the body's centroid height against gravity, in id order (deterministic).
      const Muscle& muscle = muscles_[m];
      double z = 0.0, v = 0.0;
      for (int64_t id = muscle.firstId; id < muscle.firstId + muscle.idCount; ++id) {
        const size_t i = indexOfId_[size_t(id)];
        z += double(p.x[i]) * up_.x() + double(p.y[i]) * up_.y() + double(p.z[i]) * up_.z();
        v += double(p.vx[i]) * up_.x() + double(p.vy[i]) * up_.y() + double(p.vz[i]) * up_.z();
      }
      const double n = double(std::max<int64_t>(1, muscle.idCount));
      muscleForces_[m] *= ceilingFactor(muscle.ceiling, muscle.ceilingBand, (z + double(muscle.ceilingLead) * v) / n);
    }
    any = any || muscleForces_[m] != 0.0f;
  }
  if (!any) return;
  for (size_t m = 0; m < muscles_.size(); ++m)
    if (weightPointers_[m] && muscleForces_[m] != 0.0f) updateRighting(p, m);
  addMuscleAccelerations(springs_, muscleForces_.data(), weightPointers_.data(), p, indexOfId_);
}

void BodySystem::updateRighting(const ParticleSet& p, size_t m) {
  // The body's axis: from the ring's centroid to the body's centroid (a bell's margin to its dome).
  const Muscle& muscle = muscles_[m];
  auto at = [&](int64_t id) {
    const size_t i = indexOfId_[size_t(id)];
    return Eigen::Vector3d(p.x[i], p.y[i], p.z[i]);
  };
  Eigen::Vector3d body = Eigen::Vector3d::Zero(), ring = Eigen::Vector3d::Zero();
  for (int64_t id = muscle.firstId; id < muscle.firstId + muscle.idCount; ++id) body += at(id);
  for (int64_t id : muscle.ring) ring += at(id);
  body /= double(muscle.idCount);
  ring /= double(muscle.ring.size());
  std::vector<float>& w = muscleWeights_[m];
  const Eigen::Vector3d axis = body - ring;
  if (!(axis.norm() > 0.0)) {
    for (int64_t id : muscle.ring) w[size_t(id)] = 1.0f;
    return;
  }
  const Eigen::Vector3d a = axis.normalized(), up = up_.cast<double>();
  double radius = 0.0;
  for (int64_t id : muscle.ring) {
    const Eigen::Vector3d d = at(id) - ring;
    radius += (d - d.dot(a) * a).norm();
  }
  radius /= double(muscle.ring.size());
  for (int64_t id : muscle.ring) {
    const Eigen::Vector3d d = at(id) - ring;
    const double h = radius > 0.0 ? (d - d.dot(a) * a).dot(up) / radius : 0.0;
    w[size_t(id)] = float(std::max(0.0, 1.0 - double(muscle.righting) * h));
  }
}

void BodySystem::applyPins(ParticleSet& p, double t) const {
  for (size_t k = 0; k < pinnedIds_.size(); ++k) {
    if (!(t < pinnedUntil_[size_t(pinnedIds_[k])])) continue;
    const size_t i = indexOfId_[size_t(pinnedIds_[k])];
    p.x[i] = pinnedAt_[k].x(); p.y[i] = pinnedAt_[k].y(); p.z[i] = pinnedAt_[k].z();
    p.vx[i] = p.vy[i] = p.vz[i] = 0.0f;
  }
}

void BodySystem::markUnsolved(const ParticleSet& p, double t, std::vector<uint8_t>& state) const {
  state.assign(p.size(), kSolved);
  if (telescopic_ || boundaryCoupled_)
    for (size_t id = 0; id < indexOfId_.size(); ++id) {
      const float leng = lengthRatio_[id];  // 1 for a body without telescopic density
      if (boundaryBody_[size_t(bodyOf_[id])]) state[indexOfId_[id]] = kBoundary;
      else if (leng * leng * leng < kTornDensityRatio) state[indexOfId_[id]] = kTorn;
    }
  for (size_t k = 0; k < pinnedIds_.size(); ++k)
    if (t < pinnedUntil_[size_t(pinnedIds_[k])]) state[indexOfId_[size_t(pinnedIds_[k])]] = kHeld;
}

void BodySystem::boundaryPatches(const ParticleSet& p, BoundaryBodies& out) const {
  const size_t n = p.size();
  out.sample.assign(n, 0);
  out.offsets.assign(n + 1, 0);
  out.patch.clear();
  out.share.assign(n, 0.0f);
  for (size_t id = 0; id < indexOfId_.size(); ++id)
    if (boundaryBody_[size_t(bodyOf_[id])]) out.sample[indexOfId_[id]] = 1;
  for (size_t i = 0; i < n; ++i) {  // by sorted index, so the solver gathers in a fixed order
    out.offsets[i] = uint32_t(out.patch.size());
    if (!out.sample[i]) continue;
    out.patch.push_back(uint32_t(i));
    double mass = p.mass[i];
    for (const SpringNetwork::End* e = springs_.begin(p.id[i]); e != springs_.end(p.id[i]); ++e) {
      const uint32_t q = indexOfId_[e->other];
      if (!out.sample[q]) continue;  // a chain's spring to another body: patches stay symmetric
      out.patch.push_back(q);
      mass += p.mass[q];
    }
    out.share[i] = float(p.mass[i] / mass);
  }
  out.offsets[n] = uint32_t(out.patch.size());
}

namespace {
constexpr int kCellBits = 21;
constexpr int64_t kCellBias = int64_t(1) << (kCellBits - 1);
uint64_t cellKey(int64_t cx, int64_t cy, int64_t cz) {
  const uint64_t mask = (uint64_t(1) << kCellBits) - 1;
  return (uint64_t(cx + kCellBias) & mask) << (2 * kCellBits) | (uint64_t(cy + kCellBias) & mask) << kCellBits |
         (uint64_t(cz + kCellBias) & mask);
}

// Calls f(id) for every body particle of `cells` whose cell is (cx, cy, cz) or one of its 26
// neighbours, by cell (z, then y, then x offset) and by id within a cell.
template <class F>
void forEachInNeighbourCells(const detail::BodyCellTable& cells, int64_t cx, int64_t cy, int64_t cz, F&& f) {
  if (cells.range.empty()) {  // bodies spread over too many cells for a table: binary searches
    for (int64_t dz = -1; dz <= 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const uint64_t key = cellKey(cx + dx, cy + dy, cz + dz);
          auto it = std::lower_bound(cells.order.begin(), cells.order.end(), std::make_pair(key, uint32_t(0)));
          for (; it != cells.order.end() && it->first == key; ++it) f(it->second);
        }
    return;
  }
  for (int64_t z = std::max(cz - 1, cells.z0); z <= std::min(cz + 1, cells.z0 + cells.nz - 1); ++z)
    for (int64_t y = std::max(cy - 1, cells.y0); y <= std::min(cy + 1, cells.y0 + cells.ny - 1); ++y)
      for (int64_t x = std::max(cx - 1, cells.x0); x <= std::min(cx + 1, cells.x0 + cells.nx - 1); ++x) {
        const auto [begin, end] = cells.range[size_t(((z - cells.z0) * cells.ny + (y - cells.y0)) * cells.nx + (x - cells.x0))];
        for (uint32_t k = begin; k < end; ++k) f(cells.order[k].second);
      }
}

// Pushes particles i and j apart along `normal` (from j to i) from distance r to `contact`,
// weighted by their inverse masses wi, wj (0 = does not move), and removes their approaching
// normal velocity: a fully inelastic penalty impulse.
void separate(ParticleSet& p, size_t i, size_t j, float wi, float wj, float contact, const Eigen::Vector3f& normal,
              float r) {
  const float push = (contact - r) / (wi + wj);
  p.x[i] += push * wi * normal.x(); p.y[i] += push * wi * normal.y(); p.z[i] += push * wi * normal.z();
  p.x[j] -= push * wj * normal.x(); p.y[j] -= push * wj * normal.y(); p.z[j] -= push * wj * normal.z();
  const float approach =
      (p.vx[i] - p.vx[j]) * normal.x() + (p.vy[i] - p.vy[j]) * normal.y() + (p.vz[i] - p.vz[j]) * normal.z();
  if (approach < 0.0f) {
    const float impulse = -approach / (wi + wj);
    p.vx[i] += impulse * wi * normal.x(); p.vy[i] += impulse * wi * normal.y(); p.vz[i] += impulse * wi * normal.z();
    p.vx[j] -= impulse * wj * normal.x(); p.vy[j] -= impulse * wj * normal.y(); p.vz[j] -= impulse * wj * normal.z();
  }
}

}  // namespace

// One Gauss-Seidel pass over all body particles: every pair closer than its collision diameter
// (d_i + d_j) / 2 with d_i = d0 / L_i^leng, not joined by a spring, is pushed apart to exactly
// that distance (mass-weighted; pinned particles do not move) and its approaching normal velocity
// removed (a fully inelastic penalty impulse). Candidates come from the particle's own and the 26
// adjacent cells of a grid whose cell is the largest diameter. Returns the pairs resolved.
int BodySystem::collisionPass(ParticleSet& p, double t) {
  const size_t count = indexOfId_.size();
  float cell = 0.0f;
  for (size_t id = 0; id < count; ++id) cell = std::max(cell, diameter_[id] / lengthRatio_[id]);
  cell *= std::max(1.0f, fluidContact_ * maxContactScale_);
  if (!(cell > 0.0f)) return 0;
  auto cellOf = [&](size_t i, int axis) {
    const float v = axis == 0 ? p.x[i] : axis == 1 ? p.y[i] : p.z[i];
    return int64_t(std::floor(v / cell));
  };
  detail::BodyCellTable& table = cells_;
  table.order.resize(count);
  Eigen::Array<int64_t, 3, 1> lo = Eigen::Array<int64_t, 3, 1>::Constant(std::numeric_limits<int64_t>::max()), hi = -lo;
  for (size_t id = 0; id < count; ++id) {
    const size_t i = indexOfId_[id];
    // A non-finite position has no cell (its cast is undefined): the pass leaves it, and the
    // step's finite check stops the run with an error naming the time.
    if (!std::isfinite(p.x[i]) || !std::isfinite(p.y[i]) || !std::isfinite(p.z[i])) return 0;
    const Eigen::Array<int64_t, 3, 1> c(cellOf(i, 0), cellOf(i, 1), cellOf(i, 2));
    lo = lo.min(c);
    hi = hi.max(c);
    table.order[id] = {cellKey(c.x(), c.y(), c.z()), uint32_t(id)};
  }
  std::sort(table.order.begin(), table.order.end());
  const Eigen::Array<int64_t, 3, 1> n = hi - lo + 1;
  table.range.clear();
  if (count > 0 && double(n.x()) * double(n.y()) * double(n.z()) <= double(64 * count + 65536)) {
    table.x0 = lo.x(), table.y0 = lo.y(), table.z0 = lo.z();
    table.nx = n.x(), table.ny = n.y(), table.nz = n.z();
    table.range.assign(size_t(n.prod()), {0u, 0u});
    for (uint32_t k = 0; k < uint32_t(count);) {
      uint32_t end = k + 1;
      while (end < count && table.order[end].first == table.order[k].first) ++end;
      const size_t i = indexOfId_[table.order[k].second];
      table.range[size_t(((cellOf(i, 2) - lo.z()) * n.y() + (cellOf(i, 1) - lo.y())) * n.x() + (cellOf(i, 0) - lo.x()))] = {k, end};
      k = end;
    }
  }
  int resolved = 0;
  for (size_t n = 0; n < count; ++n) {
    const uint32_t a = table.order[n].second;
    const size_t i = indexOfId_[a];
    forEachInNeighbourCells(table, cellOf(i, 0), cellOf(i, 1), cellOf(i, 2), [&](uint32_t b) {
      if (b <= a) return;
      const size_t j = indexOfId_[b];
      const float contact = 0.5f * (diameter_[a] / lengthRatio_[a] + diameter_[b] / lengthRatio_[b]);
      Eigen::Vector3f d(p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]);
      const float r = d.norm();
      if (r >= contact * (1.0f - 1e-4f) || springs_.connected(a, b)) return;
      const float wi = t < pinnedUntil_[a] ? 0.0f : 1.0f / p.mass[i];
      const float wj = t < pinnedUntil_[b] ? 0.0f : 1.0f / p.mass[j];
      if (wi + wj <= 0.0f) return;
      separate(p, i, j, wi, wj, contact, r > 0.0f ? Eigen::Vector3f(d / r) : Eigen::Vector3f::UnitX(), r);  // i above j in id
      ++resolved;
    });
  }
  if (fluidContact_ > 0.0f) resolved += fluidPass(p, t, cell);
  return resolved;
}

// Fluid against bodies, with the grid of the body pass (cells_): every fluid particle
// closer than fluidContact d_j / L_j to body particle j is pushed out to that distance and its
// approach removed, mass-weighted as between body particles.
int BodySystem::fluidPass(ParticleSet& p, double t, float cell) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const auto& [key, id] : cells_.order) {
    const size_t j = indexOfId_[id];
    lo = lo.cwiseMin(Eigen::Vector3f(p.x[j], p.y[j], p.z[j]));
    hi = hi.cwiseMax(Eigen::Vector3f(p.x[j], p.y[j], p.z[j]));
  }
  lo.array() -= cell;
  hi.array() += cell;
  const auto cellOf = [cell](float v) { return int64_t(std::floor(v / cell)); };
  int resolved = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != 0 || p.x[i] < lo.x() || p.y[i] < lo.y() || p.z[i] < lo.z() || p.x[i] > hi.x() ||
        p.y[i] > hi.y() || p.z[i] > hi.z())
      continue;
    forEachInNeighbourCells(cells_, cellOf(p.x[i]), cellOf(p.y[i]), cellOf(p.z[i]), [&](uint32_t b) {
      const size_t j = indexOfId_[b];
      const float contact = fluidContact_ * contactScale_[b] * diameter_[b] / lengthRatio_[b];
      Eigen::Vector3f d(p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]);
      const float r = d.norm();
      if (r >= contact * (1.0f - 1e-4f)) return;
      const float wi = 1.0f / p.mass[i];
      const float wj = t < pinnedUntil_[b] ? 0.0f : 1.0f / p.mass[j];
      separate(p, i, j, wi, wj, contact, r > 0.0f ? Eigen::Vector3f(d / r) : Eigen::Vector3f::UnitZ(), r);
      ++resolved;
    });
  }
  return resolved;
}

void BodySystem::collide(ParticleSet& p, int maxPasses, double t) {
  int passes = 0;
  int found = 0;
  do {
    found = collisionPass(p, t);
    ++passes;
    stats_.collisionsResolved += uint64_t(found);
  } while (found > 0 && passes < maxPasses);
  stats_.collisionPasses += uint64_t(passes);
  stats_.mostPasses = std::max(stats_.mostPasses, passes);
  if (found > 0) ++stats_.capHits;
}

void BodySystem::saveState(StateWriter& out) const {
  out.array(lengthRatio_);
  for (const std::vector<float>& w : muscleWeights_) out.array(w);
  out.value(stats_);
}

void BodySystem::restoreState(StateReader& in) {
  in.arrayOf(lengthRatio_, lengthRatio_.size());
  for (std::vector<float>& w : muscleWeights_) in.arrayOf(w, w.size());
  stats_ = in.value<BodyStats>();
}

}  // namespace kurage::sim
