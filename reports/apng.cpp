// Animated PNG writer (see apng.h). A PNG is the signature and chunks: length (4 bytes, big
// endian), type (4), data, CRC-32 of type and data. An APNG adds, after IHDR, acTL (frame count,
// play count 0 = for ever), and before each frame's data an fcTL (sequence number, size, offset,
// delay as a fraction of a second, dispose and blend operations); frame 0's data stays in IDAT
// (what a viewer without APNG support shows), every later frame's is in fdAT chunks (a sequence
// number, then the same zlib stream an IDAT would hold). Sequence numbers count fcTL and fdAT
// chunks together from 0.
#include "reports/apng.h"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "base/text_files.h"

namespace aoeval {

namespace {

namespace fs = std::filesystem;

using Bytes = std::vector<uint8_t>;

uint32_t crc32(const uint8_t* data, size_t n, uint32_t crc = 0) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

// Appends big-endian bytes (a range insert: GCC 12's -Wstringop-overflow misfires on push_back
// into an empty vector).
void put32(Bytes& out, uint32_t v) {
  const uint8_t b[4] = {static_cast<uint8_t>(v >> 24), static_cast<uint8_t>(v >> 16),
                        static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v)};
  out.insert(out.end(), b, b + 4);
}
void put16(Bytes& out, uint32_t v) {
  const uint8_t b[2] = {static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v)};
  out.insert(out.end(), b, b + 2);
}
uint32_t get32(const Bytes& in, size_t at) {
  return (uint32_t{in[at]} << 24) | (uint32_t{in[at + 1]} << 16) | (uint32_t{in[at + 2]} << 8) |
         uint32_t{in[at + 3]};
}

void chunk(Bytes& out, const char type[5], const Bytes& data) {
  put32(out, static_cast<uint32_t>(data.size()));
  const size_t from = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  put32(out, crc32(out.data() + from, out.size() - from));
}

struct Png {
  Bytes ihdr, idat;  // IHDR's data; every IDAT's data, concatenated (one zlib stream)
  std::vector<std::pair<std::string, Bytes>> ancillary;  // chunks between IHDR and IDAT
};

const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

// One frame through OpenImageIO's PNG writer, split into its chunks.
Png encode(const OIIO::ImageBuf& frame, const std::string& scratch) {
  if (!frame.write(scratch, OIIO::TypeDesc::UINT8, "png"))
    throw std::runtime_error(scratch + ": OpenImageIO cannot write PNG: " + frame.geterror());
  std::ifstream in(scratch, std::ios::binary);
  const Bytes file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::error_code ec;
  fs::remove(scratch, ec);
  if (file.size() < 8 || !std::equal(kSignature, kSignature + 8, file.begin()))
    throw std::runtime_error(scratch + ": not a PNG");
  Png png;
  for (size_t at = 8; at + 12 <= file.size();) {
    const uint32_t length = get32(file, at);
    if (at + 12 + length > file.size()) throw std::runtime_error(scratch + ": truncated chunk");
    const std::string type(file.begin() + static_cast<long>(at) + 4,
                           file.begin() + static_cast<long>(at) + 8);
    const Bytes data(file.begin() + static_cast<long>(at) + 8,
                     file.begin() + static_cast<long>(at + 8 + length));
    if (type == "IHDR") {
      png.ihdr = data;
    } else if (type == "IDAT") {
      png.idat.insert(png.idat.end(), data.begin(), data.end());
    } else if (type != "IEND" && png.idat.empty()) {
      png.ancillary.emplace_back(type, data);
    }
    at += 12 + length;
  }
  if (png.ihdr.size() != 13 || png.idat.empty())
    throw std::runtime_error(scratch + ": a PNG without IHDR or IDAT");
  return png;
}

// True when every pixel of every frame is 3-channel 8-bit with R = G = B (a grey picture in RGB).
bool all_grey(const std::vector<OIIO::ImageBuf>& frames) {
  for (const OIIO::ImageBuf& f : frames) {
    if (f.nchannels() != 3) return false;
    std::vector<uint8_t> px(size_t(f.spec().width) * size_t(f.spec().height) * 3);
    if (!f.get_pixels(f.roi(), OIIO::TypeDesc::UINT8, px.data())) return false;
    for (size_t k = 0; k < px.size(); k += 3)
      if (px[k] != px[k + 1] || px[k] != px[k + 2]) return false;
  }
  return true;
}

}  // namespace

void write_apng(const std::vector<OIIO::ImageBuf>& frames, double fps, const std::string& path) {
  if (frames.empty()) throw std::runtime_error(path + ": no frames");
  const std::string temp = temporary_path_for(path);
  // Grey frames in RGB are written as one grey channel (PNG colour type 0): the same 8-bit values,
  // a third of the data to deflate (a sequence's video, reference | estimate: 124 -> 80 KB a
  // frame).
  const bool grey = all_grey(frames);
  std::vector<Png> pngs;
  try {
    for (size_t i = 0; i < frames.size(); ++i) {
      const OIIO::ImageBuf frame =
          grey ? OIIO::ImageBufAlgo::channels(frames[i], 1, {0}) : frames[i];
      pngs.push_back(encode(frame, temp + ".frame" + std::to_string(i) + ".png"));
      // Every frame must decode with frame 0's header (size, bit depth, colour type, interlace).
      if (pngs.back().ihdr != pngs.front().ihdr)
        throw std::runtime_error(path + ": frame " + std::to_string(i) +
                                 " differs from frame 0 in size or pixel format");
    }
  } catch (...) {
    discard_temporary(temp);
    throw;
  }
  // The delay of every frame, delay_num / delay_den seconds: 1 / fps, fps rounded to a whole
  // number in [1, 65535].
  const uint32_t per_second =
      static_cast<uint32_t>(std::clamp<long>(std::lround(fps > 0.0 ? fps : 10.0), 1L, 65535L));
  Bytes out(kSignature, kSignature + 8);
  chunk(out, "IHDR", pngs.front().ihdr);
  Bytes actl;
  put32(actl, static_cast<uint32_t>(frames.size()));
  put32(actl, 0);  // loop for ever
  chunk(out, "acTL", actl);
  for (const auto& [type, data] : pngs.front().ancillary) chunk(out, type.c_str(), data);
  uint32_t sequence = 0;
  for (size_t i = 0; i < pngs.size(); ++i) {
    Bytes fctl;
    put32(fctl, sequence++);
    fctl.insert(fctl.end(), pngs[i].ihdr.begin(), pngs[i].ihdr.begin() + 8);  // width, height
    put32(fctl, 0);                                                           // x offset
    put32(fctl, 0);                                                           // y offset
    put16(fctl, 1);
    put16(fctl, per_second);
    put16(fctl, 0);  // dispose 0: none (the next frame covers it whole); blend 0: source
    chunk(out, "fcTL", fctl);
    if (i == 0) {
      chunk(out, "IDAT", pngs[i].idat);
    } else {
      Bytes fdat;
      put32(fdat, sequence++);
      fdat.insert(fdat.end(), pngs[i].idat.begin(), pngs[i].idat.end());
      chunk(out, "fdAT", fdat);
    }
  }
  chunk(out, "IEND", {});
  {
    std::ofstream file(temp, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
    if (!file) {
      discard_temporary(temp);
      throw std::runtime_error(path + ": cannot write " + temp);
    }
  }
  commit_temporary(temp, path);
}

}  // namespace aoeval
