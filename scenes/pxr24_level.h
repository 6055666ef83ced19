// The zlib level of OpenEXR's PXR24 files (the report folder's kept references, frames and
// estimates, kept_references.h). OpenEXR 3.1.5's PXR24 compressor deflates with zlib's
// compress() (ImfPxr24Compressor.cpp), which is level 6, and has no setting for it (its ZIP
// compressor takes the header's zip level, PXR24 does not). OpenEXR 3.2 and later deflate PXR24
// through their Core library (libdeflate) at a default level a caller can set; there this
// override does nothing and KeptReferences.Pxr24DeflatesThroughTheExecutablesCompress fails,
// which is the cue to set that level instead.
// scenes/exr_io.cpp defines compress() in the executable, where it comes before libz's in
// the dynamic linker's search (ELF symbol interposition; the link exports it,
// --export-dynamic-symbol=compress in CMakeLists.txt), as zlib's compress2() at kPxr24ZlibLevel.
// aoeval's own deflates call compress2, as do OpenEXR's ZIP and DWA compressors; of the other
// libraries that import compress() (OIIO's dependencies libavcodec and libspatialite, per
// LD_DEBUG=bindings, and libOpenEXRCore, whose own PXR24 writer OIIO 2.4 does not use) none
// runs in aoeval's paths, and any would still write a valid zlib stream.
// So only PXR24's level changes, and its files read back bit for bit (a deflate stream at any
// level inflates to the same bytes).
//
// Level 4 (issue 42), measured over the 1635 PXR24 files of a cold default run's folder, rewritten
// at each level (the process CPU time of the writes, OIIO from Python): level 6 16.4 s of CPU and
// 115.5 MB, level 5 10.7 s and 117.5 MB, level 4 7.9 s and 119.0 MB. Below 4 zlib switches to
// its lazy-match-free strategy and the kept frames grow by 9-18 % (level 3 to 1).
#pragma once

#include <cstdint>

namespace aoeval {

inline constexpr int kPxr24ZlibLevel = 4;

// How many times this process's compress() ran (tests: OpenEXR's PXR24 writes do reach it).
uint64_t pxr24_deflate_count();

}  // namespace aoeval
