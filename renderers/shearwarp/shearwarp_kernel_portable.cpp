// Shear-warp's kernels for any CPU (the compiler's baseline instruction set).
#define SVR_SHEARWARP_ISA portable
#include "renderers/shearwarp/shearwarp_kernel.h"

namespace svr::shearwarp::portable {
BandFn pick(const KernelKey& key) { return pickKernel(key); }
}  // namespace svr::shearwarp::portable
