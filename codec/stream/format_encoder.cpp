#include "codec/stream/format_encoder.h"

#include <stdexcept>

#include "codec/stream/header_fields.h"

namespace dtm {

using header_fields::FieldWriter;
using header_fields::read_fields;

std::vector<uint8_t> write_header(StreamHeader h) {
  FieldWriter writer;
  visit_fields(h, writer);
  return writer.w.take();
}

std::vector<uint8_t> write_layer(LayerHeader h, std::span<const uint8_t> payload,
                                 std::span<const uint8_t> carving, std::span<const uint8_t> values,
                                 std::span<const uint8_t> candidates, std::span<const uint8_t> regions,
                                 std::span<const uint8_t> faces, std::span<const uint8_t> cell_values,
                                 std::span<const uint8_t> order, std::span<const uint8_t> exact,
                                 std::span<const uint8_t> edge_nodes, std::span<const uint8_t> edge_values,
                                 std::span<const uint8_t> node_order, std::span<const uint8_t> node_labels) {
  h.candidate_bytes = static_cast<uint32_t>(candidates.size());
  h.payload_bytes = static_cast<uint32_t>(payload.size());
  h.carving_bytes = static_cast<uint32_t>(carving.size());
  h.value_bytes = static_cast<uint32_t>(values.size());
  h.region_bytes = static_cast<uint32_t>(regions.size());
  h.face_bytes = static_cast<uint32_t>(faces.size());
  h.cell_value_bytes = static_cast<uint32_t>(cell_values.size());
  h.order_bytes = static_cast<uint32_t>(order.size());
  h.exact_bytes = static_cast<uint32_t>(exact.size());
  h.edge_node_bytes = static_cast<uint32_t>(edge_nodes.size());
  h.edge_value_bytes = static_cast<uint32_t>(edge_values.size());
  h.node_order_bytes = static_cast<uint32_t>(node_order.size());
  h.node_label_bytes = static_cast<uint32_t>(node_labels.size());
  std::vector<uint8_t> body(candidates.begin(), candidates.end());
  body.insert(body.end(), payload.begin(), payload.end());
  body.insert(body.end(), carving.begin(), carving.end());
  body.insert(body.end(), regions.begin(), regions.end());
  body.insert(body.end(), faces.begin(), faces.end());
  body.insert(body.end(), values.begin(), values.end());
  body.insert(body.end(), cell_values.begin(), cell_values.end());
  body.insert(body.end(), order.begin(), order.end());
  body.insert(body.end(), exact.begin(), exact.end());
  body.insert(body.end(), edge_nodes.begin(), edge_nodes.end());
  body.insert(body.end(), edge_values.begin(), edge_values.end());
  body.insert(body.end(), node_order.begin(), node_order.end());
  body.insert(body.end(), node_labels.begin(), node_labels.end());
  FieldWriter writer;
  writer.trailer = body;
  visit_fields(h, writer);
  // (23.0: a section whose length the stream's flags leave out of the
  // header would make a stream no decoder reads: the caller's error.)
  const std::vector<uint8_t>& header = writer.w.data();
  const LayerHeader back = read_fields<LayerHeader>(header, h.format_major, h.bricked, h.stream_flags);
  if (back.body_bytes() != h.body_bytes())
    throw std::logic_error("write_layer: a section the stream's flags have no length for in this layer");
  writer.w.bytes(body);
  return writer.w.take();
}

std::vector<uint8_t> write_bricked_layer(LayerHeader h, std::span<const uint8_t> index,
                                         std::span<const uint8_t> chunks) {
  h.bricked = true;
  h.index_bytes = static_cast<uint32_t>(index.size());
  h.chunk_bytes = chunks.size();
  FieldWriter writer;
  writer.trailer = index;
  visit_fields(h, writer);
  writer.w.bytes(index);
  writer.w.bytes(chunks);
  return writer.w.take();
}

}  // namespace dtm
