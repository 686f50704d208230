// Our shear-warp against VolPack (Lacroute's shear-warp library, Debian libvolpack1-dev) on the
// engine scene, one run, orthographic, elevation 30°, azimuths including both sides of the 45°
// principal-axis switch, at 512² and 800²:
//   VolPack/<grey|rgb>/<size>/az<deg>         vpShadeTable + vpRenderClassifiedVolume
//   Shearwarp/<rgb|factor:6>/<size>/az<deg>   ShearWarpRenderer::render with the encoding built
//   ShearwarpPre/<rgb|factor:6>/<size>/az<deg> the same with shearwarp.classification=pre
//                                              (VolPack's pre-classified method)
// Both classify once outside the timed loop (VolPack: vpClassifyScalars into its run-length
// encoded volume; ours: classify + RleVolume::buildAll), as a viewer does while only the view
// changes. VolPack is single-threaded: run this with OMP_NUM_THREADS=1 for equal threads
// (bench/peers/run does, and adds our rows at 2 threads).
//
// What matches: one sample per slice at volume resolution (shearwarp.slice_samples=1,
// supersample=1), the volume (our loader), the opacity per unit length at every 8-bit value (from
// our classification: peer_scene.h), the early-termination threshold (ray opacity 0.99 = T <
// 0.01), the camera (orthographic, same framing), the light direction, two-sided lighting and
// the Phong model: VolPack's lookup shader is given four "materials" — red, green and blue
// diffuse (ambient 0.3, diffuse 0.7) and a white specular (0.4, exponent 24) — weighted per value
// by our rgb reflectance and specular weight, so colour = ρ ⊙ (0.3 + 0.7 |n·l|) + 0.4 s |n·h|^24
// as in classified_sample.h (grey: luminance of ρ and the specular "material").
// What does not: VolPack classifies and shades at the voxels (8-bit opacity, 13-bit quantised
// normals, a lookup table per view) and resamples the shaded colours; we interpolate the value
// and classify and shade every sample (float, k channels, exact normals), then keep a
// light-independent k-channel image rather than 8-bit RGB.
//
// --images=DIR writes each view once as PPM (VolPack's image; ours: S of the rgb model under
// flat white light, linear 8-bit like VolPack's) to check that the two frame and light the volume
// alike.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <volpack.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/peers/peer_scene.h"
#include "renderers/shearwarp/rle_volume.h"
#include "renderers/shearwarp/shearwarp_renderer.h"
#include "base/error.h"

