// TIFF stacks through libtiff: one multi-page TIFF (a page per z), or a folder of numbered
// single-page TIFFs (a file per z, in the order of the number in each name). Grey images only
// (one sample per pixel), 8/16/32-bit integers and 32/64-bit floats, stripped or tiled, with any
// compression libtiff decodes (it also swaps bytes to the machine's order). TIFF states no
// z spacing, so the spacing comes from the caller (the scene), 1 when not given.
#include <fmt/format.h>
#include <tiffio.h>

#include <algorithm>
#include <cstdarg>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>

#include "renderers/volume/memory_budget.h"
#include "renderers/volume/volume_source.h"
#include "base/error.h"

namespace svr::detail {

namespace fs = std::filesystem;

namespace {

// libtiff reports through a global handler; the last message is kept (per thread) for the error
// svr throws, instead of being printed.
thread_local std::string tiff_message;
void keepMessage(const char* module, const char* format, va_list args) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, args);
  tiff_message = module ? fmt::format("{}: {}", module, text) : std::string(text);
}
void installHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    TIFFSetErrorHandler(keepMessage);
    TIFFSetWarningHandler(nullptr);
  });
}

struct TiffClose {
  void operator()(TIFF* tif) const { TIFFClose(tif); }
};
using TiffPtr = std::unique_ptr<TIFF, TiffClose>;

TiffPtr openTiff(const std::string& path) {
  installHandlers();
  tiff_message.clear();
  TiffPtr tif(TIFFOpen(path.c_str(), "r"));
  if (!tif) throw Error(fmt::format("{}: not a TIFF file libtiff can read ({})", path, tiff_message));
  return tif;
}

// What one page holds; every page of a stack must hold the same.
struct PageLayout {
  std::uint32_t width = 0, height = 0;
  ScalarType type = ScalarType::kUint8;
  std::uint16_t compression = COMPRESSION_NONE;
  bool operator==(const PageLayout&) const = default;
};

std::string describe(const PageLayout& p) {
  return fmt::format("{} × {} {}", p.width, p.height, toString(p.type));
}

PageLayout pageLayout(TIFF* tif, const std::string& where) {
  PageLayout p;
  std::uint16_t bits = 8, format = SAMPLEFORMAT_UINT, samples = 1, photometric = 0;
  TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &p.width);
  TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &p.height);
  TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &p.compression);
  TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photometric);
  if (p.width < 1 || p.height < 1 || p.width > (1u << 30) || p.height > (1u << 30))
    throw Error(fmt::format("{}: image is {} × {}; expected 1 … 2^30 each way", where, p.width,
                            p.height));
  if (samples != 1 || photometric == PHOTOMETRIC_PALETTE)
    throw Error(fmt::format("{}: has {} samples per pixel{}; svr reads grey-value stacks (one "
                            "sample per pixel, no palette)",
                            where, samples, photometric == PHOTOMETRIC_PALETTE ? " (palette)" : ""));
  const auto type = [&]() -> std::optional<ScalarType> {
    if (format == SAMPLEFORMAT_UINT || format == SAMPLEFORMAT_VOID)
      return bits == 8 ? ScalarType::kUint8 : bits == 16 ? ScalarType::kUint16
             : bits == 32 ? std::optional(ScalarType::kUint32) : std::nullopt;
    if (format == SAMPLEFORMAT_INT)
      return bits == 8 ? ScalarType::kInt8 : bits == 16 ? ScalarType::kInt16
             : bits == 32 ? std::optional(ScalarType::kInt32) : std::nullopt;
    if (format == SAMPLEFORMAT_IEEEFP)
      return bits == 32 ? ScalarType::kFloat32 : bits == 64 ? std::optional(ScalarType::kFloat64)
                                                            : std::nullopt;
    return std::nullopt;
  }();
  if (!type)
    throw Error(fmt::format("{}: {}-bit samples of sample format {}; svr reads 8/16/32-bit "
                            "integers and 32/64-bit floats",
                            where, bits, format));
  p.type = *type;
  return p;
}

