#pragma once
// Shared by the libFuzzer targets (one parser each; docs/robustness.md): a private
// scratch folder holding small fixture files that fuzzed headers and scenes may refer to, the
// spectrum library and observer loaded once, and the memory budget the fuzzed volumes get.
//
// A target passes an input when the parser returns or throws svr::Error; anything else (a
// sanitizer report, another exception, a timeout, an allocation above -malloc_limit_mb) is a
// finding.

#include <cstddef>
#include <cstdint>
#include <string>

#include "spectral/colorimetry.h"
#include "spectral/spectrum_library.h"

namespace svr::fuzz {

// Small enough that a fuzzed header or scene cannot make a single run slow or memory-bound, big
// enough for the fixtures and every seed's volume.
inline constexpr std::uint64_t kMemoryBudget = std::uint64_t{1} << 20;

// The scratch folder (created on first use, removed at exit). It holds
//   data.raw      64 bytes (4×4×4 uint8 0..63)      data.raw.gz  the same, gzip-compressed
//   data.zlib     the same, zlib-compressed          volume.nhdr  a detached header for data.raw
//   spectrum.csv  a two-column spectrum table on 380…780 nm
//   series/       IM0001.dcm, a good slice of tests/data/formats/series
const std::string& scratchDir();

// Writes the input to scratchDir()/name (replacing it) and returns the path.
std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size);

// Writes the input to scratchDir()/name and loads it as a volume (header, budget check, payload)
// under kMemoryBudget: the NRRD and MetaImage targets differ only in the name's extension.
int loadVolumeInput(const std::string& name, const std::uint8_t* data, std::size_t size);
// Writes the input to scratchDir()/name and loads the folder holding it (a DICOM series).
int loadFolderInput(const std::string& name, const std::uint8_t* data, std::size_t size);
const SpectrumLibrary& library();
const Observer& observer();

}  // namespace svr::fuzz
