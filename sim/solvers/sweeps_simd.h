// The SIMD paths of sweeps.h, written once over a lane type L (W floats: AVX2's 8, AVX-512's 16)
// and included by the translation unit compiled for that ISA (sweeps_avx2.cpp, sweeps_avx512.cpp;
// their flags in sim/CMakeLists.txt). Neighbours go W at a time: their indices in a group (the
// list's tail padded with its first index, slope 0), their 16-byte records transposed to lanes
// (L::records), per-particle scalars gathered (L::gather); per lane accumulators, summed across
// lanes in a fixed tree at the end (L::sum).
#pragma once

#include "sim/solvers/sweeps.h"

#include <immintrin.h>

#include <cstring>

namespace kurage::sim::solvers::simd {

// Calls f(idx, slopes) for each group of W neighbours: idx W indices, slopes W floats (0 past the
// list's end, where idx repeats the first neighbour).
template <class L, class F>
inline void groups(const uint32_t* begin, const uint32_t* end, const float* slope, F&& f) {
  constexpr int W = L::W;
  const size_t count = size_t(end - begin);
  size_t g = 0;
  for (; g + W <= count; g += W) f(begin + g, L::load(slope + g));
  if (g == count) return;
  alignas(64) uint32_t idx[W];
  const auto s = L::tail(begin + g, slope + g, count - g, idx);
  f(static_cast<const uint32_t*>(idx), s);
}

template <class L>
float rate(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const Float4* v,
           Float4 xi, Float4 vi) {
  using V = typename L::V;
  const V Xi = L::set1(xi[0]), Yi = L::set1(xi[1]), Zi = L::set1(xi[2]);
  const V Ui = L::set1(vi[0]), Vi = L::set1(vi[1]), Wi = L::set1(vi[2]);
  V acc = L::zero();
  groups<L>(begin, end, slope, [&](const uint32_t* idx, V s) {
    V X, Y, Z, Wt, U, Vv, Ww, unused;
    L::records(x, idx, X, Y, Z, Wt);
    L::records(v, idx, U, Vv, Ww, unused);
    V dot = L::mul(L::sub(Xi, X), L::sub(Ui, U));
    dot = L::fma(L::sub(Yi, Y), L::sub(Vi, Vv), dot);
    dot = L::fma(L::sub(Zi, Z), L::sub(Wi, Ww), dot);
    acc = L::fma(L::mul(Wt, s), dot, acc);  // w_j s_ij (x_i - x_j) . (v_i - v_j)
  });
  return L::sum(acc);
}

template <class L>
Float4 push(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const float* k,
            Float4 xi, float ki) {
  using V = typename L::V;
  const V Xi = L::set1(xi[0]), Yi = L::set1(xi[1]), Zi = L::set1(xi[2]), Ki = L::set1(ki);
  V ax = L::zero(), ay = ax, az = ax;
  groups<L>(begin, end, slope, [&](const uint32_t* idx, V s) {
    V X, Y, Z, Wt;
    L::records(x, idx, X, Y, Z, Wt);
    const V c = L::mul(s, L::mul(Wt, L::add(Ki, L::gather(k, idx))));  // s_ij w_j (k_i + k_j)
    ax = L::fma(c, L::sub(Xi, X), ax);
    ay = L::fma(c, L::sub(Yi, Y), ay);
    az = L::fma(c, L::sub(Zi, Z), az);
  });
  return Float4{L::sum(ax), L::sum(ay), L::sum(az), 0.0f};
}

template <class L>
void factor(const uint32_t* begin, const uint32_t* end, const float* slope, const Float4* x, const float* response,
            Float4 xi, Float4& F, float& S) {
  using V = typename L::V;
  const V Xi = L::set1(xi[0]), Yi = L::set1(xi[1]), Zi = L::set1(xi[2]);
  V fx = L::zero(), fy = fx, fz = fx, sq = fx;
  groups<L>(begin, end, slope, [&](const uint32_t* idx, V s) {
    V X, Y, Z, Wt;
    L::records(x, idx, X, Y, Z, Wt);
    const V gx = L::mul(s, L::sub(Xi, X)), gy = L::mul(s, L::sub(Yi, Y)), gz = L::mul(s, L::sub(Zi, Z));
    fx = L::fma(Wt, gx, fx);
    fy = L::fma(Wt, gy, fy);
    fz = L::fma(Wt, gz, fz);
    const V g2 = L::fma(gz, gz, L::fma(gy, gy, L::mul(gx, gx)));
    sq = L::fma(L::gather(response, idx), g2, sq);  // c_j |grad W_ij|^2
  });
  F += Float4{L::sum(fx), L::sum(fy), L::sum(fz), 0.0f};
  S += L::sum(sq);
}

template <class L>
constexpr SweepTable table(SweepIsa isa, const char* name) {
  return SweepTable{isa, name, rate<L>, push<L>, factor<L>, L::sift, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
}

}  // namespace kurage::sim::solvers::simd
