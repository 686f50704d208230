#include "renderers/shearwarp/shearwarp_renderer.h"

#include <fmt/format.h>
#include <omp.h>

#include <atomic>
#include <optional>
#include <utility>
#include <cmath>
#include <glm/geometric.hpp>

#include "renderers/shearwarp/intermediate_warp.h"
#include "renderers/shearwarp/shear_warp_factorization.h"
#include "renderers/shearwarp/shearwarp_kernels.h"
#include "base/error.h"
#include "renderers/render/backend_entry.h"
#include "renderers/shearwarp/rle_volume.h"

namespace svr {
namespace {

constexpr int kMaxSupersample = 4;

// The kernel for this CPU, chosen once per render: AVX2 where the CPU has it (and FMA) and the
// portable path is not forced (as the raycaster chooses); the portable compilation otherwise.
shearwarp::BandFn pickKernel(const shearwarp::KernelKey& key, const KernelForce& force) {
  return takeAvx2Kernels(shearwarp::avx2::compiled(), force) ? shearwarp::avx2::pick(key)
                                                              : shearwarp::portable::pick(key);
}

// The range of the transmission coefficients (factor models may leave [0, 1]) and 1.
std::pair<float, float> transmissionRange(const ClassifiedVolume& cv) {
  float lo = 1.f, hi = 1.f;
  for (float t : cv.transmission) lo = std::min(lo, t), hi = std::max(hi, t);
  return {std::min(lo, 0.f), hi};
}


}  // namespace

const BackendInfo& ShearWarpRenderer::info() const {
  static const BackendInfo info{
      "shearwarp", "Lacroute & Levoy shear-warp over run-length-encoded classified slices",
      {.perspective = false, .spectral_transmittance = true,
       .max_channels = shearwarp::kMaxChannels, .bricks = true},
      {OptionSpec::integer("supersample", 0, 0, kMaxSupersample,
                           "intermediate pixels per voxel along each slice axis: 0 (auto) "
                           "follows the screen, as many as the final pixels a voxel spans (no "
                           "blur under zoom, for time); 1 is volume resolution"),
       OptionSpec::integer("slice_samples", 0, 0, shearwarp::RleVolume::kMaxSliceSamples,
                           "samples per voxel slice along the ray, trilinear between slices: "
                           "0 (auto) takes enough that they are no farther apart than "
                           "render.step, as the raycaster's; 1 samples each slice once "
                           "(Lacroute & Levoy, VolPack). Label maps and classification=pre "
                           "take 1"),
       OptionSpec::choice("classification", {"post", "pre"},
                          "post: classify and shade each sample's interpolated value; pre: "
                          "classify and quantise normals at the voxels, interpolate the "
                          "classified voxels and shade from a table per view (VolPack's method: "
                          "faster, less accurate at material edges)")}};
  return info;
}

namespace {

// The grid the view is factorised for: the whole volume's, for a brick.
const Dims& viewDims(const ClassifiedVolume& cv) { return cv.brick ? cv.brick->whole : cv.dims; }

// The view's factorisation at the option's supersample, or for 0 (auto) at the screen's.
shearwarp::ShearWarpFactorization factorizeRequest(const RenderRequest& req,
                                                   const BackendOptions& options) {
  const ClassifiedVolume& cv = req.volume;
  const auto at = [&](int scale) {
    return shearwarp::factorizeView(req.camera, req.width, req.height, viewDims(cv), cv.spacing,
                                    scale);
  };
  const int asked = options.integer("supersample");
  if (asked > 0) return at(asked);
  const shearwarp::ShearWarpFactorization volume_resolution = at(1);
  const int scale = shearwarp::supersampleForScreen(volume_resolution, kMaxSupersample);
  return scale == 1 ? volume_resolution : at(scale);
}

// The samples per voxel slice: the option's, or for 0 (auto) enough for the render step.
// Label maps and pre-classified records cannot be interpolated between slices.
int sliceSamples(const ClassifiedVolume& cv, const shearwarp::ShearWarpFactorization& view,
                 const BackendOptions& options) {
  const int asked = options.integer("slice_samples");
  const bool pre = options.choice("classification") == "pre";
  if (asked == 0)
    return cv.labels || pre ? 1
                            : shearwarp::sliceSamplesForStep(
                                  view, cv.step_world, shearwarp::RleVolume::kMaxSliceSamples);
  if (asked > 1 && pre)
    throw Error(fmt::format("shearwarp: slice_samples {} needs classification=post (pre-classified "
                            "records are not interpolated between slices); use 0 or 1",
                            asked));
  return asked;  // a label map's > 1 is refused by its encoding, with the reason
}

// A brick's place in the whole grid and its own samples (CompositeJob's fields): its own voxel
// slices [lo, hi) and the slices between each and the next.
void placeBrick(const ClassifiedVolume& cv, int axis, shearwarp::CompositeJob& job,
                int slices) {
  job.slice_begin = 0, job.slice_end = slices;
  if (!cv.brick) return;
  const int m = job.view->slice_samples;
  const VolumeBrick& b = *cv.brick;
  for (int a = 0; a < 3; ++a) {
    job.origin[a] = b.stored.lo[a];
    if (b.own.lo[a] > 0) job.lo[a] = b.own.lo[a];
    if (b.own.hi[a] < b.whole[a]) job.hi[a] = b.own.hi[a];
  }
  job.slice_begin = (b.own.lo[axis] - b.stored.lo[axis]) * m;
  job.slice_end = std::min((b.own.hi[axis] - b.stored.lo[axis]) * m, slices);
}

// The intermediate image as a light-independent image of its size (planar), and back.
LightIndependentImage planarOf(const shearwarp::IntermediateImage& im) {
  LightIndependentImage out(im.width, im.height, im.s_channels, im.t_channels);
  const int planes = im.channels();
  const std::size_t n = out.pixels();
  for (int p = 0; p < planes; ++p) {
    float* plane = out.planeFloat(p).data();
    for (std::size_t i = 0; i < n; ++i) plane[i] = im.data[i * im.stride + p];
  }
  return out;
}

}  // namespace

LightIndependentImage ShearWarpRenderer::finishBricks(LightIndependentImage composited,
                                                      const RenderRequest& req) const {
  const ClassifiedVolume& cv = req.volume;
  const BackendOptions options = readBackendOptions(info().options, req.options, info().name,
                                                    req.options_source);
  const shearwarp::ShearWarpFactorization view = factorizeRequest(req, options);
  shearwarp::IntermediateImage intermediate(view.width, view.height, cv.k, cv.t_channels);
  if (composited.width() != view.width || composited.height() != view.height)
    throw Error(fmt::format("shearwarp: composited bricks are {}×{}, the view's intermediate "
                            "image {}×{}",
                            composited.width(), composited.height(), view.width, view.height));
  const int planes = intermediate.channels();
  const std::size_t n = composited.pixels();
  for (int p = 0; p < planes; ++p) {
    const float* plane = composited.planeFloat(p).data();
    for (std::size_t i = 0; i < n; ++i) intermediate.data[i * intermediate.stride + p] = plane[i];
  }
  intermediate.touchAll();
  return warped(intermediate, view, req);
}

LightIndependentImage ShearWarpRenderer::warped(const shearwarp::IntermediateImage& intermediate,
                                                const shearwarp::ShearWarpFactorization& view,
                                                const RenderRequest& req) const {
  LightIndependentImage image = LightIndependentImage::unset(
      req.width, req.height, req.volume.k, req.volume.t_channels);
  // Writes every sample, and checks each as it does (requireFinite, below, need not).
  if (!shearwarp::warpToFinal(intermediate, view, image)) Renderer::requireFinite(image, req);
  return image;
}

std::uint64_t ShearWarpRenderer::workingBytes(const RenderRequest& req,
                                              const BackendOptions& options) const {
  const ClassifiedVolume& cv = req.volume;
  const shearwarp::ShearWarpFactorization view = factorizeRequest(req, options);
  return std::uint64_t(view.width) * std::uint64_t(view.height) *
         std::uint64_t(shearwarp::IntermediateImage::strideFor(cv.k, cv.t_channels)) *
         sizeof(float);
}

LightIndependentImage ShearWarpRenderer::renderImpl(const RenderRequest& req,
                                                    const BackendOptions& options,
                                                    ProgressCounter& progress) const {
  const ClassifiedVolume& cv = req.volume;
  const std::shared_ptr<const shearwarp::RleVolume> encoded = shearwarp::RleVolume::of(cv);
  shearwarp::ShearWarpFactorization view = factorizeRequest(req, options);
  shearwarp::sampleBetweenSlices(view, sliceSamples(cv, view, options));
  const shearwarp::AxisEncoding& encoding = encoded->encoding(view.axis, view.slice_samples);

  // Opacity and transmission for the slice spacing instead of the classification step: of the
  // entries (post-classified), or of each sample's interpolated α and t (pre-classified).
  const double ratio = view.slice_spacing_world / cv.step_world;
  const bool pre = options.choice("classification") == "pre";
  std::optional<shearwarp::SliceTable> table;
  if (!pre) {
    std::vector<float> alpha(cv.entries), transmission(cv.transmission.size());
    for (int e = 0; e < cv.entries; ++e)
      alpha[e] = 1.f - shearwarp::signedPow(1.f - cv.alpha[e], ratio);
    for (std::size_t i = 0; i < transmission.size(); ++i)
      transmission[i] = shearwarp::signedPow(cv.transmission[i], ratio);
    table.emplace(cv, alpha, transmission);
  }

  const RayGenerator rays(req.camera, req.width, req.height);
  const glm::dvec3 view_dir = -rays.forward();
  const glm::dvec3 light = req.light_direction ? glm::normalize(*req.light_direction) : view_dir;
  const glm::dvec3 half = glm::normalize(light + view_dir);

  const auto pooled = pool_.take();
  pooled->resize(view.width, view.height, cv.k, cv.t_channels);  // each band clears its rows
  shearwarp::IntermediateImage& intermediate = *pooled;
  shearwarp::CompositeJob job{&cv,
                              &encoding,
                              &view,
                              table ? &*table : nullptr,
                              static_cast<float>(req.termination),
                              PhongSetup(req.shading, light, half),
                              &intermediate};
  placeBrick(cv, view.axis, job, encoding.slices());
  std::shared_ptr<const shearwarp::PreclassifiedAxis> preclassified;
  std::optional<shearwarp::ShadingTable> shading;
  std::optional<shearwarp::PowerTable> opacity_power, transmission_power;
  if (pre) {
    preclassified = shearwarp::PreclassifiedAxis::of(cv, view.axis);
    shading.emplace(job.phong);
    opacity_power.emplace(0.f, 1.f, ratio);
    const auto [t_lo, t_hi] = transmissionRange(cv);
    transmission_power.emplace(t_lo, t_hi, ratio);
    job.pre = preclassified.get();
    job.shading = &*shading;
    job.opacity_power = &*opacity_power;
    job.transmission_power = &*transmission_power;
  }
  const shearwarp::BandFn fn = pickKernel(
      {.k = cv.k, .spectral_t = cv.t_channels > 1, .pre = pre, .dynamic_width = force_.dynamic_width},
      force_);
  // Bands of kBand scanlines (compositeBand); dynamic over bands, as opaque regions end some
  // bands early.
  constexpr int kBand = 16;
  const int bands = (view.height + kBand - 1) / kBand;
  progress.stage(bands, 0.0, 0.95);
#pragma omp parallel
  {
    std::vector<int> links;
#pragma omp for schedule(dynamic)
    for (int b = 0; b < bands; ++b) {
      if (progress.stopped()) continue;  // the rest is skipped, then Cancelled
      const int v0 = b * kBand, v1 = std::min((b + 1) * kBand, view.height);
      intermediate.clearRows(v0, v1);
      fn(job, v0, v1, links);
      progress.advance();
    }
  }

  LightIndependentImage image;
  if (cv.brick) {
    image = planarOf(intermediate);  // composited with the other bricks, then finishBricks
  } else {
    image = warped(intermediate, view, req);
  }
  return image;
}

void ShearWarpRenderer::requireFinite(const LightIndependentImage& image,
                                      const RenderRequest& req) const {
  // A whole volume's image was checked by the warp that wrote it; a brick's (the intermediate
  // image, planar) is checked here.
  if (req.volume.brick) Renderer::requireFinite(image, req);
}

ShearWarpRenderer::ShearWarpRenderer(KernelForce force) : force_(force) {}
ShearWarpRenderer::~ShearWarpRenderer() = default;

namespace backends {
BackendEntry shearwarp() {
  return {ShearWarpRenderer().info(), [] { return std::make_unique<ShearWarpRenderer>(); }, {}, {}};
}
}  // namespace backends

}  // namespace svr
