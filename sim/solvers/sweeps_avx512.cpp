// sweeps.h's AVX-512 path (this file is compiled with -mavx512f -mavx2 -mfma -mpopcnt; sim/CMakeLists.txt): 16 lanes.

// GCC 12's AVX-512 intrinsics start from _mm512_undefined_*(), which -Wuninitialized reports once
// inlined (set before the intrinsics' header is read).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "sim/solvers/sweeps_simd.h"

namespace kurage::sim::solvers {

namespace {
struct Avx512 {
  static constexpr int W = 16;
  using V = __m512;
  static V zero() { return _mm512_setzero_ps(); }
  static V set1(float a) { return _mm512_set1_ps(a); }
  static V load(const float* p) { return _mm512_loadu_ps(p); }
  // The list's last `count` < 16 entries: their slopes (0 beyond), their indices to idx (the first beyond)
  static V tail(const uint32_t* list, const float* s, size_t count, uint32_t* idx) {
    const __mmask16 m = __mmask16((1u << count) - 1u);
    _mm512_store_si512(idx, _mm512_mask_loadu_epi32(_mm512_set1_epi32(int(list[0])), m, list));
    return _mm512_maskz_loadu_ps(m, s);
  }
  static V add(V a, V b) { return _mm512_add_ps(a, b); }
  static V sub(V a, V b) { return _mm512_sub_ps(a, b); }
  static V mul(V a, V b) { return _mm512_mul_ps(a, b); }
  static V fma(V a, V b, V c) { return _mm512_fmadd_ps(a, b, c); }
  static V gather(const float* base, const uint32_t* idx) {
    return _mm512_i32gather_ps(_mm512_loadu_si512(idx), base, 4);
  }
  // The records r[idx[0..16)] as four lanes: rows [r_k | r_k+4 | r_k+8 | r_k+12] transposed 4 x 4
  // within each quarter.
  static void records(const Float4* r, const uint32_t* idx, V& a, V& b, V& c, V& d) {
    const auto at = [&](int k) { return _mm_load_ps(reinterpret_cast<const float*>(r + idx[k])); };
    const auto row = [&](int k) {
      V q = _mm512_castps128_ps512(at(k));
      q = _mm512_insertf32x4(q, at(k + 4), 1);
      q = _mm512_insertf32x4(q, at(k + 8), 2);
      return _mm512_insertf32x4(q, at(k + 12), 3);
    };
    const V r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
    const __m512d t0 = _mm512_castps_pd(_mm512_unpacklo_ps(r0, r1)), t1 = _mm512_castps_pd(_mm512_unpackhi_ps(r0, r1));
    const __m512d t2 = _mm512_castps_pd(_mm512_unpacklo_ps(r2, r3)), t3 = _mm512_castps_pd(_mm512_unpackhi_ps(r2, r3));
    a = _mm512_castpd_ps(_mm512_unpacklo_pd(t0, t2));
    b = _mm512_castpd_ps(_mm512_unpackhi_pd(t0, t2));
    c = _mm512_castpd_ps(_mm512_unpacklo_pd(t1, t3));
    d = _mm512_castpd_ps(_mm512_unpackhi_pd(t1, t3));
  }
  // 16 candidates at a time: r^2 as the scalar path forms it (no FMA: the same floats), the
  // neighbours' indices packed to the front.
  static size_t sift(const float* x, const float* y, const float* z, float xi, float yi, float zi, float h2,
                     uint32_t self, const std::array<uint32_t, 2>* ranges, int rangeCount, uint32_t* out) {
    const V X = set1(xi), Y = set1(yi), Z = set1(zi), H2 = set1(h2);
    const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    size_t found = 0;
    for (int r = 0; r < rangeCount; ++r) {
      const uint32_t last = ranges[r][1];
      for (uint32_t j = ranges[r][0]; j < last; j += 16) {
        const __mmask16 in = last - j >= 16 ? __mmask16(0xffff) : __mmask16((1u << (last - j)) - 1u);
        const V dx = sub(_mm512_maskz_loadu_ps(in, x + j), X);
        const V dy = sub(_mm512_maskz_loadu_ps(in, y + j), Y);
        const V dz = sub(_mm512_maskz_loadu_ps(in, z + j), Z);
        const V r2 = add(add(mul(dx, dx), mul(dy, dy)), mul(dz, dz));
        __mmask16 near = _mm512_mask_cmp_ps_mask(in, r2, H2, _CMP_LT_OQ);
        if (self - j < 16u) near &= __mmask16(~(1u << (self - j)));
        // compressed in a register, then stored under a mask (a compressing store to memory is slow on some cores)
        const __m512i packed = _mm512_maskz_compress_epi32(near, _mm512_add_epi32(iota, _mm512_set1_epi32(int(j))));
        const int count = _mm_popcnt_u32(near);
        _mm512_mask_storeu_epi32(out + found, __mmask16((1u << count) - 1u), packed);
        found += size_t(count);
      }
    }
    return found;
  }
  // Halves added (16 -> 8 -> 4 -> 2 -> 1), each step in lane order.
  static float sum(V a) {
    const __m256 upper = _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(a), 1));
    const __m256 h = _mm256_add_ps(_mm512_castps512_ps256(a), upper);
    __m128 s = _mm_add_ps(_mm256_castps256_ps128(h), _mm256_extractf128_ps(h, 1));
    s = _mm_add_ps(s, _mm_movehl_ps(s, s));
    s = _mm_add_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
  }
};
}  // namespace

namespace detail {
const SweepTable& avx512Table() {
  static constexpr SweepTable table = simd::table<Avx512>(SweepIsa::Avx512, "avx512");
  return table;
}
}  // namespace detail

}  // namespace kurage::sim::solvers
