// The walk described in dicom_structure.h: one pass over element headers, seeking past values.
#include "renderers/volume/dicom_structure.h"

#include <fmt/format.h>
#include <gdcmDicts.h>
#include <gdcmGlobal.h>
#include <gdcmVR.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

#include "base/error.h"

namespace svr::detail {

namespace {

constexpr std::uint32_t kUndefinedLength = 0xffffffff;
constexpr int kMaxDepth = 32;
// PS3.5 7.1.2: these VRs have a 2-byte reserved field and a 4-byte length; the rest a 2-byte one.
const std::string kLongVrs = "OB OD OF OL OV OW SQ SV UC UN UR UT UV";
const std::string kShortVrs = "AE AS AT CS DA DS DT FD FL IS LO LT PN SH SL SS ST TM UI UL US";
const char* const kImplicitLittle = "1.2.840.10008.1.2";
const char* const kExplicitBig = "1.2.840.10008.1.2.2";
const char* const kDeflated = "1.2.840.10008.1.2.1.99";

bool isVrIn(const std::string& vr, const std::string& list) {
  return vr.size() == 2 && vr[0] >= 'A' && vr[0] <= 'Z' && vr[1] >= 'A' && vr[1] <= 'Z' &&
         list.find(vr) != std::string::npos;
}

// DICOM's data dictionary (GDCM's) VR of a public tag: INVALID where it knows none.
gdcm::VR dictionaryVr(unsigned group, unsigned element) {
  if (group % 2 == 1) return gdcm::VR::INVALID;
  const gdcm::Tag tag(static_cast<std::uint16_t>(group), static_cast<std::uint16_t>(element));
  return gdcm::Global::GetInstance().GetDicts().GetDictEntry(tag).GetVR();
}

// One element's (or item's, or delimiter's) header.
struct ElementHeader {
  unsigned group = 0, element = 0;
  std::string vr;  // empty for implicit VR and for items and delimiters
  std::uint32_t length = 0;
  std::uint64_t value_at = 0;
  bool is(unsigned g, unsigned e) const { return group == g && element == e; }
  std::string tag() const { return fmt::format("({:04x},{:04x})", group, element); }
  std::uint64_t end() const { return value_at + length; }
};

class StructureWalk {
 public:
  explicit StructureWalk(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    std::error_code ec;
    size_ = std::filesystem::file_size(path, ec);
    if (ec || !in_) throw Error(fmt::format("{}: cannot be read: {}", path, ec.message()));
  }

  void run() {
    if (size_ < 132 || !read(128, 4) || std::memcmp(bytes_.data(), "DICM", 4) != 0)
      throw Error(fmt::format("{}: not a DICOM Part 10 file (no \"DICM\" after the 128-byte "
                              "preamble)",
                              path_));
    const std::uint64_t data_set = metaGroup(132);
    if (data_set >= size_)
      throw Error(fmt::format("{}: the file ends after its meta group (no data set)", path_));
    dataSet(data_set, size_, 0, false);
  }

 private:
  [[noreturn]] void fail(std::uint64_t at, const std::string& what) const {
    throw Error(fmt::format("{}: {} at byte {}; not a well-formed DICOM file", path_, what, at));
  }

  bool read(std::uint64_t at, std::size_t n) {
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(at));
    in_.read(reinterpret_cast<char*>(bytes_.data()), static_cast<std::streamsize>(n));
    return static_cast<std::size_t>(in_.gcount()) == n;
  }
  std::uint32_t number(std::size_t at, int n) const {
    std::uint32_t v = 0;
    for (int i = 0; i < n; ++i)
      v |= std::uint32_t{bytes_[at + static_cast<std::size_t>(little_ ? i : n - 1 - i)]} << (8 * i);
    return v;
  }

