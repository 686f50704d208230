#pragma once
// A DICOM Part 10 file's framing, checked before GDCM reads it. GDCM (Debian's build keeps its
// asserts) aborts on some malformed meta groups and allocates whatever an element's length field
// says (both found by fuzz_dicom), so svr walks the file first:
//   - the 128-byte preamble and "DICM";
//   - the meta group (0002,xxxx) in explicit VR little endian, which must name the transfer
//     syntax (0002,0010);
//   - every element of the data set in that syntax (implicit or explicit VR, little or big
//     endian), into sequences, their items and encapsulated pixel data.
// Every length must end inside its container (the file, a sequence, an item); an undefined
// length is taken only where the standard allows one (a sequence, UN, encapsulated pixel
// data); delimiters have length 0; nesting is at most 32 deep; an explicit VR agrees with the
// data dictionary's for a public tag (GDCM asserts that too). Values are skipped, not read:
// this is the file's framing only, what its elements say is for GDCM and the series reader.
// The deflated transfer syntax is refused (its data set cannot be walked without inflating it).

#include <string>

namespace svr::detail {

// Throws svr::Error "PATH: <what> at byte N" for the first fault.
void checkDicomStructure(const std::string& path);

// A value without the padding DICOM adds to make its length even (a space, or NUL for UIDs).
std::string withoutPadding(std::string value);

}  // namespace svr::detail
