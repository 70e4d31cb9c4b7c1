// The neighbour sums of the pressure solvers' sweeps (dfsph/, iisph/), one particle i a call, over
// its neighbour list [begin, end) with the density pass's s_ij = W'(r_ij)/r_ij alongside
// (NeighborLists::slopes), on the solvers' packed data: x_j = (x, y, z, w_j), v_j = (vx, vy, vz, 0):
//   rate:   sum_j w_j (v_i - v_j) . s_ij (x_i - x_j)              the density rate's sum (DFSPH 2017, eq. 9)
//   push:   sum_j s_ij w_j (k_i + k_j) (x_i - x_j)                the symmetric pressure push (eq. 7; lane 3 0)
//   factor: F += sum_j w_j s_ij (x_i - x_j),
//           S += sum_j c_j |s_ij (x_i - x_j)|^2                   the factor's two sums (eq. 13)
// and the density pass's neighbour search (fluid.cpp), `sift`: of the candidates in the grid's
// index ranges, those j != i with |x_i - x_j|^2 < h^2, appended in index order (every path finds
// the same list: the same r^2 floats, no FMA).
// (factor: DFSPH's factor pass; IISPH's keeps its own loop, whose squares add in another order.)
// Paths, one table each, chosen once per solver (and per density pass) by sweepTable():
//   scalar: one neighbour at a time, a Float4 per pair (any x86-64; the floats of solvers::rateSum
//           and pushSum, in list order); the sift 4 candidates at a time (SSE2).
//   avx2:   8 neighbours at a time (AVX2 + FMA): their records loaded 128 bits each and transposed
//           in registers to x, y, z, w lanes; k_j and c_j gathered; the list's tail in masked lanes
//           (slope 0, a duplicate index: they add +-0).
//   avx512: the same, 16 neighbours at a time (AVX-512F); the sift 16 candidates at a time, the
//           neighbours' indices compressed to the list with one masked store.
//   lanes:  the scalar path, but DFSPH's rate, push and factor (with the corrected gradient too)
//           and its viscosity pass (fluid.cpp) 8 particles at a time (AVX2), lane l summing particle l's list with the scalar sums'
//           operations in list order: the scalar path's floats. Their lists interleaved once a step (LaneLists), each row's 8 records
//           loaded 128 bits each and transposed, k_j and c_j by 8 loads; no horizontal sum, no tail.
// Each path's sum for a particle is in a fixed order (per lane, then a fixed tree across lanes): a
// run does not depend on the thread count on any path. The avx2 and avx512 paths contract to FMA
// and add in another order than the scalar one: their floats differ from it by rounding (a few
// ulp of a sum's largest term). KURAGE_SIMD=scalar|avx2|avx512|lanes in the environment asks for a
// path (one the CPU runs; another value is an error). Unset: lanes where the CPU runs AVX2, else
// scalar (the same floats either way). Only the ISA files are compiled with the ISA's flags and
// only the tables' functions use them, so one binary runs on any x86-64. The avx2 and avx512 sums
// ran no faster than the scalar ones on the machine measured (docs/notebook/simulation-speed.md),
// and the AVX-512 sift, though faster itself, left the rest of a step slower: they are asked for.
#pragma once

#include "sim/solvers/solver_common.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace kurage::sim::solvers {

enum class SweepIsa { Scalar, Avx2, Avx512, Lanes };

// The lanes path's lists: eight consecutive particles' lists interleaved, row r holding the r-th
// neighbour of each (index and s_ij), a group's rows as many as its longest list; past a list's
// end its lane holds the particle itself with slope 0 (count says where the list ends). Groups
// start at multiples of 8 and so lie within one NeighborLists chunk, whose rows they share.
// Consecutive particles are close, so a row's eight neighbours mostly share cache lines.
struct alignas(64) LaneRow {
  uint32_t idx[8];
  float slope[8];
};
struct LaneGroup {
  uint32_t first, rows;  // its rows in its chunk's
  uint32_t used;         // its particles: self[0..used)
  uint32_t self[8];      // its particles (the first one repeated past used)
  int32_t count[8];      // their neighbour counts (0 past used)
};
struct LaneLists {
  std::vector<std::vector<LaneRow>> rows;  // per NeighborLists chunk
  std::vector<LaneGroup> groups;           // chunk c's: [groupsBegin(c), groupsEnd(c))
  static constexpr size_t kWidth = 8;
  static constexpr size_t kGroupsPerChunk = NeighborLists::kChunk / kWidth;
  // From the density pass's lists and slopes (every chunk's slopes filled), for `count` particles.
  void build(const NeighborLists& neighbors, size_t count);
  size_t groupsBegin(size_t chunk) const { return chunk * kGroupsPerChunk; }
  size_t groupsEnd(size_t chunk) const { return std::min(groups.size(), (chunk + 1) * kGroupsPerChunk); }
  size_t memoryBytes() const;
};

