// sweeps.h's AVX2 path (this file is compiled with -mavx2 -mfma; sim/CMakeLists.txt): 8 lanes.
#include "sim/solvers/sweeps_simd.h"

namespace kurage::sim::solvers {

namespace {
struct Avx2 {
  static constexpr int W = 8;
  using V = __m256;
  static V zero() { return _mm256_setzero_ps(); }
  static V set1(float a) { return _mm256_set1_ps(a); }
  static V load(const float* p) { return _mm256_loadu_ps(p); }
  // The list's last `count` < 8 entries: their slopes (0 beyond), their indices to idx (the first beyond)
  static V tail(const uint32_t* list, const float* s, size_t count, uint32_t* idx) {
    const __m256i m = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(count)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i in = _mm256_maskload_epi32(reinterpret_cast<const int*>(list), m);
    _mm256_store_si256(reinterpret_cast<__m256i*>(idx), _mm256_blendv_epi8(_mm256_set1_epi32(int(list[0])), in, m));
    return _mm256_maskload_ps(s, m);
  }
  static V add(V a, V b) { return _mm256_add_ps(a, b); }
  static V sub(V a, V b) { return _mm256_sub_ps(a, b); }
  static V mul(V a, V b) { return _mm256_mul_ps(a, b); }
  static V fma(V a, V b, V c) { return _mm256_fmadd_ps(a, b, c); }
  static V gather(const float* base, const uint32_t* idx) {
    return _mm256_i32gather_ps(base, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(idx)), 4);
  }
  // The records r[Stride idx[0..8)] as four lanes: rows [r_k | r_k+4] transposed 4 x 4 within each half.
  template <size_t Stride = 1>
  static void records(const Float4* r, const uint32_t* idx, V& a, V& b, V& c, V& d) {
    const auto row = [&](int k) {
      return _mm256_insertf128_ps(
          _mm256_castps128_ps256(_mm_load_ps(reinterpret_cast<const float*>(r + Stride * idx[k]))),
          _mm_load_ps(reinterpret_cast<const float*>(r + Stride * idx[k + 4])), 1);
    };
    const V r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
    const __m256d t0 = _mm256_castps_pd(_mm256_unpacklo_ps(r0, r1)), t1 = _mm256_castps_pd(_mm256_unpackhi_ps(r0, r1));
    const __m256d t2 = _mm256_castps_pd(_mm256_unpacklo_ps(r2, r3)), t3 = _mm256_castps_pd(_mm256_unpackhi_ps(r2, r3));
    a = _mm256_castpd_ps(_mm256_unpacklo_pd(t0, t2));
    b = _mm256_castpd_ps(_mm256_unpackhi_pd(t0, t2));
    c = _mm256_castpd_ps(_mm256_unpacklo_pd(t1, t3));
    d = _mm256_castpd_ps(_mm256_unpackhi_pd(t1, t3));
  }
  static constexpr auto sift = detail::siftFour;  // 4 at a time, as the scalar path
  // ((l0 + l4) + (l2 + l6)) + ((l1 + l5) + (l3 + l7))
  static float sum(V a) {
    __m128 s = _mm_add_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    s = _mm_add_ps(s, _mm_movehl_ps(s, s));
    s = _mm_add_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
  }
};
}  // namespace

// The lanes path (sweeps.h): lane l sums particle g.self[l]'s list, row by row, with the scalar
// sums' operations in their order (this file fuses no multiply and add it does not write). A row
// past the lane's list adds the particle's own record at slope 0: a term +-0, which leaves every
// sum as it is (a sum from +0 is never -0: x + +-0 = x for x != -0).
namespace {
// x, y, z and w of the records r[Stride idx[0..8)]: 128-bit loads transposed (AMD's hardware
// gathers, one element a cycle or slower, cost more)
template <size_t Stride = 1>
inline void lanesOf(const Float4* r, const uint32_t* idx, __m256& a, __m256& b, __m256& c, __m256& d) {
  Avx2::records<Stride>(r, idx, a, b, c, d);
}
// Eight loads a[idx[0..8)] (not a gather: above)
inline __m256 loadEight(const float* a, const uint32_t* j) {
  return _mm256_setr_ps(a[j[0]], a[j[1]], a[j[2]], a[j[3]], a[j[4]], a[j[5]], a[j[6]], a[j[7]]);
}
// out[l] = (a_l, b_l, c_l, 0) for the eight lanes
inline void storeLanes(__m256 a, __m256 b, __m256 c, Float4* out) {
  alignas(32) float pa[8], pb[8], pc[8];
  _mm256_store_ps(pa, a);
  _mm256_store_ps(pb, b);
  _mm256_store_ps(pc, c);
  for (int l = 0; l < 8; ++l) out[l] = Float4{pa[l], pb[l], pc[l], 0.0f};
}
// A row's grad W_ij = s_ij (x_i - x_j) per axis, and w_j (the records' fourth lane)
inline void rowGradient(const LaneRow& row, const Float4* x, __m256 Xi, __m256 Yi, __m256 Zi, __m256& gx, __m256& gy,
                        __m256& gz, __m256& W) {
  const __m256 s = _mm256_load_ps(row.slope);
  __m256 X, Y, Z;
  lanesOf(x, row.idx, X, Y, Z, W);
  gx = _mm256_mul_ps(s, _mm256_sub_ps(Xi, X));
  gy = _mm256_mul_ps(s, _mm256_sub_ps(Yi, Y));
  gz = _mm256_mul_ps(s, _mm256_sub_ps(Zi, Z));
}
}  // namespace

