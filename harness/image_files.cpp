#include "harness/image_files.h"

#include <fmt/format.h>

#include <OpenImageIO/imageio.h>
#include <filesystem>

#include "spectral/error.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

std::string channelName(const char* prefix, int c) { return fmt::format("{}.{:02d}", prefix, c); }

// Writes with `write` into a temporary sibling, then renames it over `path`.
template <typename WriteFn>
void writeAtomically(const std::string& path, WriteFn&& write) {
  const fs::path target(path);
  const fs::path tmp = target.parent_path() / (".tmp." + target.filename().string());
  try {
    write(tmp.string());
    fs::rename(tmp, target);
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

}  // namespace

void writeLightIndependentExr(const LightIndependentImage& image, const std::string& path,
                              const std::map<std::string, std::string>& attributes) {
  const bool half = image.storage() == SampleStorage::kHalf;
  OIIO::ImageSpec spec(image.width(), image.height(), image.planes(),
                       half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  spec.channelnames.clear();
  for (int c = 0; c < image.channels(); ++c) spec.channelnames.push_back(channelName("S", c));
  for (int c = 0; c < image.transmittanceChannels(); ++c)
    spec.channelnames.push_back(channelName("T", c));
  spec.attribute("compression", "zip");
  for (const auto& [key, value] : attributes) spec.attribute("svr:" + key, value);
  // Interleave the planes (OIIO writes pixels with their channels together).
  const std::size_t n = image.pixels();
  const int planes = image.planes();
  std::vector<float> interleaved(n * planes);
  for (int p = 0; p < planes; ++p)
    for (std::size_t i = 0; i < n; ++i)
      interleaved[i * planes + p] = image.sample(p, static_cast<int>(i % image.width()),
                                                 static_cast<int>(i / image.width()));
  writeAtomically(path, [&](const std::string& tmp) {
    auto out = OIIO::ImageOutput::create("openexr");
    if (!out) throw Error(fmt::format("{}: OpenImageIO has no EXR writer", path));
    if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, interleaved.data()) ||
        !out->close())
      throw Error(fmt::format("{}: cannot write EXR: {}", path, out->geterror()));
  });
}

LightIndependentImage readLightIndependentExr(const std::string& path,
                                              std::map<std::string, std::string>* attributes) {
  if (!fs::exists(path)) throw Error(fmt::format("{}: no such file", path));
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(fmt::format("{}: cannot read as an image: {}", path, OIIO::geterror()));
  const OIIO::ImageSpec spec = in->spec();
  if (std::string(in->format_name()) != "openexr")
    throw Error(fmt::format("{}: is {}, not an OpenEXR light-independent image", path,
                            in->format_name()));
  int s = 0, t = 0;
  for (int c = 0; c < spec.nchannels; ++c) {
    const std::string& name = spec.channelnames[c];
    if (name == channelName("S", s) && t == 0) {
      ++s;
    } else if (name == channelName("T", t)) {
      ++t;
    } else {
      throw Error(fmt::format("{}: channel {} is '{}', expected {} or {}", path, c, name,
                              channelName("S", s), channelName("T", t)));
    }
  }
  if (s == 0) throw Error(fmt::format("{}: no S.nn channels", path));
  if (t != 0 && t != 1 && t != s)
    throw Error(fmt::format("{}: {} T channels for {} S channels (expected 0, 1 or {})", path, t,
                            s, s));
  const bool half = spec.format == OIIO::TypeDesc::HALF;
  LightIndependentImage image(spec.width, spec.height, s, t,
                              half ? SampleStorage::kHalf : SampleStorage::kFloat);
  std::vector<float> pixels(image.pixels() * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
    throw Error(fmt::format("{}: cannot read pixels: {}", path, in->geterror()));
  for (int p = 0; p < spec.nchannels; ++p)
    for (std::size_t i = 0; i < image.pixels(); ++i) {
      const float v = pixels[i * spec.nchannels + p];
      if (!std::isfinite(v))
        throw Error(fmt::format("{}: channel {} holds a non-finite value at pixel ({}, {})", path,
                                spec.channelnames[p], i % spec.width, i / spec.width));
      image.setSample(p, static_cast<int>(i % spec.width), static_cast<int>(i / spec.width), v);
    }
  if (attributes)
    for (const auto& attr : spec.extra_attribs) {
      const std::string name = attr.name().string();
      if (name.rfind("svr:", 0) == 0) (*attributes)[name.substr(4)] = attr.get_string();
    }
  return image;
}

void writeSrgbPng(const std::vector<std::uint8_t>& rgb, int width, int height,
                  const std::string& path) {
  if (rgb.size() != static_cast<std::size_t>(width) * height * 3)
    throw Error(fmt::format("{}: {} bytes for a {}×{} RGB image", path, rgb.size(), width, height));
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  writeAtomically(path, [&](const std::string& tmp) {
    auto out = OIIO::ImageOutput::create("png");
    if (!out) throw Error(fmt::format("{}: OpenImageIO has no PNG writer", path));
    if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) ||
        !out->close())
      throw Error(fmt::format("{}: cannot write PNG: {}", path, out->geterror()));
  });
}

}  // namespace svr
