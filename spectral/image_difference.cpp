#include "spectral/image_difference.h"

#include <fmt/format.h>

#include <cmath>

#include "spectral/colorimetry.h"
#include "base/error.h"
#include "spectral/post_illumination.h"

namespace svr {
namespace {

std::vector<float> relitXyz(const LightIndependentImage& image, const ColourModel& model,
                            const Spectrum& light, const std::optional<Spectrum>& background) {
  PostIlluminator post(model);
  post.setLight(light);
  if (background) post.setBackground(model.project(*background));
  std::vector<float> xyz(3 * image.pixels());
  post.relightLinear(image, xyz, RelitSpace::kXyz);
  return xyz;
}

float minTransmittance(const LightIndependentImage& image, int x, int y) {
  float t = 1.0f;
  for (int c = 0; c < image.transmittanceChannels(); ++c)
    t = std::min(t, image.transmittance(c, x, y));
  return t;
}

}  // namespace

ImageDifference compareRelit(const LightIndependentImage& a, const ColourModel& model_a,
                             const LightIndependentImage& b, const ColourModel& model_b,
                             const Spectrum& unit_light, const Xyz& white, double coverage,
                             const std::optional<Spectrum>& background) {
  if (a.width() != b.width() || a.height() != b.height())
    throw Error(fmt::format("compare: images are {}×{} and {}×{}", a.width(), a.height(),
                            b.width(), b.height()));
  if (a.transmittanceChannels() == 0 || b.transmittanceChannels() == 0)
    throw Error("compare: both images need transmittance channels to tell covered pixels");
  const auto xa = relitXyz(a, model_a, unit_light, background);
  const auto xb = relitXyz(b, model_b, unit_light, background);
  if (background) coverage = INFINITY;  // the backdrop is part of the picture
  ImageDifference diff;
  diff.map.assign(a.pixels(), 0.0f);
  std::vector<double> values;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      if (std::min(minTransmittance(a, x, y), minTransmittance(b, x, y)) > coverage) continue;
      const std::size_t i = static_cast<std::size_t>(y) * a.width() + x;
      const Xyz pa(xa[3 * i], xa[3 * i + 1], xa[3 * i + 2]);
      const Xyz pb(xb[3 * i], xb[3 * i + 1], xb[3 * i + 2]);
      const double de = deltaE2000(xyzToLab(pa, white), xyzToLab(pb, white));
      diff.map[i] = static_cast<float>(de);
      values.push_back(de);
    }
  diff.covered = values.size();
  diff.stats = summarize(std::move(values));
  return diff;
}

}  // namespace svr
