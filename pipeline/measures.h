// Error measures against references, shared by the studies (pipeline/study.h) and the tests:
// the dam break against Martin & Moyce (1952), Archimedes' submerged fraction, fluid tunnelling
// through a membrane, a still tank's free surface and pressure, the distance of a metaball level
// set from the exact metaball surface, and the RMSE between two images. Each takes particles or
// images as they are; none runs anything.
//
// Units: metres and seconds unless a name says otherwise; dimensionless series are Martin &
// Moyce's (front Z = x / a against T = t sqrt(2 g / a), residual height H = h / (2a) against
// tau = t sqrt(g / a)).
#pragma once

#include "render/image.h"
#include "render/surfacing.h"
#include "sim/params.h"
#include "sim/particles.h"

#include <Eigen/Core>

#include <filesystem>
#include <map>
#include <vector>

namespace kurage::pipeline {

struct SeriesPoint {
  double x = 0.0, y = 0.0;
};

// y at x, linear between the points (sorted by x), the end values outside them.
double interpolateSeries(const std::vector<SeriesPoint>& series, double x);

struct SeriesError {
  double meanRelative = 0.0;  // mean of |measured(x) - y| / y over the reference points used
  int points = 0;             // reference points inside the measured range of x
};
// Compares `measured` (sorted by x) with each reference point whose x lies within the measured
// range; points beyond it (a run shorter than the experiment) are left out and not counted.
SeriesError meanRelativeError(const std::vector<SeriesPoint>& measured, const std::vector<SeriesPoint>& reference);

// ---- Dam break: Martin & Moyce (1952) ----

// The two series of tests/data/martin_moyce_1952.csv (a copy of ../shared/data/).
struct MartinMoyce {
  std::vector<SeriesPoint> surgeFront;    // (T, Z)
  std::vector<SeriesPoint> columnHeight;  // (tau, H)
};
// Throws std::runtime_error naming the path if the file is missing or malformed.
MartinMoyce loadMartinMoyce(const std::filesystem::path& csv);

// A column of width a (along x from the back wall at origin.x) and initial height `height`
// standing on the floor z = origin.z, collapsing along +x under gravity g.
struct DamBreakGeometry {
  double width = 0.0;    // a, m
  double height = 0.0;   // initial column height (2a in Martin & Moyce), m
  double gravity = 0.0;  // |g|, m/s^2
  double spacing = 0.0;  // fluid particle spacing l, m
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // back wall x, floor z
};

// Samples the surge front and the residual column height of the fluid (kind 0) over time, as
// tests/test_dam_break.cpp and docs/VALIDATION.md define them: the front is the 99.8th
// percentile of x over particles below z = a / 4 (robust to isolated spray), plus half a
// spacing; the column height is the highest particle within two spacings of the back wall that has
// at least three other fluid particles within two spacings (not spray), plus half a spacing (0 when
// the band holds only spray). Both series start at (0, 1).
class DamBreakTrack {
public:
  explicit DamBreakTrack(const DamBreakGeometry& geometry);
  void record(const sim::ParticleSet& particles, double time);
  const std::vector<SeriesPoint>& front() const { return front_; }    // (T, Z)
  const std::vector<SeriesPoint>& column() const { return column_; }  // (tau, H)
  // tau = t sqrt(g / a) for a time in seconds, and back.
  double tau(double time) const;
  double timeAtTau(double tau) const;

private:
  DamBreakGeometry g_;
  std::vector<SeriesPoint> front_, column_;
  std::vector<float> xs_;
  std::vector<std::pair<float, size_t>> band_;  // (z, index) of the particles by the back wall
  static constexpr int kColumnNeighbours = 3;   // fewer within two spacings: spray, not the column
};

// ---- Bodies ----

// Extent of the particles of one kind (k >= 1: body k - 1).
struct KindExtent {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(1e30f), max = Eigen::Vector3f::Constant(-1e30f);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  size_t count = 0;
};
KindExtent kindExtent(const sim::ParticleSet& particles, int kind);

// The free surface of the fluid away from a body: over columns `cellSize` wide (cells of the x-y
// grid anchored at 0) whose centre lies farther than `clear` from (cx, cy) horizontally, the mean
// height of the top fluid particle, plus half a fluid spacing. 0 when no column qualifies.
double freeSurfaceHeight(const sim::ParticleSet& particles, double cx, double cy, double clear, float cellSize,
                         float spacing);

// Archimedes: the share of body `kind`'s particles whose centre lies below the free surface, the
// surface measured clear of the body by its horizontal half extent plus 1.5 spacings.
double submergedFraction(const sim::ParticleSet& particles, int kind, float fluidSpacing);

// Fluid particles that have tunnelled through a membrane: those more than half a fluid spacing
// below the membrane's lowest particle (its centre).
struct MembraneLeak {
  size_t fluid = 0;   // fluid particles in the scene
  size_t leaked = 0;  // of which below the membrane
};
MembraneLeak membraneLeak(const sim::ParticleSet& particles, int kind, float fluidSpacing);

// Who carries the poured fluid's weight (docs/PHYSICS.md, "Why the membrane's contrast is
// WCSPH's"): the 90th percentile of the pressure of the membrane's particles that have a fluid
// particle within 0.7 h, and the median pressure of the fluid particles within h of the membrane
// (Pa; 0 where there are none). Brute force over fluid x membrane pairs: for the small scenes
// that pour fluid onto a membrane.
struct MembraneLoad {
  double sheetPressure90 = 0;  // the loaded sheet's pressure, 90th percentile
  double fluidPressure50 = 0;  // the fluid's pressure against the sheet, median
  size_t sheetParticles = 0, fluidParticles = 0;  // how many each figure is over
};
MembraneLoad membraneLoad(const sim::ParticleSet& particles, int kind, float supportRadius);

// ---- A still tank ----

// Samples a tank of fluid (kind 0) filled to `filledHeight` above the container's floor, meant to
// stand still (tests/test_dfsph.cpp's HydrostaticTank, the hydrostatic_tank study):
// - the free surface: the height at which the colour field of the interior's particles (clear of
//   the side walls by h), averaged over the interior's floor area, is one half:
//   c(z) = sum_j (m_j / rho0) Wbar(z - z_j) / area, Wbar the cubic spline of support h integrated
//   over a horizontal plane. The water's volume per floor area, read where it ends: on a lattice
//   at h = 2 l exactly its top layer plus half a spacing (0.454 l at h = 1.5 l), and unchanged
//   when the particles move sideways,
//   so a disordered top layer reads where its water is. (The mean over columns one spacing wide of
//   the top particle, used before, read such a layer low: a column that its top layer's particles
//   have left reads a layer down, tests/test_study.cpp);
// - each interior slab's pressure over rho0 g (depth): slabs two spacings thick, wholly inside
//   [2h, H - 2h] above the floor, clear of the side walls by h, their depth measured from the
//   sample's free surface and, apart, from the filled height H. Two spacings, because the
//   symmetric pressure force on a lattice layer k reads differences p_{k+m} - p_{k-m} of layers
//   as far above as below, which have the same parity: a pressure alternating from layer to
//   layer pushes nothing, so the solves do not correct it (in the bulk), and a slab one spacing
//   thick reads it (a calm DFSPH tank's top layers alternate by +-1-2 %, docs/PHYSICS.md "Slabs
//   two spacings thick"). A slab of two layers holds one of each and reads the pressure that
//   acts. The one-spacing layers are kept apart (worstLayer; the slabs are aligned to the floor,
//   so at h = 1.5 l they start at 4 l and the layers at 3 l, and a layer may lie in no slab);
// - each slab's mean pressure against the mean weight of the water above its particles: for each,
//   m g over the interior's floor area for each interior particle above it (the columns clear of
//   the side walls by h, half-open: [lo + h, hi - h)), one within half a spacing of it counting the
//   fraction of a spacing-thick layer that lies above it: exact on a lattice whose extent is a
//   multiple of the spacing, unbiased on a disordered packing. It reads 1 when the pressure carries the water
//   that is there, wherever the surface stands and however close the water has packed.
// Each record adds one sample; the slabs' ratios are averaged over every sample.
class HydrostaticTrack {
public:
  HydrostaticTrack(const sim::SimParams& params, double filledHeight);
  void record(const sim::ParticleSet& particles);
  // Free surface of one sample, m above the container's floor (0 when no column qualifies).
  double freeSurface(const sim::ParticleSet& particles) const;
  int samples() const { return samples_; }
  int slabs() const { return int(slabs_.size()); }
  // |mean free surface - H| / H over the samples.
  double surfaceError() const;
  // The largest |mean of p / (rho0 g depth) - 1| over the slabs, depth below each sample's free
  // surface; and below the filled height.
  double worstSlab() const { return worst(slabs_); }
  double worstSlabBelowFilled() const { return worst(filled_); }
  // The same as worstSlab over layers one spacing thick, which a pressure alternating from layer
  // to layer (the force's blind spot, above) moves.
  double worstLayer() const { return worst(layers_); }
  // The largest |mean pressure / mean weight of the water above - 1| over the slabs.
  double worstSlabAgainstWeight() const;

private:
  struct Slab {
    double sum = 0.0;
    long count = 0;
  };
  static double worst(const std::map<int, Slab>& slabs);
  // A fluid particle clear of the side walls by h.
  bool interior(const sim::ParticleSet& p, size_t i) const;
  float l_, h_;  // spacing and support radius, m
  Eigen::Vector3f lo_, hi_;
  double rho0_, rho0g_, g_;
  double area_;  // the interior's floor area, clear of the side walls by h
  double filledHeight_ = 0.0, surfaceSum_ = 0.0;
  int samples_ = 0;
  std::map<int, Slab> slabs_, filled_, layers_;
  struct Carried {
    double pressure = 0.0, weight = 0.0;  // sums over the slab's particles and samples
  };
  std::map<int, Carried> carried_;
  // The interior's particles as (height above the floor, mass), sorted by height.
  void sortInterior(const sim::ParticleSet& p, std::vector<std::pair<float, float>>& out) const;
  // The free surface (header) of the interior's particles so sorted.
  double surfaceOf(const std::vector<std::pair<float, float>>& column) const;
  // record's scratch: the interior particles (sortInterior), and the sums from the top of m g
  // and m g z
  std::vector<std::pair<float, float>> interiorZ_;
  std::vector<double> weightAbove_, momentAbove_;
  // The weight of the interior water above height z (header), per unit floor area.
  double weightAbove(float z) const;
};

// RMS speed of the particles of one kind (0 = fluid), m/s; 0 when there are none.
double rmsSpeed(const sim::ParticleSet& particles, int kind);

// ---- Jellyfish (a shell body: the bell) ----

// The smallest distance between two segments of a chain (an oral arm: body `kind`'s particles
// in id order) that share no particle: a chain that crosses or knots itself brings two such
// segments within a particle spacing. Infinity for fewer than four particles.
double chainSelfApproach(const sim::ParticleSet& particles, int kind);

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

// ---- Surfacing ----

// The exact metaball field f(x) = sum s (1 - (|x - x_i| / R)^2)^2 of render/surfacing.h,
// summed over all particles within R (a bucket grid of cell R).
class MetaballField {
public:
  MetaballField(std::vector<Eigen::Vector3f> points, const render::MetaballParams& params);
  double operator()(const Eigen::Vector3d& x) const;
  const Eigen::Vector3d& centroid() const { return centroid_; }
  double reach() const { return reach_; }  // max distance of a particle from the centroid, plus R

private:
  std::vector<Eigen::Vector3f> points_;
  render::MetaballParams params_;
  Eigen::Vector3d centroid_ = Eigen::Vector3d::Zero();
  double reach_ = 0.0;
  Eigen::Vector3i cells_ = Eigen::Vector3i::Zero();
  Eigen::Vector3d lower_ = Eigen::Vector3d::Zero();
  std::vector<uint32_t> cellStart_, cellPoints_;
};

// Distance of a level set's zero crossing from the exact surface f = T, along `rays` rays from
// the particles' centroid in directions spread evenly over the sphere (a Fibonacci lattice):
// on each ray, the outermost crossing of each (marched inwards from outside in steps of a tenth
// of min(R, voxel), then bisected to 1e-6 of the voxel). The particle arrangement must be
// star-shaped about its centroid for the distance along a ray to be the distance to the surface
// (a lattice block or ball is); rays that miss one of the surfaces count as failures.
struct SurfaceDistance {
  double mean = 0.0;  // m
  double max = 0.0;   // m
  double rms = 0.0;   // m
  int rays = 0;       // rays that found both crossings
  int misses = 0;     // rays where only one surface was found
};
SurfaceDistance surfaceDistance(const render::LevelSet& levelSet, const MetaballField& field,
                                const render::MetaballParams& params, int rays);

// ---- Images ----

// Root mean square difference of the RGB channels in sRGB-encoded values (clamped to [0, 1], as
// PNG stores them), over every pixel. Throws std::invalid_argument when the sizes differ.
double imageRmse(const render::Image& actual, const render::Image& reference);

}  // namespace kurage::pipeline
