#pragma once
// The interface every backend implements (DESIGN §3, §5): the same classified volume, camera
// and shading in; the same light-independent k-channel image out (S, and T for the backdrop).
// Backends differ only in how they sample and composite.

#include <functional>
#include <memory>
#include <string>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "renderers/core/camera.h"
#include "renderers/core/classification.h"
#include "renderers/core/scene.h"
#include "spectral/light_independent_image.h"

namespace svr {

struct RenderRequest {
  const ClassifiedVolume& volume;
  Camera camera;
  int width = 512, height = 512;
  Shading shading;
  std::optional<glm::dvec3> light_direction;  // towards the light; empty = headlight
  double termination = 0.01;  // early termination when max T < this; 0 = off
  bool empty_space_skipping = true;
  // Backend options, keyed by backend name: {"splat": {"mode": "sheet"}}. Each backend reads
  // its own object (through a JsonReader, so unknown keys are errors) and ignores the others',
  // so one set of options can drive a comparison across every backend.
  nlohmann::json options = nlohmann::json::object();
};

// Called with the fraction done, from one thread, often enough for a progress bar.
using ProgressFn = std::function<void(double)>;

class Renderer {
 public:
  virtual ~Renderer() = default;
  virtual std::string name() const = 0;
  virtual LightIndependentImage render(const RenderRequest& request,
                                       const ProgressFn& progress) const = 0;
};

}  // namespace svr
