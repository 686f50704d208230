#include "renderers/volume/volume_source.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <span>
#include <sstream>

#include "renderers/volume/memory_budget.h"
#include "base/error.h"

namespace svr::detail {

namespace fs = std::filesystem;

namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// "header says 41×41×41 uint8 = 68921 bytes": the expectation every size message starts from.
std::string expectation(const VolumeHeader& header) {
  return fmt::format("{} says {} = {} bytes", header.format == "raw" ? "the raw layout" : "header",
                     describeShape(header.dims, header.type), header.data_bytes);
}

// Fills `out` from the zlib or gzip stream in `file` (zlib detects which from the stream's own
// header), after dropping `source.skip_decompressed` bytes. Concatenated gzip members are read
// as one stream, as gzip(1) does. The stream must end, with a good checksum, exactly where the
// voxels end: a short stream, a stream without its trailer and a longer stream are all errors.
// Copies what falls inside `box` of the payload bytes [at, at + n) (x fastest, dims of the whole
// grid, `w` bytes a voxel) into `out`, the box's voxels x fastest.
void copyBoxPart(const Dims& dims, const VoxelBox& box, std::size_t w, std::uint64_t at,
                 const unsigned char* bytes, std::size_t n, std::byte* out) {
  const std::uint64_t row_bytes = static_cast<std::uint64_t>(dims[0]) * w;
  const Dims size = box.size();
  const std::uint64_t end = at + n;
  for (std::uint64_t pos = at; pos < end;) {
    const std::uint64_t row = pos / row_bytes;
    const std::uint64_t row_start = row * row_bytes, row_end = row_start + row_bytes;
    const int y = static_cast<int>(row % dims[1]), z = static_cast<int>(row / dims[1]);
    if (y >= box.lo[1] && y < box.hi[1] && z >= box.lo[2] && z < box.hi[2]) {
      const std::uint64_t lo = std::max(pos, row_start + box.lo[0] * w);
      const std::uint64_t hi = std::min(end, row_start + box.hi[0] * w);
      if (lo < hi) {
        const std::uint64_t dest_row =
            (static_cast<std::uint64_t>(z - box.lo[2]) * size[1] + (y - box.lo[1])) * size[0] * w;
        std::memcpy(out + dest_row + (lo - row_start - box.lo[0] * w), bytes + (lo - at),
                    static_cast<std::size_t>(hi - lo));
      }
    }
    pos = std::min(end, row_end);
  }
}

// Where decompressed voxel bytes go: window(at) is room for the bytes from stream offset `at`
// (after the dropped header bytes), commit(at, n) says n of them were written there.
struct PayloadSink {
  virtual ~PayloadSink() = default;
  virtual std::span<unsigned char> window(std::uint64_t at) = 0;
  virtual void commit(std::uint64_t at, std::size_t n) {}
};

// The whole payload, inflated straight into its vector.
struct WholeSink final : PayloadSink {
  std::vector<std::byte>& out;
  explicit WholeSink(std::vector<std::byte>& o) : out(o) {}
  std::span<unsigned char> window(std::uint64_t at) override {
    return {reinterpret_cast<unsigned char*>(out.data()) + at, out.size() - at};
  }
};

// A box of the payload: bytes are inflated into a chunk and the box's parts of each voxel row
// copied out.
struct BoxSink final : PayloadSink {
  const Dims dims;
  const VoxelBox box;
  const std::size_t voxel_bytes;
  std::vector<std::byte>& out;
  std::vector<unsigned char> chunk = std::vector<unsigned char>(std::size_t{1} << 20);
  BoxSink(const Dims& d, const VoxelBox& b, std::size_t w, std::vector<std::byte>& o)
      : dims(d), box(b), voxel_bytes(w), out(o) {}
  std::span<unsigned char> window(std::uint64_t) override { return chunk; }
  void commit(std::uint64_t at, std::size_t n) override {
    copyBoxPart(dims, box, voxel_bytes, at, chunk.data(), n, out.data());
  }
};

// A sub-lattice of the payload: of each chosen row, the chosen voxels' bytes that the chunk holds.
struct LatticeSink final : PayloadSink {
  const Dims dims;
  const LatticeIndices& at;
  const std::size_t voxel_bytes;
  std::vector<std::byte>& out;
  std::array<std::vector<int>, 3> slot;  // voxel index → its place in the lattice, −1: not taken
  std::vector<unsigned char> chunk = std::vector<unsigned char>(std::size_t{1} << 20);
  LatticeSink(const Dims& d, const LatticeIndices& a, std::size_t w, std::vector<std::byte>& o)
      : dims(d), at(a), voxel_bytes(w), out(o) {
    for (int axis = 0; axis < 3; ++axis) {
      slot[axis].assign(dims[axis], -1);
      for (std::size_t i = 0; i < at[axis].size(); ++i) slot[axis][at[axis][i]] = static_cast<int>(i);
    }
  }
  std::span<unsigned char> window(std::uint64_t) override { return chunk; }
  void commit(std::uint64_t from, std::size_t n) override {
    const std::uint64_t w = voxel_bytes, row_bytes = static_cast<std::uint64_t>(dims[0]) * w;
    const std::uint64_t end = from + n;
    for (std::uint64_t row = from / row_bytes; row * row_bytes < end; ++row) {
      const int sy = slot[1][row % dims[1]], sz = slot[2][row / dims[1]];
      if (sy < 0 || sz < 0) continue;
      const std::uint64_t dest_row = (static_cast<std::uint64_t>(sz) * at[1].size() + sy) * at[0].size();
      for (std::size_t i = 0; i < at[0].size(); ++i) {
        const std::uint64_t voxel = row * row_bytes + at[0][i] * w;
        const std::uint64_t lo = std::max(voxel, from), hi = std::min(voxel + w, end);
        if (lo < hi)
          std::memcpy(out.data() + (dest_row + i) * w + (lo - voxel), chunk.data() + (lo - from),
                      static_cast<std::size_t>(hi - lo));
      }
    }
  }
};

void inflatePayload(std::FILE* file, const VolumeSource& source, PayloadSink& sink) {
  const VolumeHeader& h = source.header;
  const std::string stream = fmt::format("the {} stream in '{}'", h.encoding, h.data_file);
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK)
    throw Error(fmt::format("{}: cannot start zlib to read {}", h.path, stream));
  struct InflateEnd {
    z_stream* zs;
    ~InflateEnd() { inflateEnd(zs); }
  } const inflate_end{&zs};

