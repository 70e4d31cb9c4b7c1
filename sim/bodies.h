// The telescopic deformable bodies of a simulation (SPEC §3): their springs, stretch-following
// rest density, muscles, pins and collisions. A Simulation holds one only when its scene has
// bodies, so a fluid-only scene allocates no spring data and runs none of these stages.
//
// Body particles get the ids 0 .. count-1 (before any fluid particle), so per-body data is
// indexed by id; `index()` maps ids to the current (cell-sorted) positions after every sort.
#pragma once

#include "sim/body_shapes.h"
#include "sim/params.h"
#include "sim/particles.h"
#include "sim/springs.h"
#include "sim/state.h"

#include <cstdint>
#include <string>
#include <vector>

namespace kurage::sim {

struct BoundaryBodies;  // sim/solvers/pressure_solver.h

// A scene error in bodies[body]: `field` is the key below it ("" for the body itself).
struct BodyProblem {
  size_t body = 0;
  std::string field;
  std::string message;
};

// Checks every body before any work: a shape that yields no particle, a connection radius that
// joins no spring or leaves particles unconnected, a body outside the container or overlapping
// another body, a pin or muscle that selects nothing, a chain hung from a missing body.
std::vector<BodyProblem> checkBodies(const SimParams& params);

struct BodyStats {
  uint64_t collisionPasses = 0;     // passes of the collision loop, all steps
  uint64_t collisionsResolved = 0;  // pairs pushed apart
  uint64_t capHits = 0;             // steps whose loop stopped at the cap with collisions left
  int mostPasses = 0;               // most passes in one step
};

namespace detail {
// The collision grid: the body particles as (cell key, id) sorted, and over the box of cells they
// occupy a dense table of each cell's [begin, end) in that order (empty when the box is too large
// for one: then cells are found by binary search).
struct BodyCellTable {
  std::vector<std::pair<uint64_t, uint32_t>> order;
  std::vector<std::pair<uint32_t, uint32_t>> range;
  int64_t x0 = 0, y0 = 0, z0 = 0, nx = 0, ny = 0, nz = 0;
};
}  // namespace detail

class BodySystem {
public:
  // Appends the bodies' particles to `particles` with ids nextId, nextId + 1, ... (nextId must be
  // 0: body ids come first) and builds their springs. Throws std::invalid_argument for bodies
  // that checkBodies() refuses.
  BodySystem(const SimParams& params, ParticleSet& particles, int64_t& nextId);

  size_t particleCount() const { return pinnedUntil_.size(); }
  size_t springCount() const { return springs_.springCount(); }
  // A body's particle mass and rest density at its specific_gravity (its parts scale both).
  float particleMass(size_t body) const { return mass_[body]; }
  float restDensity(size_t body) const { return restDensity_[body]; }
  // Rest density of the particle with this id as built (its part's, else its body's), kg/m^3.
  float initialRestDensity(int64_t id) const { return baseDensity_[size_t(id)]; }
  // Specific gravity averaged over the body's particles, parts included.
  float meanSpecificGravity(size_t body) const { return meanGravity_[body]; }
  // The step bound of the stiffest spring: min_i min(sqrt(2 m_i / K_i), m_i / D_i) with K_i, D_i
  // the sums of k and d over particle i's springs (explicit spring and damper stability).
  float springStep() const { return springStep_; }
  bool hasTelescopicDensity() const { return telescopic_; }
  bool hasMuscles() const { return !muscles_.empty(); }
  // Force per spring of muscle m (scene order over all bodies) as last applied: its curve at the
  // step's time times its depth reflex's factor (0 before the first step), N.
  float appliedMuscleForce(size_t m) const { return m < muscleForces_.size() ? muscleForces_[m] : 0.0f; }
  // Pinned particles or bodies held until a time (hold_until).
  bool hasPins() const { return !pinnedIds_.empty(); }
  const BodyStats& stats() const { return stats_; }
  // What the bodies carry from step to step (stretch ratios, righting weights, statistics), for
  // checkpoints; the springs, pins and muscles are rebuilt from the scene.
  void saveState(StateWriter& out) const;
  void restoreState(StateReader& in);
  size_t memoryBytes() const;