namespace svr::peers {
namespace {

// The fields vpClassifyScalars fills: shading reads the normal and the value (the weight
// index); classification reads the value; the gradient magnitude is computed but unused.
struct Voxel {
  std::uint16_t normal;
  std::uint8_t value;
  std::uint8_t gradient;
};
constexpr int kNormalField = 0, kValueField = 1, kGradientField = 2;

void check(vpContext* vpc, vpResult r, const char* call) {
  if (r != VP_OK)
    throw Error(fmt::format("volpack: {} failed: {}", call, vpGetErrorString(vpGetError(vpc))));
}

// One VolPack context holding the classified engine, shaded grey (1 channel) or RGB.
class VolPackScene {
 public:
  explicit VolPackScene(int channels)
      : channels_(channels), context_(vpCreateContext(), vpDestroyContext), vpc_(context_.get()) {
    const Scene& scene = engineBenchScene().scene;
    const Volume& volume = scene.volume;
    if (volume.type() != ScalarType::kUint8)
      throw Error("volpack bench: the engine volume must be uint8");
    const Dims& d = volume.dims();
    max_dim_ = std::max({d[0], d[1], d[2]});
    check(vpc_, vpSetVolumeSize(vpc_, d[0], d[1], d[2]), "vpSetVolumeSize");
    check(vpc_, vpSetVoxelSize(vpc_, sizeof(Voxel), 3, 2, 1), "vpSetVoxelSize");
    check(vpc_, vpSetVoxelField(vpc_, kNormalField, 2, offsetof(Voxel, normal), VP_NORM_MAX),
          "vpSetVoxelField(normal)");
    check(vpc_, vpSetVoxelField(vpc_, kValueField, 1, offsetof(Voxel, value), VP_SCALAR_MAX),
          "vpSetVoxelField(value)");
    check(vpc_,
          vpSetVoxelField(vpc_, kGradientField, 1, offsetof(Voxel, gradient), VP_GRAD_MAX),
          "vpSetVoxelField(gradient)");

    const ValueTables t = engineValueTables();
    opacity_.assign(t.opacity.begin(), t.opacity.end());
    check(vpc_,
          vpSetClassifierTable(vpc_, 0, kValueField, opacity_.data(),
                               static_cast<int>(opacity_.size() * sizeof(float))),
          "vpSetClassifierTable");
    // Keep every voxel whose opacity survives VolPack's 8-bit quantisation: our encoding drops
    // only exactly transparent cells.
    check(vpc_, vpSetd(vpc_, VP_MIN_VOXEL_OPACITY, 0.5 / 255.0), "vpSetd(MIN_VOXEL_OPACITY)");
    auto* bytes = reinterpret_cast<unsigned char*>(const_cast<std::byte*>(volume.data().data()));
    check(vpc_,
          vpClassifyScalars(vpc_, bytes, static_cast<int>(volume.bytes()), kValueField,
                            kGradientField, kNormalField),
          "vpClassifyScalars");

    // Materials: RGB = {red, green, blue diffuse, white specular}; grey = {diffuse, specular}.
    const Shading& sh = scene.shading;
    materials_ = channels == 3 ? 4 : 2;
    const int specular_material = materials_ - 1;
    weights_.resize(256 * materials_);
    for (int v = 0; v < 256; ++v) {
      float* w = &weights_[v * materials_];
      if (channels == 3) {
        for (int c = 0; c < 3; ++c) w[c] = t.rgb[v][c];
      } else {
        w[0] = 0.2126f * t.rgb[v][0] + 0.7152f * t.rgb[v][1] + 0.0722f * t.rgb[v][2];
      }
      w[specular_material] = t.specular[v];
    }
    colours_.resize(static_cast<std::size_t>(VP_NORM_MAX + 1) * materials_ * channels);
    check(vpc_,
          vpSetLookupShader(vpc_, channels, materials_, kNormalField, colours_.data(),
                            static_cast<int>(colours_.size() * sizeof(float)), kValueField,
                            weights_.data(), static_cast<int>(weights_.size() * sizeof(float))),
          "vpSetLookupShader");
    for (int m = 0; m < specular_material; ++m) {
      double rgb[3] = {0, 0, 0};
      if (channels == 3) rgb[m] = 1.0; else rgb[0] = rgb[1] = rgb[2] = 1.0;
      setMaterial(m, sh.ambient, sh.diffuse, 0.0, rgb);
    }
    const double white[3] = {1, 1, 1};
    setMaterial(specular_material, 0.0, 0.0, sh.specular, white);
    check(vpc_,
          vpSetMaterial(vpc_, VP_MATERIAL0 + specular_material, VP_SHINYNESS, VP_BOTH_SIDES,
                        sh.shininess, 0, 0),
          "vpSetMaterial(shininess)");
    const glm::dvec3 l = glm::normalize(scene.light_direction.value_or(glm::dvec3(0, -1, 0)));
    check(vpc_, vpSetLight(vpc_, VP_LIGHT0, VP_DIRECTION, l.x, l.y, l.z), "vpSetLight");
    check(vpc_, vpSetLight(vpc_, VP_LIGHT0, VP_COLOR, 1, 1, 1), "vpSetLight(colour)");
    check(vpc_, vpEnable(vpc_, VP_LIGHT0, 1), "vpEnable(LIGHT0)");
    check(vpc_, vpEnable(vpc_, VP_LIGHT_BOTH_SIDES, 1), "vpEnable(LIGHT_BOTH_SIDES)");
    check(vpc_, vpSetd(vpc_, VP_MAX_RAY_OPACITY, 1.0 - scene.termination),
          "vpSetd(MAX_RAY_OPACITY)");
  }

