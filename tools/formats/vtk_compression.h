// The block compressors of VTK's XML writers (vtkZLibDataCompressor,
// vtkLZ4DataCompressor, vtkLZMADataCompressor), which ParaView, VTK and
// meshio use by default: an array's bytes cut into blocks of one size, each
// compressed on its own, behind a header of block sizes (vtu_reader.cpp
// reads the header). Decompressed through Debian's zlib, liblz4 and liblzma.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace dtm {

enum class VtkCompressor { kZlib, kLz4, kLzma };

// The compressor a VTKFile's `compressor` attribute names, if known.
std::optional<VtkCompressor> vtk_compressor_named(std::string_view name);

// Decompresses one block, which must give exactly `size` bytes, appending
// them to `out`. Returns "" or what is wrong with the block.
std::string decompress_vtk_block(VtkCompressor compressor, std::string_view block, size_t size,
                                 std::string& out);

}  // namespace dtm