struct SweepTable {
  SweepIsa isa;
  const char* name;  // "scalar", "avx2", "avx512"
  float (*rate)(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const Float4* v,
                Float4 xi, Float4 vi);
  Float4 (*push)(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const float* k,
                 Float4 xi, float ki);
  void (*factor)(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x,
                 const float* response, Float4 xi, Float4& F, float& S);
  // Writes the neighbours among `rangeCount` candidate ranges [first, last) to out (room for every
  // candidate; past the count it may write anything) and returns their count.
  size_t (*sift)(const float* x, const float* y, const float* z, float xi, float yi, float zi, float h2,
                 uint32_t self, const std::array<uint32_t, 2>* ranges, int rangeCount, uint32_t* out);
  // The lanes path's rate and push for one group's eight particles, lane by lane the scalar sums
  // rate and push, in list order with the same operations (so the same floats); nullptr on the
  // other paths. out: 8 rates; 8 pushes (fourth lane 0).
  void (*rateLanes)(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, float* out);
  void (*pushLanes)(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* k, Float4* out);
  // The factor's sums F and S of the group's eight particles, added to F[0..8) and S[0..8) (F's
  // fourth lane left 0), lane by lane the scalar factor's operations in list order.
  void (*factorLanes)(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* response, Float4* F,
                      float* S);
  // The viscosity's neighbour sum of the group's eight particles (fluid.h's (6) over its
  // coefficient), lane by lane the scalar force pass's operations in list order:
  //   fv_i = sum_j (m_j / rho_j) (h - r_ij) (v_j - v_i),  r_ij = |x_i - x_j| (0 where r_ij^2 <= tiny2)
  // from the records x_j = (x, y, z, m_j / rho_j) and v_j = (vx, vy, vz, 0). out: 8 sums (fourth lane 0).
  void (*viscosityLanes)(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, float h,
                         float tiny2, Float4* out);
  // The corrected gradient's neighbour sums (solver_common.h's correctedRateSum, correctedFactorSum,
  // correctedPushSum) of the group's eight particles, lane by lane their operations in list order:
  // t[3l + a] the rate's T_a; plain[l] and S[l] the factor's, L_i's rows at correction[3i..3i+3);
  // m[2l], m[2l + 1] and y2[l] the push's, from terms (two a particle) and z.
  void (*rateCorrectedLanes)(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, Float4* t);
  void (*factorCorrectedLanes)(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* response,
                               const Float4* correction, Float4* plain, float* S);
  void (*pushCorrectedLanes)(const LaneRow* rows, const LaneGroup& g, const Float4* terms, const float* z, Float4* m,
                             float* y2);
};

// Whether this CPU (and its OS) runs a path.
bool sweepSupported(SweepIsa isa);
// The table of a path this CPU runs (tests compare paths); the solvers' (above: KURAGE_SIMD's, or
// the scalar path; std::invalid_argument for an unknown or unsupported name).
const SweepTable& sweepTable(SweepIsa isa);
const SweepTable& sweepTable();

namespace detail {  // the ISA translation units' tables (sweeps_avx2.cpp, sweeps_avx512.cpp)
size_t siftFour(const float* x, const float* y, const float* z, float xi, float yi, float zi, float h2, uint32_t self,
                const std::array<uint32_t, 2>* ranges, int rangeCount, uint32_t* out);
const SweepTable& avx2Table();
const SweepTable& avx512Table();
// The lanes path's sums (sweeps_avx2.cpp)
void rateLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, float* out);
void pushLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* k, Float4* out);
void factorLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* response, Float4* F, float* S);
void viscosityLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, float h, float tiny2,
                    Float4* out);
void rateCorrectedLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, Float4* t);
void factorCorrectedLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* response,
                          const Float4* correction, Float4* plain, float* S);
void pushCorrectedLanes(const LaneRow* rows, const LaneGroup& g, const Float4* terms, const float* z, Float4* m,
                        float* y2);
}  // namespace detail

}  // namespace kurage::sim::solvers