  // The view of our camera: VolPack's object coordinates put the volume's longest side in
  // [−0.5, 0.5], so the world is our voxel space divided by that side. The rows (right, up,
  // forward) are the ones that reproduce our image (checked with --images): VolPack's eye space
  // here looks down +z with x to the right, and its image has row 0 at the bottom.
  void setView(const Camera& camera, int size) {
    const glm::dvec3 f = glm::normalize(camera.target - camera.eye);
    const glm::dvec3 r = glm::normalize(glm::cross(f, camera.up));
    const glm::dvec3 u = glm::cross(r, f);
    vpMatrix4 view = {{r.x, r.y, r.z, 0}, {u.x, u.y, u.z, 0}, {f.x, f.y, f.z, 0}, {0, 0, 0, 1}};
    check(vpc_, vpCurrentMatrix(vpc_, VP_VIEW), "vpCurrentMatrix(VIEW)");
    check(vpc_, vpSetMatrix(vpc_, view), "vpSetMatrix(VIEW)");
    const double h = 0.5 * camera.ortho_height / max_dim_;
    check(vpc_, vpCurrentMatrix(vpc_, VP_PROJECT), "vpCurrentMatrix(PROJECT)");
    check(vpc_, vpIdentityMatrix(vpc_), "vpIdentityMatrix");
    check(vpc_, vpWindow(vpc_, VP_PARALLEL, -h, h, -h, h, -1.0, 1.0), "vpWindow");
    check(vpc_, vpCurrentMatrix(vpc_, VP_MODEL), "vpCurrentMatrix(MODEL)");
    size_ = size;
    image_.assign(static_cast<std::size_t>(size) * size * channels_, 0);
    check(vpc_,
          vpSetImage(vpc_, image_.data(), size, size, size * channels_,
                     channels_ == 3 ? VP_RGB : VP_LUMINANCE),
          "vpSetImage");
  }

  // One frame: the shading table depends on the view (the highlight), so it is per frame.
  void render() {
    check(vpc_, vpShadeTable(vpc_), "vpShadeTable");
    check(vpc_, vpRenderClassifiedVolume(vpc_), "vpRenderClassifiedVolume");
  }
  const std::vector<unsigned char>& image() const { return image_; }
  int channels() const { return channels_; }

 private:
  void setMaterial(int m, double ambient, double diffuse, double specular, const double rgb[3]) {
    const int id = VP_MATERIAL0 + m;
    check(vpc_, vpSetMaterial(vpc_, id, VP_AMBIENT, VP_BOTH_SIDES, ambient * rgb[0],
                              ambient * rgb[1], ambient * rgb[2]), "vpSetMaterial(ambient)");
    check(vpc_, vpSetMaterial(vpc_, id, VP_DIFFUSE, VP_BOTH_SIDES, diffuse * rgb[0],
                              diffuse * rgb[1], diffuse * rgb[2]), "vpSetMaterial(diffuse)");
    check(vpc_, vpSetMaterial(vpc_, id, VP_SPECULAR, VP_BOTH_SIDES, specular * rgb[0],
                              specular * rgb[1], specular * rgb[2]), "vpSetMaterial(specular)");
  }

  int channels_;
  // Owned here, so a failed set-up step does not leak it.
  std::unique_ptr<vpContext, decltype(&vpDestroyContext)> context_;
  vpContext* vpc_;
  int max_dim_ = 1, materials_ = 1, size_ = 0;
  std::vector<float> opacity_, weights_, colours_;
  std::vector<unsigned char> image_;
};

std::string imagesDir;  // --images=DIR, empty = none

void writePpm(const std::string& path, int size, int channels, const unsigned char* rgb_or_grey,
              bool bottom_up) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(fmt::format("{}: cannot write", path));
  out << "P6\n" << size << ' ' << size << "\n255\n";
  for (int row = 0; row < size; ++row) {
    const int y = bottom_up ? size - 1 - row : row;
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c)
        out.put(static_cast<char>(rgb_or_grey[(static_cast<std::size_t>(y) * size + x) * channels +
                                              (channels == 3 ? c : 0)]));
  }
}

// Linear 8-bit, as VolPack writes its image, so the two pictures compare directly.
unsigned char linear8(float v) {
  return static_cast<unsigned char>(std::lround(255.f * std::clamp(v, 0.f, 1.f)));
}