// The current page's pixels, x fastest, native byte order. A tile buffer is sized by the tile
// tags, which may be far larger than the page (a fuzzed TileWidth asked for 32 GiB), so it must
// fit the memory budget.
std::vector<std::byte> readPage(TIFF* tif, const PageLayout& p, const std::string& where,
                                std::uint64_t budget) {
  const std::size_t w = bytesPerVoxel(p.type), row = p.width * w;
  std::vector<std::byte> out(row * p.height);
  tiff_message.clear();
  const auto fail = [&](const char* what, std::uint32_t index) {
    return Error(fmt::format("{}: cannot decode {} {} ({})", where, what, index, tiff_message));
  };
  if (TIFFIsTiled(tif)) {
    std::uint32_t tw = 0, th = 0;
    TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tw);
    TIFFGetField(tif, TIFFTAG_TILELENGTH, &th);
    if (tw == 0 || th == 0) throw Error(fmt::format("{}: a tile is {} × {}", where, tw, th));
    checkMemoryBudget(std::uint64_t{tw} * th * w, budget,
                      fmt::format("{}: a tile of {} × {} {}", where, tw, th, toString(p.type)));
    std::vector<std::byte> tile(static_cast<std::size_t>(TIFFTileSize(tif)));
    if (tile.size() < std::size_t{tw} * th * w)
      throw Error(fmt::format("{}: tiles of {} bytes cannot hold {} × {} samples", where,
                              tile.size(), tw, th));
    for (std::uint32_t y0 = 0; y0 < p.height; y0 += th)
      for (std::uint32_t x0 = 0; x0 < p.width; x0 += tw) {
        const ttile_t t = TIFFComputeTile(tif, x0, y0, 0, 0);
        if (TIFFReadEncodedTile(tif, t, tile.data(), static_cast<tmsize_t>(tile.size())) < 0)
          throw fail("tile", t);
        const std::uint32_t cols = std::min(tw, p.width - x0), rows = std::min(th, p.height - y0);
        for (std::uint32_t y = 0; y < rows; ++y)
          std::memcpy(out.data() + (y0 + y) * row + x0 * w, tile.data() + y * tw * w, cols * w);
      }
    return out;
  }
  std::uint32_t rows_per_strip = p.height;
  TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &rows_per_strip);
  rows_per_strip = std::clamp<std::uint32_t>(rows_per_strip, 1, p.height);
  for (std::uint32_t y0 = 0; y0 < p.height; y0 += rows_per_strip) {
    const std::uint32_t rows = std::min(rows_per_strip, p.height - y0);
    const tstrip_t s = TIFFComputeStrip(tif, y0, 0);
    const tmsize_t want = static_cast<tmsize_t>(rows * row);
    if (TIFFReadEncodedStrip(tif, s, out.data() + y0 * row, want) != want) throw fail("strip", s);
  }
  return out;
}

// One page per slice: a multi-page file (pages in order) or numbered files (a page each).
class TiffStack final : public SliceStack {
 public:
  TiffStack(std::vector<std::string> files, bool pages, PageLayout layout, std::uint64_t budget)
      : files_(std::move(files)), pages_(pages), layout_(layout), budget_(budget) {}
  ScalarType type() const override { return layout_.type; }
  std::vector<std::byte> slice(int z) const override {
    const std::string& file = files_[pages_ ? 0 : z];
    const std::string where = pages_ ? fmt::format("{} page {}", file, z) : file;
    if (!open_ || !pages_ || current_ < 0) open_ = openTiff(file), current_ = 0;
    if (pages_ && z != current_) {
      const bool next = z == current_ + 1 ? TIFFReadDirectory(open_.get()) == 1
                                          : TIFFSetDirectory(open_.get(), static_cast<tdir_t>(z)) == 1;
      if (!next) throw Error(fmt::format("{}: cannot read the page ({})", where, tiff_message));
      current_ = z;
    }
    const PageLayout page = pageLayout(open_.get(), where);
    if (!(page == layout_))
      throw Error(fmt::format("{}: is {} ({}); page 0 is {} ({}): every slice of a stack must "
                              "match",
                              where, describe(page), page.compression, describe(layout_),
                              layout_.compression));
    std::vector<std::byte> pixels = readPage(open_.get(), page, where, budget_);
    if (!pages_) open_.reset();
    return pixels;
  }

