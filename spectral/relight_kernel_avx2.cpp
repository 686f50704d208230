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
// gather. The table holds bytes; each lane reads 4 bytes at its entry (the table is padded)
// and the code is the low one (encode8 picks it out).
inline __m256i srgbWords(__m256 v, const std::uint8_t* lut) {
  v = _mm256_min_ps(_mm256_max_ps(v, _mm256_setzero_ps()), _mm256_set1_ps(1.0f));
  // v · scale + 0.5 rounded twice, as the portable path computes it: a fused multiply-add
  // rounds once and lands on the other side of an entry boundary now and then.
  const __m256i idx = _mm256_cvttps_epi32(_mm256_add_ps(
      _mm256_mul_ps(v, _mm256_set1_ps(kSrgbLutSize - 1)), _mm256_set1_ps(0.5f)));
  return _mm256_i32gather_epi32(reinterpret_cast<const int*>(lut), idx, 1);
}
// Eight pixels' linear RGB.
struct Rgb8 {
  __m256 r, g, b;
};

// The eight pixels' sRGB bytes, twelve per 128-bit lane (RGB RGB RGB RGB, then four zeros):
// each gathered table word keeps its code in byte 0, which one byte shuffle per channel moves
// to its place — no masking or shifting of the words.
inline __m256i encode8(const Rgb8& c, const std::uint8_t* lut) {
  constexpr char Z = -1;  // a shuffle index with the top bit set writes a zero byte
  const __m256i to_r = _mm256_setr_epi8(0, Z, Z, 4, Z, Z, 8, Z, Z, 12, Z, Z, Z, Z, Z, Z,
                                        0, Z, Z, 4, Z, Z, 8, Z, Z, 12, Z, Z, Z, Z, Z, Z);
  const __m256i to_g = _mm256_setr_epi8(Z, 0, Z, Z, 4, Z, Z, 8, Z, Z, 12, Z, Z, Z, Z, Z,
                                        Z, 0, Z, Z, 4, Z, Z, 8, Z, Z, 12, Z, Z, Z, Z, Z);
  const __m256i to_b = _mm256_setr_epi8(Z, Z, 0, Z, Z, 4, Z, Z, 8, Z, Z, 12, Z, Z, Z, Z,
                                        Z, Z, 0, Z, Z, 4, Z, Z, 8, Z, Z, 12, Z, Z, Z, Z);
  return _mm256_or_si256(_mm256_shuffle_epi8(srgbWords(c.r, lut), to_r),
                         _mm256_or_si256(_mm256_shuffle_epi8(srgbWords(c.g, lut), to_g),
                                         _mm256_shuffle_epi8(srgbWords(c.b, lut), to_b)));
}

// encode8's 24 bytes written exactly: rows are relit by different threads, so never past.
inline void store24(std::uint8_t* o, __m256i x) {
  const __m128i lo = _mm256_castsi256_si128(x), hi = _mm256_extracti128_si256(x, 1);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(o), lo);
  const int lo_tail = _mm_extract_epi32(lo, 2);
  std::memcpy(o + 8, &lo_tail, 4);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(o + 12), hi);
  const int hi_tail = _mm_extract_epi32(hi, 2);
  std::memcpy(o + 20, &hi_tail, 4);
}

inline void encodeSrgbChunk(const float* r, const float* g, const float* b, int n,
                            std::uint8_t* out, const std::uint8_t* lut) {
  int i = 0;
  for (; i + 8 <= n; i += 8)
    store24(out + 3 * i,
            encode8({_mm256_loadu_ps(r + i), _mm256_loadu_ps(g + i), _mm256_loadu_ps(b + i)}, lut));
  encodeSrgbWithTable(r + i, g + i, b + i, n - i, out + 3 * i, lut);
}
#include "spectral/relight_kernel_body.inc"

// The relit linear RGB of eight pixels, from P float planes.
template <int P>
inline Rgb8 relit8(const RelightJob& job, const __m256* mr, const __m256* mg,
                        const __m256* mb, std::size_t i) {
  Rgb8 o{_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
  for (int p = 0; p < P; ++p) {
    const __m256 v = _mm256_loadu_ps(static_cast<const float*>(job.planes[p]) + i);
    o.r = _mm256_fmadd_ps(mr[p], v, o.r);
    o.g = _mm256_fmadd_ps(mg[p], v, o.g);
    o.b = _mm256_fmadd_ps(mb[p], v, o.b);
  }
  return o;
}

// r + g + b is finite exactly when all three are (an Inf stays Inf or meets −Inf in a NaN, a
// NaN stays NaN; relit values are far below float's overflow), and x − x is NaN exactly for
// NaN and ±Inf: one test for the three channels (and, summed again, for sixteen pixels).
inline __m256 sum8(const Rgb8& c) {
  return _mm256_add_ps(_mm256_add_ps(c.r, c.g), c.b);
}
inline bool finite(__m256 sum) {
  const __m256 zero_or_nan = _mm256_sub_ps(sum, sum);
  return _mm256_movemask_ps(_mm256_cmp_ps(zero_or_nan, zero_or_nan, _CMP_UNORD_Q)) == 0;
}

// The common case fused: float planes to sRGB8, kept in registers from the loads through the
// matrix, the finiteness test and the encoding to the byte stores (the general body
// round-trips every chunk through a buffer); sixteen pixels a step, written as three whole
// 16-byte stores, then eight. Rows that do not fill the last eight pixels, and any row holding
// a non-finite value, go through the general body.
template <int P>
long relightFusedSrgb(const RelightJob& job) {
  const float* m = job.matrix;
  __m256 mr[P], mg[P], mb[P];
  for (int p = 0; p < P; ++p) {
    mr[p] = _mm256_set1_ps(m[p]);
    mg[p] = _mm256_set1_ps(m[P + p]);
    mb[p] = _mm256_set1_ps(m[2 * P + p]);
  }
  std::size_t i = job.begin;
  for (; i + 16 <= job.end; i += 16) {
    const Rgb8 first = relit8<P>(job, mr, mg, mb, i);
    const Rgb8 second = relit8<P>(job, mr, mg, mb, i + 8);
    // One test for both: a non-finite value in either makes the sum of sums non-finite.
    if (!finite(_mm256_add_ps(sum8(first), sum8(second)))) break;  // the body reports it
    const __m256i x = encode8(first, job.srgb_lut), y = encode8(second, job.srgb_lut);
    // Four 12-byte groups a, b, c, d into 48 contiguous bytes (exactly: rows are relit by
    // different threads, so never write past).
    const __m128i a = _mm256_castsi256_si128(x), b = _mm256_extracti128_si256(x, 1);
    const __m128i c = _mm256_castsi256_si128(y), d = _mm256_extracti128_si256(y, 1);
    __m128i* o = reinterpret_cast<__m128i*>(job.out_srgb + 3 * i);
    _mm_storeu_si128(o, _mm_or_si128(a, _mm_slli_si128(b, 12)));
    _mm_storeu_si128(o + 1, _mm_or_si128(_mm_srli_si128(b, 4), _mm_slli_si128(c, 8)));
    _mm_storeu_si128(o + 2, _mm_or_si128(_mm_srli_si128(c, 8), _mm_slli_si128(d, 4)));
  }
  if (i + 8 <= job.end) {
    const Rgb8 last = relit8<P>(job, mr, mg, mb, i);
    if (finite(sum8(last))) {
      store24(job.out_srgb + 3 * i, encode8(last, job.srgb_lut));
      i += 8;
    }
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