  std::vector<unsigned char> input(std::size_t{1} << 20);
  std::uint64_t input_left = source.compressed_bytes.value_or(UINT64_MAX);
  bool input_done = false;
  const auto refill = [&] {
    if (zs.avail_in > 0 || input_done) return;
    const std::size_t want =
        static_cast<std::size_t>(std::min<std::uint64_t>(input.size(), input_left));
    const std::size_t got = want == 0 ? 0 : std::fread(input.data(), 1, want, file);
    if (std::ferror(file))
      throw Error(
          fmt::format("{}: cannot read '{}': {}", h.path, h.data_file, std::strerror(errno)));
    input_left -= got;
    input_done = got < want || input_left == 0;
    zs.next_in = input.data();
    zs.avail_in = static_cast<uInt>(got);
  };

  std::array<unsigned char, 1 << 16> scratch;
  std::uint64_t skip = source.skip_decompressed;
  std::size_t filled = 0;
  bool ended = false;
  const auto truncated = [&] {
    return Error(fmt::format("{}: {} but {} ends after {} bytes (truncated)", h.path,
                             expectation(h), stream, filled));
  };
  const auto corrupt = [&](int code) {
    return Error(fmt::format("{}: {} is corrupt after {} bytes ({})", h.path, stream, filled,
                             zs.msg ? zs.msg : zError(code)));
  };
  // One inflate call into dest[0, room): its return code and how many bytes it wrote.
  struct Step {
    int code;
    std::size_t produced;
    bool stalled;  // neither consumed input nor wrote output
  };
  const auto step = [&](unsigned char* dest, std::size_t room) {
    refill();
    zs.next_out = dest;
    zs.avail_out = static_cast<uInt>(std::min<std::size_t>(room, UINT32_MAX));
    const uInt in_before = zs.avail_in, out_before = zs.avail_out;
    const int code = inflate(&zs, Z_NO_FLUSH);
    if (code == Z_NEED_DICT || code == Z_DATA_ERROR || code == Z_MEM_ERROR ||
        code == Z_STREAM_ERROR)
      throw corrupt(code);
    const std::size_t produced = out_before - zs.avail_out;
    const bool stalled = code != Z_STREAM_END && produced == 0 && zs.avail_in == in_before;
    // Stalled with input left cannot happen while there is room to write, but would loop
    // forever, so it counts as corruption.
    if (stalled && zs.avail_in > 0) throw corrupt(code);
    return Step{code, produced, stalled};
  };
  const auto inputExhausted = [&] { return zs.avail_in == 0 && input_done; };

