#include "vtk_compression.h"

#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

#include <climits>
#include <cstdint>

namespace dtm {

std::optional<VtkCompressor> vtk_compressor_named(std::string_view name) {
  if (name == "vtkZLibDataCompressor") return VtkCompressor::kZlib;
  if (name == "vtkLZ4DataCompressor") return VtkCompressor::kLz4;
  if (name == "vtkLZMADataCompressor") return VtkCompressor::kLzma;
  return std::nullopt;
}

std::string decompress_vtk_block(VtkCompressor compressor, std::string_view block, size_t size,
                                 std::string& out) {
  const size_t at = out.size();
  out.resize(at + size);
  auto* dest = reinterpret_cast<uint8_t*>(out.data() + at);
  const auto* src = reinterpret_cast<const uint8_t*>(block.data());
  switch (compressor) {
    case VtkCompressor::kZlib: {
      // A zlib stream (RFC 1950) per block, as compress2() writes it.
      if (size > ULONG_MAX || block.size() > ULONG_MAX) return "a block too large for zlib";
      uLongf made = static_cast<uLongf>(size);
      const int r = uncompress(dest, &made, src, static_cast<uLong>(block.size()));
      if (r == Z_BUF_ERROR) return "a zlib block holds more than its " + std::to_string(size) + " bytes";
      if (r != Z_OK) return "a zlib block is corrupt";
      if (made != size)
        return "a zlib block holds " + std::to_string(made) + " bytes, its header says " +
               std::to_string(size);
      return "";
    }
    case VtkCompressor::kLz4: {
      // A raw LZ4 block, as LZ4_compress_default() writes it.
      if (size > INT_MAX || block.size() > INT_MAX) return "a block too large for LZ4";
      const int made = LZ4_decompress_safe(block.data(), out.data() + at, static_cast<int>(block.size()),
                                           static_cast<int>(size));
      if (made < 0)
        return "an LZ4 block is corrupt or holds more than its " + std::to_string(size) + " bytes";
      if (static_cast<size_t>(made) != size)
        return "an LZ4 block holds " + std::to_string(made) + " bytes, its header says " +
               std::to_string(size);
      return "";
    }
    case VtkCompressor::kLzma: {
      // An .xz stream per block, as lzma_easy_buffer_encode() writes it.
      // The decoder's state, its dictionary mostly, as the block's header
      // asks: xz's largest preset needs 65 MiB; a block asking more than
      // 128 MiB is refused rather than allocated.
      uint64_t memory = uint64_t{1} << 27;
      size_t in_pos = 0, out_pos = 0;
      const lzma_ret r =
          lzma_stream_buffer_decode(&memory, 0, nullptr, src, &in_pos, block.size(), dest, &out_pos, size);
      if (r == LZMA_BUF_ERROR)
        return "an LZMA block is cut short or holds more than its " + std::to_string(size) + " bytes";
      if (r == LZMA_MEMLIMIT_ERROR) return "an LZMA block asks for more than 128 MiB to decode";
      if (r != LZMA_OK) return "an LZMA block is corrupt";
      if (out_pos != size)
        return "an LZMA block holds " + std::to_string(out_pos) + " bytes, its header says " +
               std::to_string(size);
      return "";
    }
  }
  return "unknown compressor";
}

}  // namespace dtm
