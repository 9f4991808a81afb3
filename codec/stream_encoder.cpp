#include <algorithm>
#include <iterator>
#include <optional>
#include <string>

#include "codec/carving_coder.h"
#include "codec/expert_encode.h"
#include "codec/format.h"
#include "codec/layer_coder.h"

namespace dtm {

StatusOr<EncodedStream> encode_stream(const Hierarchy& hierarchy, std::span<const GridPoint> points,
                                      const Grid& grid, AlphaKind alpha_policy, const StreamOptions& options,
                                      std::vector<FieldValues> fields) {
  const auto invalid = [](const std::string& what) { return Status{StatusCode::kInvalidInput, what}; };
  if (options.level_step < 1) return invalid("encode_stream: level_step < 1");
  std::vector<int> streamed;
  for (size_t i = 0; i < hierarchy.levels.size(); ++i)
    if (i % options.level_step == 0 || i + 1 == hierarchy.levels.size())
      streamed.push_back(static_cast<int>(i));
  if (streamed.empty() || streamed.size() > 0xFFFF) return invalid("encode_stream: level count out of range");
  StreamHeader h;
  h.grid = grid;
  h.alpha_policy = alpha_policy;
  // The hierarchy carries its verdicts when it was carved to a reference:
  // then every layer corrects alpha's prediction.
  const bool corrections = !hierarchy.levels[0].kept.empty();
  const bool values = !fields.empty();
  std::vector<FieldDescription> descriptions;
  std::vector<size_t> value_counts;
  for (const FieldValues& f : fields)
    descriptions.push_back(f.description), value_counts.push_back(f.bits.size());
  DTM_RETURN_IF_ERROR(check_fields(descriptions, value_counts, points.size()).with_context("encode_stream"));
  std::optional<FieldSectionEncoder> value_coder;
  if (values) {
    auto made = FieldSectionEncoder::make(std::move(fields));
    if (!made.ok()) return made.status();
    value_coder.emplace(std::move(*made));
  }
  h.version_major = corrections ? kVersionMajor
                    : values    ? kVersionMajorWithValues
                                : kVersionMajorWithoutValues;
  h.flags = (options.cell_hashes ? kFlagCellHashes : 0) | (corrections ? kFlagCarvingCorrections : 0) |
            (values ? kFlagValues : 0);
  h.level_count = static_cast<uint16_t>(streamed.size());
  h.vertex_count = static_cast<uint32_t>(hierarchy.levels[0].vertices.size());

  EncodedStream out;
  out.bytes = write_header(h);
  if (value_coder) {
    out.fields = value_coder->descriptions();
    const auto table = write_field_table(out.fields);
    out.field_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  out.layer_bytes.assign(hierarchy.levels.size(), 0);
  out.carving_bytes.assign(hierarchy.levels.size(), 0);
  out.value_bytes.assign(hierarchy.levels.size(), 0);
  // The decoder's vertex index of each grid point, and its points in order.
  std::vector<uint32_t> decoder_index(points.size(), UINT32_MAX);
  std::vector<GridPoint> decoded;
  out.streamed_levels = streamed;
  std::vector<uint32_t> coarser;  // V_{l+1}, ascending
  std::vector<MortonCode> known;  // Morton codes of V_{l+1}, ascending
  SetCoderModels models;          // adapted layer after layer, as the decoder's
  models.enable_coordinate_reuse(grid.qbits);
  for (size_t l = streamed.size(); l-- > 0;) {
    const Level& level = hierarchy.levels[streamed[l]];
    std::vector<uint32_t> added;
    std::set_difference(level.vertices.begin(), level.vertices.end(), coarser.begin(), coarser.end(),
                        std::back_inserter(added));
    if (added.size() + coarser.size() != level.vertices.size())
      return invalid("encode_stream: levels are not nested");
    // In the decoder's order: the layer coder sends a set, which comes out
    // in ascending Morton order.
    std::vector<std::pair<MortonCode, uint32_t>> by_code;
    by_code.reserve(added.size());
    for (uint32_t i : added) by_code.emplace_back(morton_encode(points[i], grid.qbits), i);
    std::sort(by_code.begin(), by_code.end());
    std::vector<GridPoint> layer_points;
    std::vector<uint32_t> layer_indices;
    layer_points.reserve(added.size());
    for (const auto& [code, i] : by_code) {
      layer_points.push_back(points[i]);
      layer_indices.push_back(i);
      decoder_index[i] = static_cast<uint32_t>(out.decode_order.size());
      out.decode_order.push_back(i);
      decoded.push_back(points[i]);
    }
    std::vector<uint8_t> carving;
    if (corrections) {
      if (level.kept.size() != level.delaunay.cells.size())
        return invalid("encode_stream: a level without its carving verdicts");
      TetMesh dt = level.delaunay;
      for (auto& c : dt.cells)
        for (uint32_t& v : c) v = decoder_index[v];
      carving = encode_carving(dt, decoded, level.alpha, level.kept, carving_contexts(h.version_major));
    }

    std::vector<uint8_t> value_section;
    if (value_coder) {
      std::vector<uint64_t> layer_field_bytes;
      value_section = value_coder->encode_layer(layer_indices, layer_points, layer_field_bytes);
      out.field_bytes.resize(layer_field_bytes.size(), 0);
      for (size_t f = 0; f < layer_field_bytes.size(); ++f) out.field_bytes[f] += layer_field_bytes[f];
      out.level_field_bytes.resize(hierarchy.levels.size());
      out.level_field_bytes[streamed[l]] = std::move(layer_field_bytes);
    }

    LayerHeader lh;
    lh.format_major = h.version_major;
    lh.level = static_cast<uint16_t>(l);
    lh.new_vertices = static_cast<uint32_t>(added.size());
    lh.level_vertices = static_cast<uint32_t>(level.vertices.size());
    lh.alpha = level.alpha;
    if (options.cell_hashes) lh.cell_hash = cell_set_hash(points, level.carved_cells());
    const auto layer =
        write_layer(lh, encode_point_set(known, layer_points, grid.qbits, models), carving, value_section);
    out.carving_bytes[streamed[l]] = carving.size();
    out.value_bytes[streamed[l]] = value_section.size();
    merge_known(known, layer_points, grid.qbits);
    out.layer_bytes[streamed[l]] = layer.size();
    out.bytes.insert(out.bytes.end(), layer.begin(), layer.end());
    coarser = level.vertices;
  }
  return out;
}

}  // namespace dtm