  const std::uint64_t total = h.data_bytes;
  while (skip > 0 || filled < total) {
    Step s{};
    if (skip > 0) {
      s = step(scratch.data(),
               static_cast<std::size_t>(std::min<std::uint64_t>(skip, scratch.size())));
      skip -= s.produced;
    } else {
      const std::span<unsigned char> room = sink.window(filled);
      s = step(room.data(), static_cast<std::size_t>(std::min<std::uint64_t>(room.size(),
                                                                             total - filled)));
      sink.commit(filled, s.produced);
      filled += s.produced;
    }
    if (s.stalled && inputExhausted()) throw truncated();
    ended = s.code == Z_STREAM_END;
    if (ended && (skip > 0 || filled < total)) {
      refill();
      if (zs.avail_in == 0) throw truncated();
      inflateReset(&zs);  // the next gzip member
    }
  }
  // The voxels are complete; the stream must end here and its checksum must match.
  while (!ended) {
    const Step s = step(scratch.data(), 1);
    if (s.produced > 0)
      throw Error(fmt::format("{}: {} but {} holds more", h.path, expectation(h), stream));
    ended = s.code == Z_STREAM_END;
    if (s.stalled && inputExhausted())
      throw Error(fmt::format("{}: {} is truncated: it ends before its checksum", h.path, stream));
  }
}

}  // namespace

void checkHeaderLineIsText(const std::string& path, const std::string& line, int line_number) {
  for (std::size_t i = 0; i < line.size(); ++i) {
    const auto byte = static_cast<unsigned char>(line[i]);
    if (byte < 0x20 && byte != '\t' && byte != '\r')
      throw Error(fmt::format("{}: line {} of the header holds binary data (byte 0x{:02x} at "
                              "column {}); is this a data file rather than its header?",
                              path, line_number, byte, i + 1));
  }
}

void checkHeaderWithinBudget(const std::string& path, std::uint64_t consumed,
                             std::uint64_t budget, const char* what_ends_it) {
  // Any header of up to 1 MiB reads whatever the budget (a small budget is meant for voxels).
  budget = std::max<std::uint64_t>(budget, std::uint64_t{1} << 20);
  if (consumed > budget)
    throw Error(fmt::format("{}: the header runs past {} without {}, over the memory budget "
                            "(set --memory-budget to raise it)",
                            path, formatBytes(budget), what_ends_it));
}

std::string trim(const std::string& text) {
  const auto space = [](unsigned char c) { return std::isspace(c) != 0; };
  const auto begin = std::find_if_not(text.begin(), text.end(), space);
  const auto end = std::find_if_not(text.rbegin(), text.rend(), space).base();
  return begin < end ? std::string(begin, end) : std::string();
}

std::string toLower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

bool isTiffName(const std::string& path) {
  const std::string ext = toLower(fs::path(path).extension().string());
  return ext == ".tif" || ext == ".tiff";
}

