// Shear-warp's kernels for CPUs with AVX2 and FMA: the same loop (shearwarp_kernel.h), compiled
// through a target attribute rather than per-file flags, as the raycaster's are
// (raycast_kernel_avx2.cpp), so that nothing AVX2 leaks into other callers. Compiled without
// floating-point contraction (CMakeLists.txt): the gain is the wider, three-operand vector
// code, and fixed-k stays equal to dynamic-k bit for bit.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SVR_SHEARWARP_ISA avx2
#define SVR_SHEARWARP_TARGET __attribute__((target("avx2,fma")))
#include "renderers/shearwarp/shearwarp_kernel.h"

namespace svr::shearwarp::avx2 {
bool compiled() { return true; }
BandFn pick(const KernelKey& key) { return pickKernel(key); }
}  // namespace svr::shearwarp::avx2
#else
#include "renderers/shearwarp/shearwarp_kernels.h"

namespace svr::shearwarp::avx2 {
bool compiled() { return false; }
BandFn pick(const KernelKey&) { return nullptr; }
}  // namespace svr::shearwarp::avx2
#endif
