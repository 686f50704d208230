#include "renderers/core/volume_source.h"

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
#include <sstream>

#include "renderers/core/memory_budget.h"
#include "spectral/error.h"

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
void inflatePayload(std::FILE* file, const VolumeSource& source, std::vector<std::byte>& out) {
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

  while (skip > 0 || filled < out.size()) {
    Step s{};
    if (skip > 0) {
      s = step(scratch.data(),
               static_cast<std::size_t>(std::min<std::uint64_t>(skip, scratch.size())));
      skip -= s.produced;
    } else {
      s = step(reinterpret_cast<unsigned char*>(out.data()) + filled, out.size() - filled);
      filled += s.produced;
    }
    if (s.stalled && inputExhausted()) throw truncated();
    ended = s.code == Z_STREAM_END;
    if (ended && (skip > 0 || filled < out.size())) {
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
    inflatePayload(file.get(), source, out);
  }
  return out;
}

}  // namespace svr::detail
