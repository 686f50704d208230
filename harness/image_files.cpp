#include "harness/image_files.h"

#include <fmt/format.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>

#include "renderers/volume/memory_budget.h"
#include "base/atomic_file.h"
#include "base/error.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

std::string channelName(const char* prefix, int c) { return fmt::format("{}.{:02d}", prefix, c); }

// OpenEXR trusts a file's header: a corrupt attribute size, channel list, preview size or data
// window makes it allocate gigabytes before it finds the file too short (found by fuzz_exr).
// So the header is checked first, the way OpenEXR will read it: attributes (name\0 type\0
// int32 size, value) until an empty name, where every type OpenEXR parses by structure must
// have exactly the size that structure takes, so both walks stay in step, and no value may
// claim more bytes than the file has. svr writes single-part scan-line files; others are
// refused here. Headers are small: the header must lie within the file's first MiB.
void checkExrHeader(const std::string& path) {
  constexpr std::size_t kChecked = std::size_t{1} << 20;
  constexpr std::int64_t kMaxSide = 1 << 15;  // LightIndependentImage's limit
  std::error_code ec;
  const std::uintmax_t file_bytes = fs::file_size(path, ec);
  if (ec) throw Error(fmt::format("{}: cannot read the file: {}", path, ec.message()));
  std::vector<char> bytes(static_cast<std::size_t>(std::min<std::uintmax_t>(file_bytes, kChecked)));
  std::ifstream in(path, std::ios::binary);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
    throw Error(fmt::format("{}: cannot read the file", path));
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(bytes[i]); };
  if (bytes.size() < 8 || byte(0) != 0x76 || byte(1) != 0x2f || byte(2) != 0x31 || byte(3) != 0x01)
    return;  // not an EXR: OpenImageIO says what it is
  const auto corrupt = [&](const std::string& what) {
    return Error(fmt::format("{}: corrupt or unsupported EXR header: {}", path, what));
  };
  if ((byte(5) & 0x1A) != 0)  // tiled (0x02), deep (0x08) or multi-part (0x10)
    throw corrupt("tiled, deep and multi-part files are not light-independent images");
  const auto int32 = [&](std::size_t i) {
    return static_cast<std::int32_t>(byte(i) | byte(i + 1) << 8 | byte(i + 2) << 16 |
                                     static_cast<std::uint32_t>(byte(i + 3)) << 24);
  };
  std::size_t at = 8;
  // A NUL-terminated name at `at`, as OpenEXR reads it (at most 255 characters).
  const auto name = [&](const char* what) {
    const std::size_t start = at;
    while (at < bytes.size() && bytes[at] != '\0' && at - start <= 255) ++at;
    if (at >= bytes.size() || at - start > 255)
      throw corrupt(fmt::format("{} at byte {} is not a terminated name", what, start));
    return std::string(bytes.data() + start, bytes.data() + at++);
  };
  // The bytes OpenEXR reads for a value of each fixed-size type, whatever the size field says.
  static const std::map<std::string, std::int64_t> kFixed = {
      {"box2i", 16},   {"box2f", 16},   {"chromaticities", 32}, {"compression", 1},
      {"double", 8},   {"envmap", 1},   {"float", 4},           {"int", 4},
      {"keycode", 28}, {"lineOrder", 1}, {"m33f", 36},          {"m33d", 72},
      {"m44f", 64},    {"m44d", 128},   {"rational", 8},        {"tiledesc", 9},
      {"timecode", 8}, {"v2i", 8},      {"v2f", 8},             {"v2d", 16},
      {"v3i", 12},     {"v3f", 12},     {"v3d", 24},            {"deepImageState", 1}};
  bool window = false;
  for (std::string attribute; !(attribute = name("an attribute name")).empty();) {
    const std::string type = name(fmt::format("the type of '{}'", attribute).c_str());
    if (bytes.size() - at < 4) throw corrupt(fmt::format("'{}' has no size", attribute));
    const std::int64_t size = int32(at);
    at += 4;
    if (size < 0 || static_cast<std::uintmax_t>(size) > bytes.size() - at)
      throw corrupt(fmt::format("'{}' ({}) claims {} bytes, the header has {} left", attribute,
                                type, size, bytes.size() - at));
    const std::size_t value = at, end = at + static_cast<std::size_t>(size);
    std::int64_t expected = size;
    if (const auto fixed = kFixed.find(type); fixed != kFixed.end()) {
      expected = fixed->second;
    } else if (type == "chlist") {
      // Channels (name\0, int32 type, uint8 linear, 3 reserved, int32 x and y sampling) until
      // an empty name.
      while (at < end && bytes[at] != '\0') {
        name("a channel name");
        at += 16;
      }
      expected = static_cast<std::int64_t>(at + 1 - value);
    } else if (type == "preview") {
      // Width and height (uint32 each), then 4 bytes per pixel.
      expected = 8;
      if (size >= 8) {
        const std::uint64_t pixels = std::uint64_t{static_cast<std::uint32_t>(int32(at))} *
                                     static_cast<std::uint32_t>(int32(at + 4));
        expected = pixels > static_cast<std::uint64_t>(size)
                       ? -1  // more pixels than bytes: cannot match, and 4 × pixels may overflow
                       : 8 + 4 * static_cast<std::int64_t>(pixels);
      }
    } else if (type == "stringvector") {
      // Strings, each an int32 length and its bytes, filling the value exactly.
      while (at < end) {
        const std::int64_t length = end - at >= 4 ? int32(at) : -1;
        if (length < 0 || length > static_cast<std::int64_t>(end - at - 4))
          throw corrupt(fmt::format("'{}' (stringvector) holds a string of {} bytes past its end",
                                    attribute, length));
        at += 4 + static_cast<std::size_t>(length);
      }
    } else if (type == "floatvector") {
      expected = size - size % 4;
    } else if (type == "idmanifest") {
      throw corrupt(fmt::format("'{}' is an idmanifest, which svr does not read", attribute));
    }
    if (expected != size)
      throw corrupt(fmt::format("'{}' ({}) is {} bytes long, expected {}", attribute, type, size,
                                expected));
    if (attribute == "dataWindow" && type == "box2i") {
      const std::int64_t width = std::int64_t{int32(value + 8)} - int32(value) + 1;
      const std::int64_t height = std::int64_t{int32(value + 12)} - int32(value + 4) + 1;
      if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide)
        throw corrupt(fmt::format("dataWindow is {}×{} pixels, outside 1..{}", width, height,
                                  kMaxSide));
      window = true;
    }
    at = end;
  }
  if (!window) throw corrupt("no dataWindow");
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
  writeFileAtomically(path, [&](const std::string& tmp) {
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
  checkExrHeader(path);
  // The OpenEXR reader only: ImageInput::open falls back to every other format's reader when
  // the EXR one refuses a file, and OpenImageIO 2.4's RLA reader aborts the process on some
  // corrupt input (fuzz_exr's long campaign, issue 15; tests/data/bad/exr_rla_fallback.exr).
  auto in = OIIO::ImageInput::create("openexr");
  if (!in) throw Error(fmt::format("{}: OpenImageIO has no EXR reader", path));
  OIIO::ImageSpec opened;
  if (!in->open(path, opened))
    throw Error(fmt::format("{}: cannot read as an OpenEXR light-independent image: {}", path,
                            in->geterror()));
  const OIIO::ImageSpec spec = in->spec();
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
  // The samples as read (float) and as kept: checked before either is allocated, since the
  // header's data window is untrusted.
  const bool half = spec.format == OIIO::TypeDesc::HALF;
  checkMemoryBudget(static_cast<std::uint64_t>(std::max(spec.width, 0)) *
                        static_cast<std::uint64_t>(std::max(spec.height, 0)) *
                        static_cast<std::uint64_t>(spec.nchannels) * (sizeof(float) + (half ? 2 : 4)),
                    defaultMemoryBudget(),
                    fmt::format("{}: {}×{} pixels × {} channels", path, spec.width, spec.height,
                                spec.nchannels));
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
  writeFileAtomically(path, [&](const std::string& tmp) {
    auto out = OIIO::ImageOutput::create("png");
    if (!out) throw Error(fmt::format("{}: OpenImageIO has no PNG writer", path));
    if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) ||
        !out->close())
      throw Error(fmt::format("{}: cannot write PNG: {}", path, out->geterror()));
  });
}

std::vector<std::uint8_t> encodeSrgbPng(std::span<const std::uint8_t> rgb, int width,
                                        int height) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
    throw Error(fmt::format("PNG: {} bytes for a {}×{} RGB image", rgb.size(), width, height));
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  OIIO::Filesystem::IOVecOutput memory;
  auto out = OIIO::ImageOutput::create("png");
  if (!out) throw Error("PNG: OpenImageIO has no PNG writer");
  out->set_ioproxy(&memory);
  if (!out->open("memory.png", spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) ||
      !out->close())
    throw Error(fmt::format("PNG: cannot encode: {}", out->geterror()));
  return {memory.buffer().begin(), memory.buffer().end()};
}

}  // namespace svr
