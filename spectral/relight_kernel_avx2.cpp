// AVX2 + F16C + FMA instantiation of the relight kernel (this file is compiled with
// -mavx2 -mf16c -mfma; selectRelightKernel only calls it on CPUs that have them).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "spectral/relight_kernel.h"
#include "spectral/srgb_table.h"

#if defined(__AVX2__) && defined(__F16C__)
#include <immintrin.h>
#endif

namespace svr::relight_avx2 {

#if defined(__AVX2__) && defined(__F16C__)
namespace {
inline void loadHalfChunk(const std::uint16_t* src, float* dst, int n) {
  int i = 0;
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(dst + i,
                     _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(src + i))));
  for (; i < n; ++i) dst[i] = _cvtsh_ss(src[i]);
}

// sRGB code values of 8 linear values: the same table as the portable path, read with one
// gather. The table holds bytes; each lane reads 4 bytes at its entry (the table is padded) and
// keeps the low one.
inline __m256i srgbCodes(__m256 v, const std::uint8_t* lut) {
  v = _mm256_min_ps(_mm256_max_ps(v, _mm256_setzero_ps()), _mm256_set1_ps(1.0f));
  const __m256i idx = _mm256_cvttps_epi32(
      _mm256_fmadd_ps(v, _mm256_set1_ps(kSrgbLutSize - 1), _mm256_set1_ps(0.5f)));
  const __m256i word = _mm256_i32gather_epi32(reinterpret_cast<const int*>(lut), idx, 1);
  return _mm256_and_si256(word, _mm256_set1_epi32(0xff));
}

inline void encodeSrgbChunk(const float* r, const float* g, const float* b, int n,
                            std::uint8_t* out, const std::uint8_t* lut) {
  // Bytes 0-2, 4-6, 8-10, 12-14 of each 128-bit lane: four packed RGB pixels.
  const __m256i pack = _mm256_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1,
                                        0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1);
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m256i px = _mm256_or_si256(
        srgbCodes(_mm256_loadu_ps(r + i), lut),
        _mm256_or_si256(_mm256_slli_epi32(srgbCodes(_mm256_loadu_ps(g + i), lut), 8),
                        _mm256_slli_epi32(srgbCodes(_mm256_loadu_ps(b + i), lut), 16)));
    const __m256i packed = _mm256_shuffle_epi8(px, pack);
    const __m128i lo = _mm256_castsi256_si128(packed), hi = _mm256_extracti128_si256(packed, 1);
    std::uint8_t* o = out + 3 * i;
    // Exactly 12 bytes per lane: rows are relit by different threads, so never write past.
    _mm_storel_epi64(reinterpret_cast<__m128i*>(o), lo);
    const int lo_tail = _mm_extract_epi32(lo, 2);
    std::memcpy(o + 8, &lo_tail, 4);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(o + 12), hi);
    const int hi_tail = _mm_extract_epi32(hi, 2);
    std::memcpy(o + 20, &hi_tail, 4);
  }
  encodeSrgbWithTable(r + i, g + i, b + i, n - i, out + 3 * i, lut);
}
#include "spectral/relight_kernel_body.inc"

// The common case fused: float planes to sRGB8, eight pixels at a time kept in registers from
// the loads through the matrix, the finiteness test and the encoding to the byte stores (the
// general body round-trips every chunk through a buffer). Rows that do not fill the last eight
// pixels, and any row holding a non-finite value, go through the general body.
template <int P>
long relightFusedSrgb(const RelightJob& job) {
  const float* m = job.matrix;
  __m256 mr[P], mg[P], mb[P];
  for (int p = 0; p < P; ++p) {
    mr[p] = _mm256_set1_ps(m[p]);
    mg[p] = _mm256_set1_ps(m[P + p]);
    mb[p] = _mm256_set1_ps(m[2 * P + p]);
  }
  const __m256i pack = _mm256_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1,
                                        0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1);
  std::size_t i = job.begin;
  for (; i + 8 <= job.end; i += 8) {
    __m256 r = _mm256_setzero_ps(), g = r, b = r;
    for (int p = 0; p < P; ++p) {
      const __m256 v = _mm256_loadu_ps(static_cast<const float*>(job.planes[p]) + i);
      r = _mm256_fmadd_ps(mr[p], v, r);
      g = _mm256_fmadd_ps(mg[p], v, g);
      b = _mm256_fmadd_ps(mb[p], v, b);
    }
    // r + g + b is finite exactly when all three are (an Inf stays Inf or meets −Inf in a
    // NaN, a NaN stays NaN; relit values are far below float's overflow), and x − x is NaN
    // exactly for NaN and ±Inf: one test for the three channels.
    const __m256 sum = _mm256_add_ps(_mm256_add_ps(r, g), b);
    const __m256 zero_or_nan = _mm256_sub_ps(sum, sum);
    if (_mm256_movemask_ps(_mm256_cmp_ps(zero_or_nan, zero_or_nan, _CMP_UNORD_Q)))
      break;  // the general body finds and reports the pixel
    const __m256i px = _mm256_or_si256(
        srgbCodes(r, job.srgb_lut),
        _mm256_or_si256(_mm256_slli_epi32(srgbCodes(g, job.srgb_lut), 8),
                        _mm256_slli_epi32(srgbCodes(b, job.srgb_lut), 16)));
    const __m256i packed = _mm256_shuffle_epi8(px, pack);
    const __m128i lo = _mm256_castsi256_si128(packed), hi = _mm256_extracti128_si256(packed, 1);
    std::uint8_t* o = job.out_srgb + 3 * i;
    _mm_storel_epi64(reinterpret_cast<__m128i*>(o), lo);
    const int lo_tail = _mm_extract_epi32(lo, 2);
    std::memcpy(o + 8, &lo_tail, 4);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(o + 12), hi);
    const int hi_tail = _mm_extract_epi32(hi, 2);
    std::memcpy(o + 20, &hi_tail, 4);
  }
  if (i == job.end) return -1;
  RelightJob rest = job;
  rest.begin = i;
  return relightSpan<P, float, true>(rest);
}
}  // namespace

bool compiled() { return true; }
RelightFn pick(int width, SampleStorage storage, RelitEncoding encoding) {
  if (storage == SampleStorage::kFloat && encoding == RelitEncoding::kSrgb8) switch (width) {
#define SVR_CASE(N) \
  case N:           \
    return &relightFusedSrgb<N>;
      SVR_RELIGHT_PLANE_COUNTS(SVR_CASE)
#undef SVR_CASE
      default:
        break;
    }
  return pickKernel(width, storage, encoding);
}
#else
bool compiled() { return false; }
RelightFn pick(int, SampleStorage, RelitEncoding) { return nullptr; }
#endif

}  // namespace svr::relight_avx2
