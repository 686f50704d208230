#pragma once
// The interface every backend implements (design.md §3, §5): the same classified volume, camera
// and shading in; the same light-independent k-channel image out (S, and T for the backdrop).
// Backends differ only in how they sample and composite.
//
// Renderer::render is the one entry, and it is not virtual (pbrt's Render / Li split): it checks
// the request against what the backend supports, reads the backend's options against its
// description, drives progress, calls the backend's renderImpl, and runs the finite check,
// which names backend, channel and pixel. A backend writes renderImpl, and may take over the
// finite check (requireFinite) where its last pass checks every sample as it writes it.

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "renderers/render/backend_info.h"
#include "renderers/scene/camera.h"
#include "renderers/classification/classification.h"
#include "renderers/volume/memory_budget.h"
#include "renderers/render/progress_counter.h"
#include "renderers/scene/scene.h"
#include "spectral/light_independent_image.h"

namespace svr {

class FrontTransmittance;

struct RenderRequest {
  const ClassifiedVolume& volume;
  Camera camera;
  int width = 512, height = 512;
  Shading shading;
  std::optional<glm::dvec3> light_direction;  // towards the light; empty = headlight
  double termination = 0.01;  // early termination when max T < this; 0 = off
  bool empty_space_skipping = true;
  // Backend options, keyed by backend name: {"splat": {"mode": "sheet"}}. Each backend reads
  // its own object against its description (unknown keys are errors) and ignores the others',
  // so one set of options can drive a comparison across every backend.
  nlohmann::json options = nlohmann::json::object();
  // Names the options' source in errors: "scene.json: render.options".
  std::string options_source = "render.options";
  // The image and the backend's working memory must fit (checked before allocating).
  std::uint64_t memory_budget = defaultMemoryBudget();
  // Told what a user should know about how the frame was made (a slower fallback taken because
  // something did not fit); empty: not told.
  std::function<void(const std::string&)> note;
  // A brick of a distributed render: the transmittance of the bricks in front, block by block,
  // for backends that support it (BackendCapabilities::front_transmittance); null: none.
  FrontTransmittance* front = nullptr;
  // Set from any thread (the Python module's Ctrl-C) to stop the render early: render() then
  // throws svr::Cancelled instead of returning a partial image. Null: the render runs to the end.
  const std::atomic<bool>* stop = nullptr;
};

class Renderer {
 public:
  virtual ~Renderer() = default;
  virtual const BackendInfo& info() const = 0;
  std::string name() const { return info().name; }

  // Throws svr::Error for a request the backend does not support, bad options, or a non-finite
  // value in the image; svr::Cancelled when request.stop was set during the render.
  LightIndependentImage render(const RenderRequest& request,
                               const ProgressFn& progress = nullptr) const;

  // Bricks of a distributed render (request.volume.brick) composite in the space render()
  // returns them in; this makes the final image from the composited one. The final image
  // itself for most backends (the default); shear-warp composites its sheared intermediate
  // images, as the over operator does not commute with the warp's resampling, and warps once.
  virtual LightIndependentImage finishBricks(LightIndependentImage composited,
                                             const RenderRequest& request) const {
    return composited;
  }

 protected:
  // Bytes the backend allocates beyond the output image for this request (intermediate
  // images, sheet buffers), for the memory-budget check.
  virtual std::uint64_t workingBytes(const RenderRequest& request,
                                     const BackendOptions& options) const {
    return 0;
  }
  virtual LightIndependentImage renderImpl(const RenderRequest& request,
                                           const BackendOptions& options,
                                           ProgressCounter& progress) const = 0;
  // Throws svr::Error naming the backend, channel and pixel of the first NaN or ±Inf sample.
  // render() calls it on every image renderImpl returns. A backend that checks its samples as
  // it writes them (shear-warp's warp: a second pass over a 7-plane 800² image was 9 % of a
  // frame) overrides it to skip those images, and calls Renderer::requireFinite itself for an
  // image that failed, for the message.
  virtual void requireFinite(const LightIndependentImage& image,
                             const RenderRequest& request) const;
};

}  // namespace svr
