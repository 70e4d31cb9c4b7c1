#include "sim/solvers/sweeps.h"

#include <immintrin.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

namespace kurage::sim::solvers {

namespace {

using Int4 = int __attribute__((vector_size(16)));

float scalarRate(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const Float4* v,
                 Float4 xi, Float4 vi) {
  const Float4 sum = rateSum(begin, end, slope, x, v, xi, vi);
  return sum[0] + sum[1] + sum[2];
}

Float4 scalarPush(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const float* k,
                  Float4 xi, float ki) {
  return pushSum(begin, end, slope, x, k, xi, ki);
}

void scalarFactor(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x,
                  const float* response, Float4 xi, Float4& F, float& S) {
  for (const uint32_t* it = begin; it != end; ++it, ++slope) {
    const Float4 xj = x[*it];
    const Float4 grad = *slope * (xi - xj);
    F += xj[3] * grad;
    S += response[*it] * (grad[0] * grad[0] + (grad[1] * grad[1] + grad[2] * grad[2]));  // Eigen's squaredNorm order
  }
}

// Appends the candidates j in [first, last) within sqrt(h2) of (xi, yi, zi), other than `self`,
// to out from index `found`, without a branch: every candidate is written and the count advances
// only for a neighbour. Returns the new count. Four candidates at a time where SSE2 is available:
// their r^2 in one register (the same operations in the same order as the scalar loop, so the
// same floats; with KURAGE_NATIVE's FMA the compiler may contract the two differently), the
// neighbours' indices among them packed to the front through a table and all four written with
// one store (out has room for every candidate); the list is the scalar loop's, in the same order.
// Every group is written, none skipped: a branch on an empty group (most are: about 27 of 216
// candidates are neighbours) is predictable only while the particles stand on their starting
// lattice, not once they have moved.
inline size_t siftRange(const float* __restrict x, const float* __restrict y, const float* __restrict z, float xi,
                   float yi, float zi, float h2, uint32_t self, uint32_t first, uint32_t last,
                   uint32_t* __restrict out, size_t found) {
  uint32_t j = first;
#if defined(__SSE2__)
  // kPack[m]: the lanes set in the 4-bit mask m, first, in order
  alignas(16) static constexpr int kPack[16][4] = {{0, 1, 2, 3}, {0, 1, 2, 3}, {1, 0, 2, 3}, {0, 1, 2, 3}, {2, 0, 1, 3}, {0, 2, 1, 3},
                                                   {1, 2, 0, 3}, {0, 1, 2, 3}, {3, 0, 1, 2}, {0, 3, 1, 2}, {1, 3, 0, 2}, {0, 1, 3, 2},
                                                   {2, 3, 0, 1}, {0, 2, 3, 1}, {1, 2, 3, 0}, {0, 1, 2, 3}};
  // kCount[m]: the lanes set in m (std::popcount calls libgcc without -mpopcnt: 1 % of a step)
  static constexpr uint8_t kCount[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
  const Float4 X = {xi, xi, xi, xi}, Y = {yi, yi, yi, yi}, Z = {zi, zi, zi, zi}, H2 = {h2, h2, h2, h2};
  for (; j + 4 <= last; j += 4) {
    Float4 px, py, pz;
    std::memcpy(&px, x + j, sizeof px);
    std::memcpy(&py, y + j, sizeof py);
    std::memcpy(&pz, z + j, sizeof pz);
    const Float4 dx = px - X, dy = py - Y, dz = pz - Z;
    const Float4 r2 = dx * dx + dy * dy + dz * dz;
    const Int4 inside = r2 < H2;
    unsigned mask = unsigned(__builtin_ia32_movmskps(Float4(inside)));
    if (self - j < 4u) mask &= ~(1u << (self - j));
    Int4 lanes;
    std::memcpy(&lanes, kPack[mask], sizeof lanes);
    const Int4 indices = lanes + int(j);
    std::memcpy(out + found, &indices, sizeof indices);
    found += size_t(kCount[mask]);
  }
#endif
  for (; j < last; ++j) {
    const float dx = x[j] - xi, dy = y[j] - yi, dz = z[j] - zi;
    const float r2 = dx * dx + dy * dy + dz * dz;
    out[found] = j;
    found += size_t((r2 < h2) & (j != self));
  }
  return found;
}

}  // namespace

namespace detail {
size_t siftFour(const float* x, const float* y, const float* z, float xi, float yi, float zi, float h2, uint32_t self,
                const std::array<uint32_t, 2>* ranges, int rangeCount, uint32_t* out) {
  size_t found = 0;
  for (int r = 0; r < rangeCount; ++r)
    found = siftRange(x, y, z, xi, yi, zi, h2, self, ranges[r][0], ranges[r][1], out, found);
  return found;
}
}  // namespace detail

namespace {

constexpr const char* kNames[] = {"scalar", "avx2", "avx512", "lanes"};  // by SweepIsa

constexpr SweepTable kScalar{SweepIsa::Scalar, "scalar", scalarRate, scalarPush, scalarFactor, detail::siftFour,
                             nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
constexpr SweepTable kLanes{SweepIsa::Lanes, "lanes", scalarRate, scalarPush, scalarFactor, detail::siftFour,
                            detail::rateLanes, detail::pushLanes, detail::factorLanes, detail::viscosityLanes,
                            detail::rateCorrectedLanes, detail::factorCorrectedLanes, detail::pushCorrectedLanes};

}  // namespace

bool sweepSupported(SweepIsa isa) {
  switch (isa) {
    case SweepIsa::Scalar: return true;
    case SweepIsa::Avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case SweepIsa::Avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("popcnt") && sweepSupported(SweepIsa::Avx2);
    case SweepIsa::Lanes: return __builtin_cpu_supports("avx2");
  }
  return false;
}

const SweepTable& sweepTable(SweepIsa isa) {
  if (!sweepSupported(isa)) throw std::invalid_argument("this CPU does not run the requested SIMD path");
  switch (isa) {
    case SweepIsa::Avx2: return detail::avx2Table();
    case SweepIsa::Avx512: return detail::avx512Table();
    case SweepIsa::Lanes: return kLanes;
    case SweepIsa::Scalar: break;
  }
  return kScalar;
}

const SweepTable& sweepTable() {
  const char* asked = std::getenv("KURAGE_SIMD");
  if (!asked || !*asked)  // the lanes path where the CPU runs it (the scalar path's floats), else the scalar one
    return sweepSupported(SweepIsa::Lanes) ? kLanes : kScalar;
  const std::string name(asked);
  for (SweepIsa isa : {SweepIsa::Scalar, SweepIsa::Avx2, SweepIsa::Avx512, SweepIsa::Lanes})
    if (name == kNames[int(isa)] && sweepSupported(isa)) return sweepTable(isa);
  throw std::invalid_argument("KURAGE_SIMD=" + name +
                              ": one of \"scalar\", \"avx2\", \"avx512\", \"lanes\" that this CPU runs");
}

void LaneLists::build(const NeighborLists& neighbors, size_t count) {
  const size_t chunks = neighbors.chunkCount();
  rows.resize(chunks);
  static_assert(NeighborLists::kChunk % kWidth == 0);
  groups.resize((count + kWidth - 1) / kWidth);  // chunk c's from c kGroupsPerChunk (every chunk but the last full)
  tbb::parallel_for(size_t(0), chunks, [&](size_t ch) {
    const size_t first = ch * NeighborLists::kChunk;
    const size_t members = std::min(count, first + NeighborLists::kChunk) - first;
    uint32_t next = 0;
    for (size_t g = groupsBegin(ch); g < groupsEnd(ch); ++g) {
      LaneGroup& group = groups[g];
      const size_t at = (g - groupsBegin(ch)) * kWidth;
      group.first = next;
      group.used = uint32_t(std::min(kWidth, members - at));
      group.rows = 0;
      for (size_t l = 0; l < kWidth; ++l) {
        group.self[l] = uint32_t(first + (l < group.used ? at + l : at));
        group.count[l] = l < group.used ? int32_t(neighbors.count(group.self[l])) : 0;
        group.rows = std::max(group.rows, uint32_t(group.count[l]));
      }
      next += group.rows;
    }
    const float* slopes = neighbors.slopes(ch).data();
    std::vector<LaneRow>& out = rows[ch];
    out.resize(next);  // capacity is kept between steps
    for (size_t g = groupsBegin(ch); g < groupsEnd(ch); ++g) {
      const LaneGroup& group = groups[g];
      LaneRow* r = out.data() + group.first;
      for (size_t l = 0; l < kWidth; ++l) {
        const uint32_t i = group.self[l];
        const uint32_t* list = neighbors.begin(i);
        const float* s = slopes + neighbors.offset(i);
        const uint32_t c = uint32_t(group.count[l]);
        for (uint32_t k = 0; k < c; ++k) { r[k].idx[l] = list[k]; r[k].slope[l] = s[k]; }
        for (uint32_t k = c; k < group.rows; ++k) { r[k].idx[l] = i; r[k].slope[l] = 0.0f; }
      }
    }
  });
}

size_t LaneLists::memoryBytes() const {
  size_t b = groups.capacity() * sizeof(LaneGroup);
  for (const auto& r : rows) b += r.capacity() * sizeof(LaneRow);
  return b;
}

}  // namespace kurage::sim::solvers