  // The header at `at`, which must lie inside [at, end) with its value.
  ElementHeader header(std::uint64_t at, std::uint64_t end) {
    if (at + 8 > end || !read(at, 8)) fail(at, "an element header runs past its container's end");
    ElementHeader h;
    h.group = number(0, 2);
    h.element = number(2, 2);
    const std::string vr{static_cast<char>(bytes_[4]), static_cast<char>(bytes_[5])};
    if (h.group == 0xfffe || !explicit_vr_) {
      h.length = number(4, 4);
      h.value_at = at + 8;
    } else if (isVrIn(vr, kShortVrs)) {
      h.vr = vr;
      h.length = number(6, 2);
      h.value_at = at + 8;
    } else if (isVrIn(vr, kLongVrs)) {
      if (at + 12 > end || !read(at + 8, 4)) fail(at, "an element header runs past its end");
      h.vr = vr;
      h.length = number(0, 4);
      h.value_at = at + 12;
    } else {
      fail(at, fmt::format("element {} has VR {:02x} {:02x}, not one of PS3.5's",
                           h.tag(), bytes_[4], bytes_[5]));
    }
    // GDCM asserts that an explicit VR agrees with the dictionary's when it reads image
    // attributes (ImageHelper::GetSpacingValue, found by fuzz_dicom). UN is the VR of an
    // element whose VR its writer did not know.
    if (!h.vr.empty() && h.vr != "UN") {
      const gdcm::VR known = dictionaryVr(h.group, h.element);
      if (known != gdcm::VR::INVALID && known != gdcm::VR::UN &&
          !known.Compatible(gdcm::VR(gdcm::VR::GetVRType(h.vr.c_str()))))
        fail(at, fmt::format("element {} has VR {} where DICOM's data dictionary says {}",
                             h.tag(), h.vr, gdcm::VR::GetVRString(known)));
    }
    if (h.group == 0xfffe && h.element != 0xe000 && h.length != 0)  // PS3.5 7.5
      fail(at, fmt::format("delimiter {} has length {} (a delimiter's is 0)", h.tag(), h.length));
    if (h.length != kUndefinedLength && h.end() > end)
      fail(at, fmt::format("element {} {}has length {}, past its container's end (byte {})",
                           h.tag(), h.vr.empty() ? "" : h.vr + " ", h.length, end));
    return h;
  }

  // An item's or a delimiter's header where `container` expects one.
  ElementHeader itemHeader(std::uint64_t at, std::uint64_t end, const std::string& container) {
    if (at + 4 <= end && read(at, 4) && number(0, 2) != 0xfffe)
      fail(at, fmt::format("({:04x},{:04x}) where {} expects an item (fffe,e000)", number(0, 2),
                           number(2, 2), container));
    return header(at, end);
  }

  // Group 0002, always explicit VR little endian; sets the data set's syntax from (0002,0010).
  // Returns where the data set starts.
  std::uint64_t metaGroup(std::uint64_t at) {
    std::string syntax;
    bool has_syntax = false;
    while (at + 8 <= size_ && read(at, 2) && number(0, 2) == 0x0002) {
      const ElementHeader h = header(at, size_);
      if (h.vr == "SQ" || h.length == kUndefinedLength)
        fail(at, fmt::format("file meta element {} is a sequence or has an undefined length",
                             h.tag()));
      if (h.is(0x0002, 0x0010)) {
        if (h.length > 64) fail(at, fmt::format("TransferSyntaxUID has length {}", h.length));
        syntax.resize(h.length);
        in_.seekg(static_cast<std::streamoff>(h.value_at));
        in_.read(syntax.data(), h.length);
        syntax = withoutPadding(std::move(syntax));
        has_syntax = true;
      }
      at = h.end();
    }
    if (!has_syntax) fail(at, "the meta group names no TransferSyntaxUID (0002,0010) before");
    if (syntax == kDeflated)
      throw Error(fmt::format("{}: its data set is deflated (transfer syntax {}); svr reads "
                              "uncompressed data sets (the pixels may be compressed)",
                              path_, syntax));
    explicit_vr_ = syntax != kImplicitLittle;
    little_ = syntax != kExplicitBig;
    return at;
  }

