#pragma once
// The post-illumination inner loop: out[x] = M · (plane_0[x], …, plane_{P-1}[x]) for a 3×P
// matrix M, written as linear float RGB or as 8-bit sRGB. Compiled for every fixed plane count
// in one list (relight_kernel_body.inc) plus a dynamic path, and for two instruction sets
// (portable, AVX2+F16C+FMA); selectRelightKernel picks one at run time.
// Kernels neither throw nor allocate; they report the first non-finite pixel instead.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "spectral/light_independent_image.h"

namespace svr {

enum class RelitEncoding { kLinearFloat, kSrgb8 };

struct RelightJob {
  const void* const* planes = nullptr;  // plane_count pointers, float or half per storage
  int plane_count = 0;
  const float* matrix = nullptr;        // 3×plane_count, row-major
  std::size_t begin = 0, end = 0;       // pixel range
  float* out_float = nullptr;           // interleaved RGB (kLinearFloat)
  std::uint8_t* out_srgb = nullptr;     // interleaved RGB (kSrgb8)
  // kSrgbLutSize entries over linear [0, 1], then kSrgbLutPadding zero bytes so a 4-byte
  // gather at the last entry stays inside.
  const std::uint8_t* srgb_lut = nullptr;
};

inline constexpr int kSrgbLutSize = 1 << 14;
inline constexpr int kSrgbLutPadding = 4;

// Returns the index of the first pixel with a non-finite result, or -1.
using RelightFn = long (*)(const RelightJob&);

// Instruction sets the kernel is compiled for; the fastest one the CPU has is used.
enum class KernelIsa { kPortable, kAvx2 };
const char* toString(KernelIsa isa);
// Compiled in and supported by this CPU, slowest first.
const std::vector<KernelIsa>& availableKernelIsas();

struct RelightKernelChoice {
  RelightFn fn;
  KernelIsa isa;
  bool fixed_width;  // compiled for this plane count, not the dynamic path
};

// The fastest kernel for this CPU and plane count; tests force the dynamic-width path or a
// given instruction set to check that every variant gives the same pixels.
struct KernelForce {
  bool dynamic_width = false;
  std::optional<KernelIsa> isa;
};
RelightKernelChoice selectRelightKernel(int plane_count, SampleStorage storage,
                                        RelitEncoding encoding, KernelForce force = {});

// Whether a renderer whose kernels have an AVX2 compilation (`compiled`: built for this target)
// takes it: this CPU has AVX2 and `force` does not ask for the portable path. The raycaster and
// shear-warp choose their kernels by this.
inline bool takeAvx2Kernels(bool compiled, const KernelForce& force) {
  return compiled && availableKernelIsas().back() == KernelIsa::kAvx2 &&
         force.isa.value_or(KernelIsa::kAvx2) == KernelIsa::kAvx2;
}

// Per-ISA entry points (one translation unit each); width 0 selects the dynamic path.
namespace relight_portable {
RelightFn pick(int width, SampleStorage storage, RelitEncoding encoding);
}
namespace relight_avx2 {
bool compiled();
RelightFn pick(int width, SampleStorage storage, RelitEncoding encoding);
}

}  // namespace svr