  // Maps ids to sorted positions; call after every re-sort.
  void index(const ParticleSet& particles);
  // (8)-(10): rho0_i = (L_i^leng)^3 rho0_i(t = 0) for the bodies with telescopic density, L^leng
  // under each body's measure (telescopicLengthRatio).
  void updateRestDensity(ParticleSet& particles);
  // (7) spring-damper forces for a step of dt.
  void addSpringForces(ParticleSet& particles, float dt);
  // Muscle forces at time t.
  void addMuscleForces(ParticleSet& particles, double t);
  // Holds pinned particles at their initial positions, at rest; a held body's particles while
  // t < hold_until.
  void applyPins(ParticleSet& particles, double t) const;
  // Per particle (resized to the particle count): kHeld for the particles applyPins holds at time
  // t, kBoundary for the other particles of a body coupled as the fluid's boundary, kTorn for those
  // of a telescopic body whose rest density (10) has fallen below kTornDensityRatio of their
  // initial one, kSolved for every other. A solver that solves for the bodies' density leaves all
  // three out (sim/solvers/dfsph/dfsph.h). After updateRestDensity.
  void markUnsolved(const ParticleSet& particles, double t, std::vector<uint8_t>& state) const;
  bool mayLeaveParticlesUnsolved() const { return hasPins() || telescopic_ || boundaryCoupled_; }
  // A body with BodyCoupling::Boundary.
  bool hasBoundaryBodies() const { return boundaryCoupled_; }
  // The particles of the bodies coupled as the fluid's boundary and each one's patch: itself and
  // its spring neighbours, with its share m_i / (the patch's mass) (sim/solvers/dfsph/dfsph.h). After
  // index().
  void boundaryPatches(const ParticleSet& particles, BoundaryBodies& out) const;
  // L^dens below which a telescopic body particle counts as torn, stretched past what a solver of
  // its density can hold: (8)'s mean r0/|r| over its springs below 0.63, 1.6 times in every
  // direction for a uniform stretch. In membrane.json's sheet its own kernel's share of its density,
  // m W(0), is then above a third of its rest density (a tenth unstretched). The ratio holds that
  // sheet under DFSPH from 1/5 to 1/3, not at 1/8 (docs/notebook/code-history-sim.md).
  static constexpr float kTornDensityRatio = 0.25f;
  // (14) The collision loop between body particles not joined by a spring (SPEC §3.4); particles
  // pinned at time t do not move.
  void collide(ParticleSet& particles, int maxPasses, double t);

private:
  struct Muscle {
    ForceCurve force;
    float righting = 0.0f;
    float ceiling = 0.0f, ceilingBand = 0.0f, ceilingLead = 0.0f;
    int64_t firstId = 0, idCount = 0;  // its body's ids
    std::vector<int64_t> ring;          // ids of the particles its springs join
  };
  void updateRighting(const ParticleSet& particles, size_t muscle);
  int collisionPass(ParticleSet& particles, double t);

  std::vector<float> mass_, restDensity_, meanGravity_;  // per body
  std::vector<float> particleMass_, baseDensity_;       // per id: m_i and rho0_i before (10)
  std::vector<uint8_t> telescopicBody_;    // per body
  std::vector<uint8_t> boundaryBody_;      // per body: BodyCoupling::Boundary
  std::vector<TelescopicMeasure> telescopicMeasure_;  // per body
  std::vector<SpringGroup> groups_;        // per body
  SpringNetwork springs_;
  std::vector<Muscle> muscles_;
  struct Bend {
    int64_t prev, mid, next;  // ids of three consecutive chain particles
    float stiffness;          // k_b, N/m
  };
  std::vector<Bend> bends_;
  std::vector<float> muscleForces_;
  std::vector<std::vector<float>> muscleWeights_;  // per muscle: per id (righting muscles only)
  std::vector<const float*> weightPointers_;       // per muscle: muscleWeights_ data or null
  Eigen::Vector3f up_{0, 0, 1};                     // against gravity
  std::vector<int32_t> bodyOf_;            // per id
  std::vector<float> diameter_;            // per id: d0 of its body
  std::vector<float> contactScale_;        // per id: its body's fluid_contact_scale
  float maxContactScale_ = 0.0f;           // the largest of contactScale_ (sizes the collision grid)
  std::vector<float> lengthRatio_;         // per id: L^leng (1 without telescopic density)
  std::vector<float> pinnedUntil_;         // per id: 0 free, +inf pinned, else held until then
  std::vector<int64_t> pinnedIds_;
  std::vector<Eigen::Vector3f> pinnedAt_;
  std::vector<uint32_t> indexOfId_;
  std::vector<Eigen::Vector3f> predicted_;  // scratch of the implicit dampers
  detail::BodyCellTable cells_;  // collision grid scratch
  int fluidPass(ParticleSet& particles, double t, float cell);
  bool telescopic_ = false;
  bool boundaryCoupled_ = false;
  float fluidContact_ = 0.0f;  // CollisionParams::fluidContact
  float springStep_ = 0.0f;
  BodyStats stats_;
};

}  // namespace kurage::sim