std::vector<std::string> splitWhitespace(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

std::string resolveDataFile(const std::string& header_path, const std::string& name,
                            const std::string& key) {
  if (name.empty()) throw Error(fmt::format("{}: {} is empty", header_path, key));
  const fs::path given(name);
  for (const fs::path& part : given)
    if (part == "..")
      throw Error(
          fmt::format("{}: {} '{}' has a '..' component; the data file must lie in the "
                      "header's folder",
                      header_path, key, name));
  const fs::path header_dir = fs::path(header_path).parent_path();
  const fs::path full = given.is_absolute() ? given : header_dir / given;
  if (given.is_absolute()) {
    // Lexical, so a symlinked folder still counts as the folder it appears to be.
    const fs::path dir = fs::absolute(header_dir).lexically_normal();
    const fs::path file = given.lexically_normal();
    const auto [d, f] = std::mismatch(dir.begin(), dir.end(), file.begin(), file.end());
    if (d != dir.end() && !d->empty())
      throw Error(fmt::format("{}: {} '{}' is outside the header's folder '{}'", header_path, key,
                              name, dir.string()));
  }
  std::error_code ec;
  const fs::file_status status = fs::status(full, ec);
  if (!fs::exists(status))
    throw Error(fmt::format("{}: {} '{}' does not exist (looked for '{}')", header_path, key, name,
                            full.string()));
  if (!fs::is_regular_file(status))
    throw Error(fmt::format("{}: {} '{}' is not a regular file", header_path, key, name));
  return full.string();
}

std::uint64_t fileSize(const std::string& path, const std::string& source) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec)
    throw Error(fmt::format("{}: cannot read the size of '{}': {}", source, path, ec.message()));
  return size;
}

void checkRawPayloadSize(const VolumeSource& source) {
  const VolumeHeader& h = source.header;
  const std::uint64_t size = fileSize(h.data_file, h.path);
  const std::uint64_t held = size > source.offset ? size - source.offset : 0;
  if (held == h.data_bytes) return;
  const std::string after =
      source.offset > 0 ? fmt::format(" after the first {}", source.offset) : "";
  throw Error(fmt::format("{}: {} but the data file '{}' holds {} bytes{}", h.path, expectation(h),
                          h.data_file, held, after));
}

std::vector<std::byte> readPayload(const VolumeSource& source) {
  const VolumeHeader& h = source.header;
  const FilePtr file(std::fopen(h.data_file.c_str(), "rb"));
  if (!file)
    throw Error(fmt::format("{}: cannot open data file '{}': {}", h.path, h.data_file,
                            std::strerror(errno)));
  if (source.offset > static_cast<std::uint64_t>(INT64_MAX) ||
      fseeko(file.get(), static_cast<off_t>(source.offset), SEEK_SET) != 0)
    throw Error(
        fmt::format("{}: cannot seek to byte {} of '{}'", h.path, source.offset, h.data_file));
  std::vector<std::byte> out(h.data_bytes);
  if (h.encoding == "raw") {
    const std::size_t got = std::fread(out.data(), 1, out.size(), file.get());
    if (got != out.size())
      throw Error(fmt::format("{}: {} but the data file '{}' holds {} bytes", h.path,
                              expectation(h), h.data_file, got));
  } else {
    WholeSink sink(out);
    inflatePayload(file.get(), source, sink);
  }
  return out;
}

namespace {
// The data file, open; a compressed payload at its first byte (raw ones are read with seeks).
FilePtr openPayload(const VolumeSource& source) {
  const VolumeHeader& h = source.header;
  FilePtr file(std::fopen(h.data_file.c_str(), "rb"));
  if (!file)
    throw Error(fmt::format("{}: cannot open data file '{}': {}", h.path, h.data_file,
                            std::strerror(errno)));
  if (h.encoding != "raw" && (source.offset > static_cast<std::uint64_t>(INT64_MAX) ||
                              fseeko(file.get(), static_cast<off_t>(source.offset), SEEK_SET) != 0))
    throw Error(
        fmt::format("{}: cannot seek to byte {} of '{}'", h.path, source.offset, h.data_file));
  return file;
}
}  // namespace