  // The elements in [at, end). Inside an item of undefined length the walk stops at its item
  // delimiter (returning the position after it), which must come before `end`.
  std::uint64_t dataSet(std::uint64_t at, std::uint64_t end, int depth, bool until_delimiter) {
    while (at < end) {
      const ElementHeader h = header(at, end);
      if (h.group == 0xfffe) {
        if (!until_delimiter || !h.is(0xfffe, 0xe00d))
          fail(at, fmt::format("item tag {} outside the sequence it belongs to", h.tag()));
        return h.value_at;
      }
      if (h.group == 0x0002 && depth == 0)
        fail(at, fmt::format("file meta element {} inside the data set", h.tag()));
      at = h.length == kUndefinedLength ? undefinedValue(h, at, end, depth)
                                        : definedValue(h, depth);
    }
    if (until_delimiter) fail(at, "an item of undefined length ends without its delimiter");
    return at;
  }

  std::uint64_t definedValue(const ElementHeader& h, int depth) {
    // Implicit VR names no SQ; a value that opens with an item tag is read as a sequence.
    bool sequence = h.vr == "SQ";
    if (!explicit_vr_ && h.length >= 8 && read(h.value_at, 4))
      sequence = number(0, 2) == 0xfffe && number(2, 2) == 0xe000;
    return sequence ? items(h, h.end(), depth + 1) : h.end();
  }

  std::uint64_t undefinedValue(const ElementHeader& h, std::uint64_t at, std::uint64_t end,
                               int depth) {
    if (h.is(0x7fe0, 0x0010) && (h.vr == "OB" || h.vr == "OW")) return fragments(h, end);
    if (explicit_vr_ && h.vr != "SQ" && h.vr != "UN")
      fail(at, fmt::format("element {} {} has an undefined length (only sequences, UN and "
                           "encapsulated pixel data may)",
                           h.tag(), h.vr));
    if (h.vr != "UN") return items(h, end, depth + 1);
    // PS3.5 6.2.2: a UN of undefined length is a sequence encoded in implicit VR little endian.
    const bool explicit_vr = explicit_vr_, little = little_;
    explicit_vr_ = false;
    little_ = true;
    const std::uint64_t after = items(h, end, depth + 1);
    explicit_vr_ = explicit_vr;
    little_ = little;
    return after;
  }

  // A sequence's items: up to h.end() when its length is defined, else up to its delimiter,
  // which must come before `end`.
  std::uint64_t items(const ElementHeader& h, std::uint64_t end, int depth) {
    if (depth > kMaxDepth)
      fail(h.value_at, fmt::format("sequences nested more than {} deep", kMaxDepth));
    const bool defined = h.length != kUndefinedLength;
    const std::uint64_t stop = defined ? h.end() : end;
    for (std::uint64_t at = h.value_at;;) {
      if (defined && at == stop) return at;
      const ElementHeader item = itemHeader(at, stop, "sequence " + h.tag());
      if (item.is(0xfffe, 0xe0dd) && !defined) return item.value_at;
      if (!item.is(0xfffe, 0xe000))
        fail(at, fmt::format("{} where sequence {} expects an item (fffe,e000)", item.tag(),
                             h.tag()));
      at = item.length == kUndefinedLength ? dataSet(item.value_at, stop, depth, true)
                                           : dataSet(item.value_at, item.end(), depth, false);
    }
  }

  // Encapsulated pixel data: items of defined length (the offset table, then the fragments) up
  // to the sequence delimiter.
  std::uint64_t fragments(const ElementHeader& h, std::uint64_t end) {
    for (std::uint64_t at = h.value_at;;) {
      const ElementHeader item = itemHeader(at, end, "the encapsulated pixel data");
      if (item.is(0xfffe, 0xe0dd)) return item.value_at;
      if (!item.is(0xfffe, 0xe000) || item.length == kUndefinedLength)
        fail(at, fmt::format("{} of length {} where the encapsulated pixel data expects a "
                             "fragment (fffe,e000) of defined length",
                             item.tag(), item.length));
      at = item.end();
    }
  }

  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  bool explicit_vr_ = true, little_ = true;
  std::array<unsigned char, 8> bytes_{};
};

}  // namespace

void checkDicomStructure(const std::string& path) { StructureWalk(path).run(); }

std::string withoutPadding(std::string value) {
  while (!value.empty() && (value.back() == '\0' || value.back() == ' ')) value.pop_back();
  return value;
}

}  // namespace svr::detail
