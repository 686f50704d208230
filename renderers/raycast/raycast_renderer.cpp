#include "renderers/raycast/raycast_renderer.h"

#include <fmt/format.h>

#include "renderers/render/front_transmittance.h"
#include "renderers/raycast/raycast_kernels.h"
#include "renderers/render/backend_entry.h"
#include "base/error.h"

namespace svr {
namespace {

// The kernel for this CPU, chosen here once per render: AVX2 + FMA where the CPU has them
// (spectral's availableKernelIsas, the relight kernel's test) and the portable path is not
// forced; the portable compilation otherwise.
raycast::TileFn pickKernel(const raycast::KernelKey& key, const KernelForce& force) {
  return takeAvx2Kernels(raycast::avx2::compiled(), force) ? raycast::avx2::pick(key)
                                                            : raycast::portable::pick(key);
}

// Both kernels hold a cell's corner offsets as 32-bit integers (the AVX2 gathers take them as
// lanes): one slice and a row more must stay below 2³¹ voxels.
void checkSliceSize(const Dims& dims) {
  const double corner = static_cast<double>(dims[0]) * dims[1] + dims[0] + 1;
  if (corner > 2147483647.0)
    throw Error(fmt::format("raycast: a slice of {}×{} voxels is over the 2³¹ voxels its cell "
                            "offsets can address",
                            dims[0], dims[1]));
}

// The precomputed gradients, or null for on-the-fly central differences.
std::shared_ptr<const GradientVolume> gradientsFor(const RenderRequest& req,
                                                   const std::string& mode) {
  const ClassifiedVolume& cv = req.volume;
  if (mode == "on-the-fly") return nullptr;
  // auto: the cheaper way to make this one frame. Building the gradients costs about what on-
  // the-fly gradients cost over kVoxelsPerPixel voxels a pixel (engine, 8.4 M voxels, 2 threads:
  // build + frame = 93 / 173 ms against 41 / 159 ms on the fly at 256² / 512²; break-even near
  // 560²). A caller that renders many frames of one classification (a viewer, the benches)
  // asks for "precomputed": the gradients are built once and kept with the classification.
  constexpr double kVoxelsPerPixel = 24.0;
  // A brick decides as the whole volume would, so that it renders the same samples the same way.
  const Dims& d = cv.brick ? cv.brick->whole : cv.dims;
  const double voxels = static_cast<double>(d[0]) * d[1] * d[2];
  if (mode == "auto" && static_cast<double>(req.width) * req.height * kVoxelsPerPixel < voxels)
    return nullptr;
  return gradientsWithinBudget(req, mode == "precomputed", "raycast");
}

}  // namespace

const BackendInfo& RaycastRenderer::info() const {
  static const BackendInfo info{
      "raycast",
      "a ray per pixel, trilinear samples, Phong; the reference backend",
      {.perspective = true, .spectral_transmittance = true, .max_channels = raycast::kMaxChannels,
       .bricks = true,
       .front_transmittance = true,
       .reference = true},
      {OptionSpec::choice("gradients", {"auto", "precomputed", "on-the-fly"},
                          "normals from gradients precomputed at the voxels (8 bytes a voxel, "
                          "kept with the classification) or central differences per sample; "
                          "auto: whichever makes one frame faster (precomputed from about one "
                          "pixel per 24 voxels), when they fit the memory budget; ask for "
                          "precomputed when rendering many frames")}};
  return info;
}

namespace {
constexpr int kTile = 16;

// The tiles of job's rectangle, in parallel.
void traceTilesOf(const raycast::TileJob& job, raycast::TileFn fn, ProgressCounter& progress) {
  const int tiles_x = (job.x1 - job.x0 + kTile - 1) / kTile;
  const int tiles = tiles_x * ((job.y1 - job.y0 + kTile - 1) / kTile);
#pragma omp parallel for schedule(dynamic)
  for (int t = 0; t < tiles; ++t) {
    if (progress.stopped()) continue;  // the rest is skipped, then Cancelled
    raycast::TileJob tile = job;
    tile.x0 = job.x0 + t % tiles_x * kTile, tile.y0 = job.y0 + t / tiles_x * kTile;
    tile.x1 = std::min(tile.x0 + kTile, job.x1), tile.y1 = std::min(tile.y0 + kTile, job.y1);
    fn(tile);
    progress.advance();
  }
}

void traceTiles(const raycast::TileJob& job, raycast::TileFn fn, ProgressCounter& progress) {
  progress.stage(((job.x1 + kTile - 1) / kTile) * ((job.y1 + kTile - 1) / kTile));
  traceTilesOf(job, fn, progress);
}

// A brick with bricks in front: the blocks as the exchange gives them, each with the
// transmittance in front of it, passed on once done. The threads share a block at a time, so
// the calls into the exchange (MPI in svr-mpi) stay on this thread.
void traceBlocks(const raycast::TileJob& job, raycast::TileFn fn, FrontTransmittance& exchange,
                 ProgressCounter& progress) {
  constexpr int n = FrontTransmittance::kBlock;
  const int blocks_x = FrontTransmittance::blocksAcross(job.x1);
  progress.stage(static_cast<long>(exchange.blocks()) * (n / kTile) * (n / kTile));
  // Blocks the exchange never gives hold none of the brick's samples: S = 0, T = 1 there.
  LightIndependentImage& image = *job.image;
  for (int c = 0; c < image.transmittanceChannels(); ++c) {
    const auto plane = image.planeFloat(image.channels() + c);
    std::fill(plane.begin(), plane.end(), 1.f);
  }
  for (int b; (b = exchange.next()) >= 0;) {
    raycast::TileJob block = job;
    block.x0 = b % blocks_x * n, block.y0 = b / blocks_x * n;
    block.x1 = std::min(block.x0 + n, job.x1), block.y1 = std::min(block.y0 + n, job.y1);
    block.front = exchange.front(b);
    block.front_x0 = block.x0, block.front_y0 = block.y0;
    traceTilesOf(block, fn, progress);
    exchange.finished(b, *job.image);
  }
  exchange.done();
}

}  // namespace

LightIndependentImage RaycastRenderer::renderImpl(const RenderRequest& req,
                                                  const BackendOptions& options,
                                                  ProgressCounter& progress) const {
  const ClassifiedVolume& cv = req.volume;
  checkSliceSize(cv.dims);
  const auto gradients = gradientsFor(req, options.choice("gradients"));
  const auto table = raycast::sampleTableOf(cv);
  const auto occupancy = occupancyOf(cv);
  LightIndependentImage image(req.width, req.height, cv.k, cv.t_channels);
  const RayGenerator rays(req.camera, req.width, req.height);
  const raycast::TileFn fn = pickKernel(
      {.k = cv.k, .t_channels = cv.t_channels, .precomputed_gradients = gradients != nullptr,
       .dynamic_width = force_.dynamic_width},
      force_);
  const raycast::TileJob job{&cv, gradients.get(), table.get(), occupancy.get(), &rays, &req,
                             &image, 0, 0, req.width, req.height};
  if (req.front)
    traceBlocks(job, fn, *req.front, progress);
  else
    traceTiles(job, fn, progress);
  return image;
}

namespace backends {
BackendEntry raycast() {
  return {RaycastRenderer().info(), [] { return std::make_unique<RaycastRenderer>(); }, {}, {}};
}
}  // namespace backends

}  // namespace svr