 private:
  std::vector<std::string> files_;
  bool pages_;
  PageLayout layout_;
  std::uint64_t budget_;
  mutable TiffPtr open_;
  mutable int current_ = -1;
};

// The folder's TIFFs in the order of the number in their names (its last run of digits), which
// must run without gaps or repeats.
std::vector<std::string> numberedFiles(const std::string& folder) {
  std::map<long long, std::string> by_number;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || !isTiffName(entry.path().string())) continue;
    const std::string stem = entry.path().stem().string();
    const auto last = std::find_if(stem.rbegin(), stem.rend(), ::isdigit);
    if (last == stem.rend())
      throw Error(fmt::format("{}: '{}' has no number in its name; a folder stack orders its "
                              "files by number",
                              folder, entry.path().filename().string()));
    const auto first = std::find_if_not(last, stem.rend(), ::isdigit);
    const std::string digits(first.base(), last.base());
    const long long n = std::stoll(digits.substr(0, 15));
    const auto [it, fresh] = by_number.emplace(n, entry.path().string());
    if (!fresh)
      throw Error(fmt::format("{}: '{}' and '{}' both have number {}", folder,
                              fs::path(it->second).filename().string(),
                              entry.path().filename().string(), n));
  }
  if (by_number.empty()) throw Error(fmt::format("{}: holds no .tif or .tiff files", folder));
  std::vector<std::string> files;
  long long expected = by_number.begin()->first;
  for (const auto& [n, file] : by_number) {
    if (n != expected)
      throw Error(fmt::format("{}: the numbers jump from {} to {} ('{}'): slice {} is missing",
                              folder, expected - 1, n, fs::path(file).filename().string(),
                              expected));
    files.push_back(file);
    ++expected;
  }
  return files;
}

}  // namespace

VolumeSource readTiffSource(const std::string& path, const glm::dvec3& spacing,
                            std::uint64_t budget) {
  const bool folder = fs::is_directory(path);
  std::vector<std::string> files = folder ? numberedFiles(path) : std::vector<std::string>{path};
  const TiffPtr first = openTiff(files[0]);
  const int pages = TIFFNumberOfDirectories(first.get());
  // A directory chain that breaks off (a truncated file) ends the count early with an error,
  // not quietly: the stack would lose its last pages.
  if (!tiff_message.empty())
    throw Error(fmt::format("{}: cannot read past page {} ({}); is the file truncated?", files[0],
                            pages - 1, tiff_message));
  if (folder && pages != 1)
    throw Error(fmt::format("{}: has {} pages; a folder stack takes one page per file", files[0],
                            pages));
  const int depth = folder ? static_cast<int>(files.size()) : pages;
  if (depth < 1 || depth > (1 << 30))
    throw Error(fmt::format("{}: holds {} pages", path, depth));
  const PageLayout layout = pageLayout(first.get(), folder ? files[0] : path + " page 0");
  VolumeSource source;
  VolumeHeader& h = source.header;
  h.path = h.data_file = path;
  h.format = "tiff";
  const TIFFCodec* codec = TIFFFindCODEC(layout.compression);
  h.encoding = layout.compression == COMPRESSION_NONE ? "raw"
               : codec                                 ? codec->name
                                                       : fmt::format("compression {}", layout.compression);
  h.dims = {static_cast<int>(layout.width), static_cast<int>(layout.height), depth};
  h.type = layout.type;
  h.endian = nativeEndian();  // libtiff swaps to the machine's order
  h.data_bytes = volumeBytes({h.dims[0], h.dims[1], h.dims[2]}, h.type, path);
  h.spacing = spacing;
  h.orientation = folder ? fmt::format("{} numbered files, a page each, in number order", depth)
                         : fmt::format("{} page{}, in file order", depth, depth == 1 ? "" : "s");
  source.slices = std::make_shared<TiffStack>(std::move(files), !folder, layout, budget);
  return source;
}

}  // namespace svr::detail