// Classified once per channel count and per model, as the view alone changes between runs.
VolPackScene& volpackScene(int channels) {
  static std::map<int, std::unique_ptr<VolPackScene>> scenes;
  auto& scene = scenes[channels];
  if (!scene) scene = std::make_unique<VolPackScene>(channels);
  return *scene;
}

void volpackFrame(benchmark::State& state, int channels, int size, double azimuth) {
  VolPackScene& vp = volpackScene(channels);
  vp.setView(engineCamera(azimuth), size);
  vp.render();
  if (!imagesDir.empty())
    writePpm(fmt::format("{}/volpack_{}_{}_az{}.ppm", imagesDir, channels == 3 ? "rgb" : "grey",
                         size, azimuth),
             size, channels, vp.image().data(), /*bottom_up=*/true);
  for (auto _ : state) {
    vp.render();
    benchmark::DoNotOptimize(vp.image().data());
  }
}

void shearwarpFrame(benchmark::State& state, const std::string& model, int size, double azimuth,
                    const std::string& classification) {
  const ClassifiedVolume& cv = engineClassified(model);
  shearwarp::RleVolume::of(cv)->buildAll();  // cached on the classification, as in a viewer
  const ShearWarpRenderer renderer;
  RenderRequest request = engineRequest(cv, azimuth, size);
  // One sample per slice and an intermediate image at volume resolution, as VolPack's (our
  // defaults add samples between slices where the render step asks for them, and intermediate
  // pixels where the screen does: a different, finer sampling).
  request.options["shearwarp"] = {
      {"classification", classification}, {"slice_samples", 1}, {"supersample", 1}};
  const LightIndependentImage first = renderer.render(request);
  if (!imagesDir.empty() && model == "rgb" && classification == "post") {
    std::vector<unsigned char> rgb(static_cast<std::size_t>(size) * size * 3);
    for (int c = 0; c < 3; ++c) {
      const auto plane = first.planeFloat(c);
      for (std::size_t i = 0; i < plane.size(); ++i) rgb[i * 3 + c] = linear8(plane[i]);
    }
    writePpm(fmt::format("{}/shearwarp_rgb_{}_az{}.ppm", imagesDir, size, azimuth), size, 3,
             rgb.data(), /*bottom_up=*/false);
  }
  for (auto _ : state) {
    auto image = renderer.render(request);
    benchmark::DoNotOptimize(image.planeFloat(0).data());
  }
}

// The scene's azimuth (−60°), the axes, and 44°/46° on either side of the principal-axis switch.
constexpr double kAzimuths[] = {-60.0, 0.0, 30.0, 44.0, 46.0};

void registerAll() {
  for (int size : {512, 800})
    for (double az : kAzimuths) {
      for (int channels : {1, 3})
        benchmark::RegisterBenchmark(
            fmt::format("VolPack/{}/{}/az{}", channels == 3 ? "rgb" : "grey", size, az).c_str(),
            volpackFrame, channels, size, az)
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond)
            ->MinTime(0.3);
      for (const auto& [row, classification] :
           {std::pair{"Shearwarp", "post"}, std::pair{"ShearwarpPre", "pre"}})
        for (const char* model : {"rgb", "factor:6"})
          benchmark::RegisterBenchmark(
              fmt::format("{}/{}/{}/az{}", row, model, size, az).c_str(), shearwarpFrame,
              std::string(model), size, az, std::string(classification))
              ->UseRealTime()
              ->Unit(benchmark::kMillisecond)
              ->MinTime(0.3);
    }
}

}  // namespace
}  // namespace svr::peers

int main(int argc, char** argv) {
  // Our one option is taken out before Google Benchmark reads the rest.
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--images=", 0) == 0) svr::peers::imagesDir = arg.substr(9);
    else argv[kept++] = argv[i];
  }
  argc = kept;
  svr::peers::registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  try {
    benchmark::RunSpecifiedBenchmarks();
  } catch (const std::exception& e) {
    fmt::print(stderr, "svr_volpack_bench: {}\n", e.what());
    return 1;
  }
  benchmark::Shutdown();
  return 0;
}
