// The raycaster's kernels for CPUs with AVX2 and FMA: the same loop (raycast_kernel.h), compiled
// through a target attribute rather than per-file flags, so that the inline library code it
// calls out of line (std::, glm) stays baseline and nothing AVX2 leaks into other callers.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SVR_RAYCAST_ISA avx2
#define SVR_RAYCAST_AVX2 1
#define SVR_RAYCAST_TARGET __attribute__((target("avx2,fma")))
#include "renderers/raycast/raycast_kernel.h"

namespace svr::raycast::avx2 {
bool compiled() { return true; }
TileFn pick(const KernelKey& key) { return pickKernel(key); }
}  // namespace svr::raycast::avx2
#else
#include "renderers/raycast/raycast_kernels.h"

namespace svr::raycast::avx2 {
bool compiled() { return false; }
TileFn pick(const KernelKey&) { return nullptr; }
}  // namespace svr::raycast::avx2
#endif
