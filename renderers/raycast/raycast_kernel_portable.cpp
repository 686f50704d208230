// The raycaster's kernels for any CPU (the compiler's baseline instruction set).
#define SVR_RAYCAST_ISA portable
#define SVR_RAYCAST_AVX2 0
#include "renderers/raycast/raycast_kernel.h"

namespace svr::raycast::portable {
TileFn pick(const KernelKey& key) { return pickKernel(key); }
}  // namespace svr::raycast::portable