namespace detail {
void rateLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, float* out) {
  __m256 Xi, Yi, Zi, Wi, Ui, Vi, Ti, unused;
  lanesOf(x, g.self, Xi, Yi, Zi, Wi);
  lanesOf(v, g.self, Ui, Vi, Ti, unused);
  __m256 sx = _mm256_setzero_ps(), sy = sx, sz = sx;
  for (uint32_t k = 0; k < g.rows; ++k) {
    const LaneRow& row = rows[g.first + k];
    const __m256 s = _mm256_load_ps(row.slope);
    __m256 X, Y, Z, W, U, V, T;
    lanesOf(x, row.idx, X, Y, Z, W);
    lanesOf(v, row.idx, U, V, T, unused);
    // w_j ((v_i - v_j) * (s_ij * (x_i - x_j))), per axis
    const __m256 tx = _mm256_mul_ps(W, _mm256_mul_ps(_mm256_sub_ps(Ui, U), _mm256_mul_ps(s, _mm256_sub_ps(Xi, X))));
    const __m256 ty = _mm256_mul_ps(W, _mm256_mul_ps(_mm256_sub_ps(Vi, V), _mm256_mul_ps(s, _mm256_sub_ps(Yi, Y))));
    const __m256 tz = _mm256_mul_ps(W, _mm256_mul_ps(_mm256_sub_ps(Ti, T), _mm256_mul_ps(s, _mm256_sub_ps(Zi, Z))));
    sx = _mm256_add_ps(sx, tx);
    sy = _mm256_add_ps(sy, ty);
    sz = _mm256_add_ps(sz, tz);
  }
  _mm256_storeu_ps(out, _mm256_add_ps(_mm256_add_ps(sx, sy), sz));
}

void pushLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* k, Float4* out) {
  __m256 Xi, Yi, Zi, Wi;
  lanesOf(x, g.self, Xi, Yi, Zi, Wi);
  const __m256i self = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(g.self));
  const __m256 Ki = _mm256_i32gather_ps(k, self, 4);
  __m256 ax = _mm256_setzero_ps(), ay = ax, az = ax;
  for (uint32_t r = 0; r < g.rows; ++r) {
    const LaneRow& row = rows[g.first + r];
    const __m256 s = _mm256_load_ps(row.slope);
    __m256 X, Y, Z, W;
    lanesOf(x, row.idx, X, Y, Z, W);
    const __m256 Kj = loadEight(k, row.idx);
    const __m256 c = _mm256_mul_ps(s, _mm256_mul_ps(W, _mm256_add_ps(Ki, Kj)));  // s_ij (w_j (k_i + k_j))
    ax = _mm256_add_ps(ax, _mm256_mul_ps(c, _mm256_sub_ps(Xi, X)));
    ay = _mm256_add_ps(ay, _mm256_mul_ps(c, _mm256_sub_ps(Yi, Y)));
    az = _mm256_add_ps(az, _mm256_mul_ps(c, _mm256_sub_ps(Zi, Z)));
  }
  storeLanes(ax, ay, az, out);
}

void factorLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* response, Float4* F,
                 float* S) {
  static constexpr uint32_t kOwn[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  __m256 Xi, Yi, Zi, Wi, fx, fy, fz, unused;
  lanesOf(x, g.self, Xi, Yi, Zi, Wi);
  lanesOf(F, kOwn, fx, fy, fz, unused);
  __m256 sq = _mm256_loadu_ps(S);
  for (uint32_t r = 0; r < g.rows; ++r) {
    const LaneRow& row = rows[g.first + r];
    __m256 gx, gy, gz, W;
    rowGradient(row, x, Xi, Yi, Zi, gx, gy, gz, W);
    const __m256 C = loadEight(response, row.idx);
    fx = _mm256_add_ps(fx, _mm256_mul_ps(W, gx));
    fy = _mm256_add_ps(fy, _mm256_mul_ps(W, gy));
    fz = _mm256_add_ps(fz, _mm256_mul_ps(W, gz));
    // c_j (g0^2 + (g1^2 + g2^2)): the scalar factor's order (Eigen's squaredNorm)
    const __m256 g2 = _mm256_add_ps(_mm256_mul_ps(gx, gx), _mm256_add_ps(_mm256_mul_ps(gy, gy), _mm256_mul_ps(gz, gz)));
    sq = _mm256_add_ps(sq, _mm256_mul_ps(C, g2));
  }
  storeLanes(fx, fy, fz, F);
  _mm256_storeu_ps(S, sq);
}

void viscosityLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, float h, float tiny2,
                    Float4* out) {
  __m256 Xi, Yi, Zi, unused, Ui, Vi, Ti;
  lanesOf(x, g.self, Xi, Yi, Zi, unused);
  lanesOf(v, g.self, Ui, Vi, Ti, unused);
  const __m256 H = _mm256_set1_ps(h), Tiny2 = _mm256_set1_ps(tiny2);
  __m256 fx = _mm256_setzero_ps(), fy = fx, fz = fx;
  for (uint32_t r = 0; r < g.rows; ++r) {
    const LaneRow& row = rows[g.first + r];
    __m256 X, Y, Z, M, U, V, T;
    lanesOf(x, row.idx, X, Y, Z, M);
    lanesOf(v, row.idx, U, V, T, unused);
    const __m256 dx = _mm256_sub_ps(Xi, X), dy = _mm256_sub_ps(Yi, Y), dz = _mm256_sub_ps(Zi, Z);
    const __m256 r2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
    // r_ij, 0 for coincident particles (and a padded row's own record)
    const __m256 dist = _mm256_and_ps(_mm256_cmp_ps(r2, Tiny2, _CMP_GT_OQ), _mm256_sqrt_ps(r2));
    const __m256 visc = _mm256_mul_ps(M, _mm256_sub_ps(H, dist));  // (m_j / rho_j) (h - r)
    fx = _mm256_add_ps(fx, _mm256_mul_ps(visc, _mm256_sub_ps(U, Ui)));
    fy = _mm256_add_ps(fy, _mm256_mul_ps(visc, _mm256_sub_ps(V, Vi)));
    fz = _mm256_add_ps(fz, _mm256_mul_ps(visc, _mm256_sub_ps(T, Ti)));
  }
  storeLanes(fx, fy, fz, out);
}

void rateCorrectedLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const Float4* v, Float4* t) {
  __m256 Xi, Yi, Zi, Ui, Vi, Ti, unused;
  lanesOf(x, g.self, Xi, Yi, Zi, unused);
  lanesOf(v, g.self, Ui, Vi, Ti, unused);
  // t[a] per axis b: tab += (v_i - v_j)_a e_b, e = (w_j s_ij) (x_i - x_j)
  __m256 txx = _mm256_setzero_ps(), txy = txx, txz = txx, tyx = txx, tyy = txx, tyz = txx, tzx = txx, tzy = txx,
         tzz = txx;
  for (uint32_t r = 0; r < g.rows; ++r) {
    const LaneRow& row = rows[g.first + r];
    const __m256 s = _mm256_load_ps(row.slope);
    __m256 X, Y, Z, W, U, V, T;
    lanesOf(x, row.idx, X, Y, Z, W);
    lanesOf(v, row.idx, U, V, T, unused);
    const __m256 ws = _mm256_mul_ps(W, s);
    const __m256 ex = _mm256_mul_ps(ws, _mm256_sub_ps(Xi, X));
    const __m256 ey = _mm256_mul_ps(ws, _mm256_sub_ps(Yi, Y));
    const __m256 ez = _mm256_mul_ps(ws, _mm256_sub_ps(Zi, Z));
    const __m256 du = _mm256_sub_ps(Ui, U), dv = _mm256_sub_ps(Vi, V), dw = _mm256_sub_ps(Ti, T);
    txx = _mm256_add_ps(txx, _mm256_mul_ps(du, ex));
    txy = _mm256_add_ps(txy, _mm256_mul_ps(du, ey));
    txz = _mm256_add_ps(txz, _mm256_mul_ps(du, ez));
    tyx = _mm256_add_ps(tyx, _mm256_mul_ps(dv, ex));
    tyy = _mm256_add_ps(tyy, _mm256_mul_ps(dv, ey));
    tyz = _mm256_add_ps(tyz, _mm256_mul_ps(dv, ez));
    tzx = _mm256_add_ps(tzx, _mm256_mul_ps(dw, ex));
    tzy = _mm256_add_ps(tzy, _mm256_mul_ps(dw, ey));
    tzz = _mm256_add_ps(tzz, _mm256_mul_ps(dw, ez));
  }
  alignas(32) float a[9][8];
  const __m256 all[9] = {txx, txy, txz, tyx, tyy, tyz, tzx, tzy, tzz};
  for (int q = 0; q < 9; ++q) _mm256_store_ps(a[q], all[q]);
  for (int l = 0; l < 8; ++l)
    for (int q = 0; q < 3; ++q) t[3 * l + q] = Float4{a[3 * q][l], a[3 * q + 1][l], a[3 * q + 2][l], 0.0f};
}

