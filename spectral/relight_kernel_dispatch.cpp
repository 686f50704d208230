// Run-time choice of the relight kernel: the widest instruction set that is compiled in and
// that this CPU has, and the fixed-width instantiation when the plane count has one.
#include "spectral/relight_kernel.h"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

namespace svr {

#if defined(__x86_64__) || defined(__i386__)
namespace {
// F16C from CPUID leaf 1 directly: clang before 15 rejects __builtin_cpu_supports("f16c"),
// and the fuzz preset builds with clang 14.
bool cpuHasF16c() {
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  return __get_cpuid(1, &eax, &ebx, &ecx, &edx) != 0 && (ecx & bit_F16C) != 0;
}
}  // namespace
#endif

const char* toString(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::kPortable: return "portable";
    case KernelIsa::kAvx2: return "avx2";
  }
  return "?";
}

const std::vector<KernelIsa>& availableKernelIsas() {
  static const std::vector<KernelIsa> isas = [] {
    std::vector<KernelIsa> out{KernelIsa::kPortable};
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    if (relight_avx2::compiled() && __builtin_cpu_supports("avx2") &&
        cpuHasF16c() && __builtin_cpu_supports("fma"))
      out.push_back(KernelIsa::kAvx2);
#endif
    return out;
  }();
  return isas;
}

RelightKernelChoice selectRelightKernel(int planes, SampleStorage storage,
                                        RelitEncoding encoding, KernelForce force) {
  const bool fixed = planes >= 1 && planes <= 16 && !force.dynamic_width;
  const int width = fixed ? planes : 0;
  KernelIsa isa = availableKernelIsas().back();
  if (force.isa) {
    for (KernelIsa a : availableKernelIsas())
      if (a == *force.isa) isa = a;
    if (isa != *force.isa) isa = KernelIsa::kPortable;  // asked for one this CPU lacks
  }
  switch (isa) {
    case KernelIsa::kAvx2: return {relight_avx2::pick(width, storage, encoding), isa, fixed};
    case KernelIsa::kPortable: break;
  }
  return {relight_portable::pick(width, storage, encoding), KernelIsa::kPortable, fixed};
}

}  // namespace svr
