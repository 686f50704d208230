#include "spectral/wavelength_grid.h"

#include <fmt/format.h>

#include <cmath>

#include "base/error.h"

namespace svr {

std::string WavelengthGrid::describe() const {
  return fmt::format("{}–{} nm at {} nm ({} samples)", start_nm, end_nm(), step_nm, count);
}

void validate(const WavelengthGrid& grid) {
  if (!std::isfinite(grid.start_nm) || grid.start_nm <= 0)
    throw Error(fmt::format("wavelength grid: start must be > 0 nm, got {}", grid.start_nm));
  if (!std::isfinite(grid.step_nm) || grid.step_nm <= 0)
    throw Error(fmt::format("wavelength grid: step must be > 0 nm, got {}", grid.step_nm));
  if (grid.count < 2 || grid.count > 100000)
    throw Error(fmt::format("wavelength grid: count must be in 2..100000, got {}", grid.count));
}

}  // namespace svr
