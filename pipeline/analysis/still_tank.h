// A still tank's free surface and hydrostatic pressure, sampled from its particles: how well a
// pressure solver carries water at rest (p = rho0 g depth). Metres, seconds, pascals.
#pragma once

#include "sim/params.h"
#include "sim/particles.h"

#include <Eigen/Core>

#include <map>
#include <utility>
#include <vector>

namespace kurage::pipeline {

// Samples a tank of fluid (kind 0) filled to `filledHeight` above the container's floor, meant to
// stand still (tests/test_dfsph.cpp's HydrostaticTank, the hydrostatic_tank study):
// - the free surface: the height at which the colour field of the interior's particles (clear of
//   the side walls by h), averaged over the interior's floor area, is one half:
//   c(z) = sum_j (m_j / rho0) Wbar(z - z_j) / area, Wbar the cubic spline of support h integrated
//   over a horizontal plane. The water's volume per floor area, read where it ends: on a lattice
//   at h = 2 l exactly its top layer plus half a spacing (0.454 l at h = 1.5 l), and unchanged
//   when the particles move sideways, so a disordered top layer reads where its water is (the
//   top particle of each column would read a layer low where a column's top particle has left);
// - each interior slab's pressure over rho0 g (depth): slabs two spacings thick, wholly inside
//   [2h, H - 2h] above the floor, clear of the side walls by h, their depth measured from the
//   sample's free surface and, apart, from the filled height H. Two spacings, because the
//   symmetric pressure force on a lattice layer k reads differences p_{k+m} - p_{k-m} of layers
//   as far above as below, which have the same parity: a pressure alternating from layer to
//   layer pushes nothing, so the solves do not correct it (in the bulk), and a slab one spacing
//   thick reads it (a calm DFSPH tank's top layers alternate by +-1-2 %, docs/design/physics.md "Slabs
//   two spacings thick"). A slab of two layers holds one of each and reads the pressure that
//   acts. The one-spacing layers are kept apart (worstLayer; the slabs are aligned to the floor,
//   so at h = 1.5 l they start at 4 l and the layers at 3 l, and a layer may lie in no slab);
// - each slab's mean pressure against the mean weight of the water above its particles: for each,
//   m g over the interior's floor area for each interior particle above it (the columns clear of
//   the side walls by h, half-open: [lo + h, hi - h)), one within half a spacing of it counting the
//   fraction of a spacing-thick layer that lies above it: exact on a lattice whose extent is a
//   multiple of the spacing, unbiased on a disordered packing. It reads 1 when the pressure
//   carries the water that is there, wherever the surface stands and however close it has packed.
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

// The water's level: the free surface as HydrostaticTrack reads it, of every fluid particle over
// the container's whole floor (the water's volume per floor area, read where it ends; what a pour
// raises by its volume over the floor area), m above the container's floor.
double waterLevel(const sim::SimParams& params, const sim::ParticleSet& particles);

// What bodies take of the water's level (ours): the volume near the body particles that holds no
// water, over the container's floor area, m. Near: weighted by the clearance c of a point, its
// least distance beyond a body particle's fluid-contact distance as built (collisions.fluid_contact
// x fluid_contact_scale x its body's spacing; 0 without contact), w = 1 for c <= l, falling
// linearly to 0 at c = 2 h; sampled at the centres of cells of l/2 from the container's corner,
// within the container and up to `level` above its floor. The result is sum_cells w V_cell less
// sum_fluid w(its cell) m / rho0, over the floor area: the bodies' own volume, the layer their fluid
// contact keeps clear and any void their motion leaves in the water (a jellyfish's bell reopening
// its margin), but not the packing of the water farther out, which the taper (1.5 m in the jellyfish)
// averages over the layers that water forms next to a wall. waterLevel less this is the level of the water alone.
// 0 without body particles. Cost: about (2 (c_b + 2 h) / l)^3 cells a body particle.
double bodiesDisplacement(const sim::SimParams& params, const sim::ParticleSet& particles, double level);

}  // namespace kurage::pipeline
