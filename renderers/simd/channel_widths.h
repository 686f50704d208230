#pragma once
// The one list of channel counts for which the CPU backends compile a fixed-width inner loop
// (rgb, factor:4/6/8); every other k takes the dynamic-width loop (width 0), which gives the same
// bytes (tests: fixed-k = dynamic-k). Mitsuba keeps one list of variants the same way.

namespace svr {

#define SVR_COMPILED_WIDTHS(X) X(3) X(4) X(6) X(8)

// pick.template operator()<N>() for the compiled width N == k, else with N = 0 (dynamic); with
// dynamic_only, always N = 0. `pick` is a template lambda: []<int N>() { return &kernel<N>; }.
template <class Pick>
auto pickWidth(int k, bool dynamic_only, const Pick& pick) {
  if (!dynamic_only) switch (k) {
#define SVR_WIDTH_CASE(N) \
  case N:                 \
    return pick.template operator()<N>();
      SVR_COMPILED_WIDTHS(SVR_WIDTH_CASE)
#undef SVR_WIDTH_CASE
      default:
        break;
    }
  return pick.template operator()<0>();
}

}  // namespace svr