void factorCorrectedLanes(const LaneRow* rows, const LaneGroup& g, const Float4* x, const float* response,
                          const Float4* correction, Float4* plain, float* S) {
  __m256 Xi, Yi, Zi, unused;
  lanesOf(x, g.self, Xi, Yi, Zi, unused);
  // L_i's rows: Rab = row a's entry b
  __m256 R0x, R0y, R0z, R1x, R1y, R1z, R2x, R2y, R2z;
  lanesOf<3>(correction, g.self, R0x, R0y, R0z, unused);
  lanesOf<3>(correction + 1, g.self, R1x, R1y, R1z, unused);
  lanesOf<3>(correction + 2, g.self, R2x, R2y, R2z, unused);
  __m256 px = _mm256_setzero_ps(), py = px, pz = px, sq = px;
  for (uint32_t r = 0; r < g.rows; ++r) {
    const LaneRow& row = rows[g.first + r];
    __m256 dx, dy, dz, W;
    rowGradient(row, x, Xi, Yi, Zi, dx, dy, dz, W);
    const __m256 C = loadEight(response, row.idx);
    // L_i grad W_ij: row 0 d_x + row 1 d_y + row 2 d_z, added in that order
    const __m256 gx = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(R0x, dx), _mm256_mul_ps(R1x, dy)), _mm256_mul_ps(R2x, dz));
    const __m256 gy = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(R0y, dx), _mm256_mul_ps(R1y, dy)), _mm256_mul_ps(R2y, dz));
    const __m256 gz = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(R0z, dx), _mm256_mul_ps(R1z, dy)), _mm256_mul_ps(R2z, dz));
    px = _mm256_add_ps(px, _mm256_mul_ps(W, dx));
    py = _mm256_add_ps(py, _mm256_mul_ps(W, dy));
    pz = _mm256_add_ps(pz, _mm256_mul_ps(W, dz));
    // c_j ((g0^2 + g1^2) + g2^2): the scalar sum's order
    const __m256 g2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(gx, gx), _mm256_mul_ps(gy, gy)), _mm256_mul_ps(gz, gz));
    sq = _mm256_add_ps(sq, _mm256_mul_ps(C, g2));
  }
  storeLanes(px, py, pz, plain);
  _mm256_storeu_ps(S, sq);
}

void pushCorrectedLanes(const LaneRow* rows, const LaneGroup& g, const Float4* terms, const float* z, Float4* m,
                        float* y2) {
  // Lane l's (m0, m1) in one register, += s_ij times j's two records as they lie (one 256-bit load
  // each, no transpose: fewer instructions a row than the transposed form)
  __m256 acc[8];
  for (__m256& a : acc) a = _mm256_setzero_ps();
  __m256 yz = _mm256_setzero_ps();
  for (uint32_t r = 0; r < g.rows; ++r) {
    const LaneRow& row = rows[g.first + r];
    for (int l = 0; l < 8; ++l) {
      const __m256 t = _mm256_loadu_ps(reinterpret_cast<const float*>(terms + 2 * size_t(row.idx[l])));
      acc[l] = _mm256_add_ps(acc[l], _mm256_mul_ps(_mm256_broadcast_ss(row.slope + l), t));
    }
    yz = _mm256_add_ps(yz, _mm256_mul_ps(_mm256_load_ps(row.slope), loadEight(z, row.idx)));
  }
  for (int l = 0; l < 8; ++l) _mm256_storeu_ps(reinterpret_cast<float*>(m + 2 * l), acc[l]);
  _mm256_storeu_ps(y2, yz);
}

const SweepTable& avx2Table() {
  static constexpr SweepTable table = simd::table<Avx2>(SweepIsa::Avx2, "avx2");
  return table;
}
}  // namespace detail

}  // namespace kurage::sim::solvers
