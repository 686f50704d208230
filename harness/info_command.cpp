#include "harness/info_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "harness/command.h"
#include "renderers/volume/volume_description.h"
#include "base/error.h"

namespace svr {

int runInfo(const InfoOptions& options) {
  VolumeLoadOptions load{options.memory_budget, options.raw};
  load.spacing = options.spacing;
  const VolumeHeader header = readVolumeHeader(options.path, load);
  const Volume volume = loadVolume(options.path, load);
  fmt::print("{}", describeVolume(header, volume));
  return 0;
}

namespace {

// The --raw-… flags as given on the command line, before they are checked.
struct RawFlags {
  std::vector<int> dims;
  std::vector<double> spacing;
  std::string type, endian = "little";
  std::uint64_t header_bytes = 0;
};

RawLayout rawLayout(const RawFlags& f, bool spacing_given, const std::string& path) {
  if (f.dims.size() != 3 || f.type.empty())
    throw Error(fmt::format("{}: a raw layout needs --raw-dims X,Y,Z and --raw-type", path));
  RawLayout layout;
  layout.dims = {f.dims[0], f.dims[1], f.dims[2]};
  try {
    layout.type = parseScalarType(f.type);
  } catch (const Error& e) {
    throw Error(fmt::format("--raw-type: {}", e.what()));
  }
  layout.endian = f.endian == "big" ? Endian::kBig : Endian::kLittle;
  if (spacing_given) {
    if (f.spacing.size() != 3)
      throw Error(fmt::format("--raw-spacing: {} values given; expected X,Y,Z", f.spacing.size()));
    layout.spacing = {f.spacing[0], f.spacing[1], f.spacing[2]};
  }
  layout.header_bytes = f.header_bytes;
  return layout;
}

}  // namespace

namespace commands {

CommandEntry info() {
  return {"info", "what a volume file holds: layout, spacing, world box, value range, histogram",
          [](CLI::App& sub, CommandContext&) {
            auto o = std::make_shared<InfoOptions>();
            auto raw = std::make_shared<RawFlags>();
            auto budget = std::make_shared<std::string>();
            sub.add_option("FILE", o->path,
                           "volume file: .nrrd, .nhdr, .mhd, .mha, .nii, .nii.gz, .tif, .tiff, a "
                           "folder (a DICOM series or numbered TIFFs), or raw")
                ->required();
            auto spacing = std::make_shared<std::vector<double>>();
            auto* spacing_flag = sub.add_option("--spacing", *spacing,
                                                "TIFF stacks: voxel spacing X,Y,Z (default 1,1,1)")
                                     ->delimiter(',');
            std::vector<CLI::Option*> raw_flags{
                sub.add_option("--raw-dims", raw->dims, "headerless raw file: voxels X,Y,Z")
                    ->delimiter(','),
                sub.add_option("--raw-type", raw->type,
                               "headerless raw file: uint8, int8, uint16, int16, uint32, int32, "
                               "float32 or float64"),
                sub.add_option("--raw-endian", raw->endian, "headerless raw file: byte order")
                    ->check(CLI::IsMember({"little", "big"}))
                    ->capture_default_str(),
                sub.add_option("--raw-spacing", raw->spacing, "headerless raw file: X,Y,Z")
                    ->delimiter(','),
                sub.add_option("--raw-header-bytes", raw->header_bytes,
                               "headerless raw file: bytes to skip first")};
            sub.add_option("--memory-budget", *budget,
                           "most bytes of voxels to load, e.g. 512M or 2G (default: the memory "
                           "available now)");
            sub.callback([o, raw, budget, raw_flags, spacing, spacing_flag] {
              if (!budget->empty()) o->memory_budget = parseByteSize(*budget, "--memory-budget");
              if (spacing_flag->count() > 0) {
                const std::vector<double>& v = *spacing;
                if (v.size() != 3 || !std::all_of(v.begin(), v.end(), [](double x) {
                      return std::isfinite(x) && x > 0;
                    }))
                  throw Error(fmt::format("--spacing: expected three finite values > 0 (X,Y,Z); "
                                          "got {} values",
                                          v.size()));
                o->spacing = glm::dvec3(v[0], v[1], v[2]);
              }
              std::size_t given = 0;
              for (const auto* flag : raw_flags) given += flag->count();
              if (given > 0) o->raw = rawLayout(*raw, raw_flags[3]->count() > 0, o->path);
              runInfo(*o);
            });
          }};
}

}  // namespace commands

}  // namespace svr
