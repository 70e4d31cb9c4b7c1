// The bell of a jellyfish (a shell body, sim/body_shapes.h) followed by particle id from the
// shape it was built in: its margin, tilt, shape, wall layers and the fluid caught inside its
// wall. Metres and degrees.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace kurage::pipeline {

// The bell's particles as built (t = 0), tracked by id: the wall layer of each (0 = innermost,
// from its distance to the shell's centre) and the margin (the last ring of latitude of every
// layer, polar angle within a quarter spacing of the opening angle).
class ShellWall {
public:
  // `initial`: the particles at t = 0; `kind` = the shell's body index + 1.
  ShellWall(const sim::BodyParams& shell, int kind, const sim::ParticleSet& initial, float fluidSpacing);
  int kind() const { return kind_; }
  // Mean distance of the margin particles from their centroid (the ring's radius, whatever the
  // bell's tilt), m.
  double marginRadius(const sim::ParticleSet& particles) const;
  // Fluid particles inside the wall: those with a particle of the innermost layer and one of the
  // outermost layer within one body spacing, on opposite sides of it (the two offsets make an
  // obtuse angle). The layers are one body spacing apart, so a fluid particle squeezed between
  // them is found; one outside the wall, even at the margin where both layers end, is not.
  size_t fluidInsideWall(const sim::ParticleSet& particles) const;
  // Angle between the shell's axis as built and the direction from the margin's centroid to the
  // bell's centre of mass, degrees: 0 upright as built, 180 upside down.
  double tiltDegrees(const sim::ParticleSet& particles) const;
  // The same angle from another direction (from the vertical, for a bell built tilted).
  double tiltDegrees(const sim::ParticleSet& particles, const Eigen::Vector3d& reference) const;
  // Centre of mass of the bell (its parts may be heavier), m.
  Eigen::Vector3d centre(const sim::ParticleSet& particles) const;
  // Height of the bell's highest particle (its apex when upright), m.
  double apexHeight(const sim::ParticleSet& particles) const;
  // The bell's shape along its own current axis (from the margin's centroid to the centre of
  // mass): height, the extent of its particles along the axis; diameter, twice the largest
  // distance of a particle from the axis (the outer layer's margin on a bell at rest), m.
  struct Shape {
    double height = 0.0, diameter = 0.0;
  };
  Shape shape(const sim::ParticleSet& particles) const;
  // The closest approach of two bell particles that were farther apart than `joinedWithin` as
  // built (so no spring joins them: pass the body's connection radius in metres), m. A shell
  // that folds through itself brings such a pair within a body spacing.
  double closestUnjoinedPair(const sim::ParticleSet& particles, double joinedWithin) const;

private:
  std::vector<Eigen::Vector3d> built_;  // positions as built, by position in sortedIds_
  int kind_ = 1;
  int layers_ = 1;
  float spacing_ = 0.5f;  // body spacing, m
  Eigen::Vector3d axis_ = Eigen::Vector3d::UnitZ();
  std::vector<int64_t> sortedIds_;  // of the bell's particles, sorted
  std::vector<int8_t> layer_;       // by position in sortedIds_
  std::vector<uint8_t> margin_;     // idem
  int indexOf(int64_t id) const;    // -1 if not a bell particle
};

}  // namespace kurage::pipeline
