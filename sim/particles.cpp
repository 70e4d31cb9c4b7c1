#include "sim/particles.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace kurage::sim {

namespace {
template <class T>
void gather(std::vector<T>& array, const std::vector<uint32_t>& order, std::vector<T>& scratch) {
  scratch.resize(array.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 16384), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) scratch[k] = array[order[k]];
  });
  array.swap(scratch);
}

template <class T>
void compact(std::vector<T>& array, const std::vector<uint8_t>& flags) {
  size_t out = 0;
  for (size_t i = 0; i < array.size(); ++i)
    if (!flags[i]) array[out++] = array[i];
  array.resize(out);
}

// Applies f to every array of a ParticleSet together with the matching array of another.
template <class F>
void forEachArray(ParticleSet& a, ParticleSet& b, F&& f) {
  f(a.x, b.x); f(a.y, b.y); f(a.z, b.z);
  f(a.vx, b.vx); f(a.vy, b.vy); f(a.vz, b.vz);
  f(a.ax, b.ax); f(a.ay, b.ay); f(a.az, b.az);
  f(a.density, b.density); f(a.pressure, b.pressure); f(a.restDensity, b.restDensity); f(a.mass, b.mass);
  f(a.id, b.id); f(a.kind, b.kind);
}
}  // namespace

void ParticleSet::reserve(size_t n) {
  ParticleSet& self = *this;
  forEachArray(self, self, [n](auto& array, auto&) { array.reserve(n); });
}

void ParticleSet::add(float px, float py, float pz, float vxIn, float vyIn, float vzIn, float rho0, float m,
                      int64_t particleId, int32_t particleKind) {
  x.push_back(px); y.push_back(py); z.push_back(pz);
  vx.push_back(vxIn); vy.push_back(vyIn); vz.push_back(vzIn);
  ax.push_back(0); ay.push_back(0); az.push_back(0);
  density.push_back(rho0); pressure.push_back(0); restDensity.push_back(rho0); mass.push_back(m);
  id.push_back(particleId); kind.push_back(particleKind);
}

void ParticleSet::permute(const std::vector<uint32_t>& order, ParticleSet& scratch) {
  forEachArray(*this, scratch, [&order](auto& array, auto& spare) { gather(array, order, spare); });
}

void ParticleSet::removeFlagged(const std::vector<uint8_t>& flags) {
  ParticleSet& self = *this;
  forEachArray(self, self, [&flags](auto& array, auto&) { compact(array, flags); });
}

double kineticEnergy(const ParticleSet& p) {
  double e = 0.0;
  for (size_t i = 0; i < p.size(); ++i) e += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
  return e;
}

}  // namespace kurage::sim