std::vector<std::byte> readPayloadBox(const VolumeSource& source, const VoxelBox& box) {
  const VolumeHeader& h = source.header;
  const FilePtr file = openPayload(source);
  const std::size_t w = bytesPerVoxel(h.type);
  std::vector<std::byte> out(box.voxels() * w);
  if (h.encoding != "raw") {
    BoxSink sink(h.dims, box, w, out);
    inflatePayload(file.get(), source, sink);
    return out;
  }
  // Raw: a seek and a read per run of contiguous bytes (a row of the box, or whole slabs of
  // rows when the box spans the rows).
  const Dims size = box.size();
  const bool whole_rows = size[0] == h.dims[0];
  const std::size_t run = w * size[0] * (whole_rows ? size[1] : 1);
  std::byte* dest = out.data();
  for (int z = box.lo[2]; z < box.hi[2]; ++z)
    for (int y = box.lo[1]; y < box.hi[1]; y += whole_rows ? size[1] : 1) {
      const std::uint64_t at =
          source.offset +
          ((static_cast<std::uint64_t>(z) * h.dims[1] + y) * h.dims[0] + box.lo[0]) * w;
      if (fseeko(file.get(), static_cast<off_t>(at), SEEK_SET) != 0 ||
          std::fread(dest, 1, run, file.get()) != run)
        throw Error(fmt::format("{}: cannot read {} bytes at byte {} of '{}' (voxel row y {} z {})",
                                h.path, run, at, h.data_file, y, z));
      dest += run;
    }
  return out;
}

std::vector<std::byte> readPayloadLattice(const VolumeSource& source, const LatticeIndices& at) {
  const VolumeHeader& h = source.header;
  const FilePtr file = openPayload(source);
  const std::size_t w = bytesPerVoxel(h.type);
  std::vector<std::byte> out(at[0].size() * at[1].size() * at[2].size() * w);
  if (h.encoding != "raw") {
    LatticeSink sink(h.dims, at, w, out);
    inflatePayload(file.get(), source, sink);
    return out;
  }
  std::vector<std::byte> row(static_cast<std::size_t>(h.dims[0]) * w);
  std::byte* dest = out.data();
  for (const int z : at[2])
    for (const int y : at[1]) {
      const std::uint64_t from =
          source.offset + (static_cast<std::uint64_t>(z) * h.dims[1] + y) * h.dims[0] * w;
      if (fseeko(file.get(), static_cast<off_t>(from), SEEK_SET) != 0 ||
          std::fread(row.data(), 1, row.size(), file.get()) != row.size())
        throw Error(fmt::format("{}: cannot read {} bytes at byte {} of '{}' (voxel row y {} z {})",
                                h.path, row.size(), from, h.data_file, y, z));
      for (const int x : at[0]) dest = std::copy_n(row.data() + x * w, w, dest);
    }
  return out;
}

std::vector<std::byte> readSliceBox(const SliceStack& stack, const Dims& dims, const VoxelBox& box) {
  const std::size_t w = bytesPerVoxel(stack.type());
  const Dims size = box.size();
  std::vector<std::byte> out(box.voxels() * w);
  std::byte* dest = out.data();
  for (int z = box.lo[2]; z < box.hi[2]; ++z) {
    const std::vector<std::byte> slice = stack.slice(z);
    for (int y = box.lo[1]; y < box.hi[1]; ++y)
      dest = std::copy_n(slice.data() + (static_cast<std::size_t>(y) * dims[0] + box.lo[0]) * w,
                         static_cast<std::size_t>(size[0]) * w, dest);
  }
  return out;
}

std::vector<std::byte> readSliceLattice(const SliceStack& stack, const Dims& dims,
                                        const LatticeIndices& at) {
  const std::size_t w = bytesPerVoxel(stack.type());
  std::vector<std::byte> out(at[0].size() * at[1].size() * at[2].size() * w);
  std::byte* dest = out.data();
  for (const int z : at[2]) {
    const std::vector<std::byte> slice = stack.slice(z);
    for (const int y : at[1])
      for (const int x : at[0])
        dest = std::copy_n(slice.data() + (static_cast<std::size_t>(y) * dims[0] + x) * w, w, dest);
  }
  return out;
}

}  // namespace svr::detail
