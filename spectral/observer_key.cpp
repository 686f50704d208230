#include "spectral/observer_key.h"

#include "spectral/colorimetry.h"

namespace svr {

nlohmann::json observerKey(const Observer& observer) {
  const WavelengthGrid& g = observer.grid();
  const auto& cmf = observer.weightedCmf();
  return {{"grid", {g.start_nm, g.step_nm, g.count}},
          {"cmf", std::vector<double>(cmf.data(), cmf.data() + cmf.size())}};
}

}  // namespace svr
