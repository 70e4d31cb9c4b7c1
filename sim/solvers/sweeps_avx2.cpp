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
  // The records r[idx[0..8)] as four lanes: rows [r_k | r_k+4] transposed 4 x 4 within each half.
  static void records(const Float4* r, const uint32_t* idx, V& a, V& b, V& c, V& d) {
    const auto row = [&](int k) {
      return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(reinterpret_cast<const float*>(r + idx[k]))),
                                  _mm_load_ps(reinterpret_cast<const float*>(r + idx[k + 4])), 1);
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

namespace detail {
const SweepTable& avx2Table() {
  static constexpr SweepTable table = simd::table<Avx2>(SweepIsa::Avx2, "avx2");
  return table;
}
}  // namespace detail

}  // namespace kurage::sim::solvers
