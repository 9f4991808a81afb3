// The WebAssembly decoder's C interface, for the viewer's worker
// (web/page/worker.js) and for node (web/test/). A session is a LevelViewer:
// JavaScript writes each chunk into the buffer dtm_session_input() returns,
// calls dtm_session_feed(), then takes the completed levels one by one with
// dtm_session_next_level() and copies their arrays out of the heap (views
// into it are invalidated when memory grows).
//
// Nothing here throws into JavaScript: the decoder reports errors as a
// Status, and an exception (no memory) becomes the session's error.
#include <emscripten/emscripten.h>

#include <cstdint>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "codec/decode.h"
#include "web/level_view.h"

namespace {

struct Session {
  explicit Session(dtm::DecoderOptions options) : viewer(options) {}
  dtm::LevelViewer viewer;  // keeps the decoder's own errors
  std::vector<uint8_t> input;
  dtm::LevelView level;
  dtm::Status failure;  // an exception outside the decoder (no memory)
  std::string text;     // the last string handed out (a field name, a summary)
};

// How the stream stands at its end: ok, kTruncated or the error.
dtm::Status end_status(const Session* s) { return s->failure.ok() ? s->viewer.finish() : s->failure; }

const char* keep(Session* s, std::string text) {
  s->text = std::move(text);
  return s->text.c_str();
}

template <class F>
int32_t guarded(Session* s, F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    s->failure = {dtm::StatusCode::kLimitExceeded,
                  "out of memory: the stream needs more than this page can hold"};
  } catch (const std::exception& e) {
    s->failure = {dtm::StatusCode::kInternal, e.what()};
  }
  return -1;
}

const dtm::FieldDescription* field(Session* s, int32_t f) {
  const auto& fields = s->viewer.decoder().fields();
  return f >= 0 && static_cast<size_t>(f) < fields.size() ? &fields[f].description : nullptr;
}

}  // namespace

extern "C" {

// max_vertices: the most vertices the stream may make the session hold
// (refused before the level's payload is decoded).
EMSCRIPTEN_KEEPALIVE Session* dtm_session_create(double max_vertices) {
  dtm::DecoderOptions options;
  options.max_vertices = static_cast<uint64_t>(max_vertices);
  options.max_values = 64 * options.max_vertices;
  try {
    return new Session(options);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}

EMSCRIPTEN_KEEPALIVE void dtm_session_destroy(Session* s) { delete s; }

// A buffer of n bytes for the next chunk, or null without memory.
EMSCRIPTEN_KEEPALIVE uint8_t* dtm_session_input(Session* s, uint32_t n) {
  try {
    s->input.resize(n);
    return s->input.data();
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}

// Decodes the n bytes written into the input buffer: 0, or -1 on an error
// (dtm_session_error). Levels completed before an error stay available.
EMSCRIPTEN_KEEPALIVE int32_t dtm_session_feed(Session* s, uint32_t n) {
  if (!s->failure.ok()) return -1;
  return guarded(s, [&] {
    if (n > s->input.size()) throw std::invalid_argument("feed: more bytes than the input buffer holds");
    return s->viewer.feed(std::span(s->input.data(), n)).ok() ? 0 : -1;
  });
}

// At the end of the input: 0 every level decoded, 1 truncated (the levels
// decoded stand; dtm_session_error says where it ended), 2 an error.
EMSCRIPTEN_KEEPALIVE int32_t dtm_session_finish(Session* s) {
  const dtm::Status status = end_status(s);
  return status.ok() ? 0 : status.code() == dtm::StatusCode::kTruncated ? 1 : 2;
}

// Why decoding stopped (after a failed feed), or how the input ended.
EMSCRIPTEN_KEEPALIVE const char* dtm_session_error(Session* s) { return keep(s, end_status(s).message()); }

// The stream header, once dtm_session_has_header().
EMSCRIPTEN_KEEPALIVE int32_t dtm_session_has_header(Session* s) {
  return s->viewer.decoder().has_header() ? 1 : 0;
}
EMSCRIPTEN_KEEPALIVE int32_t dtm_header_version(Session* s) {
  const auto& h = s->viewer.decoder().header();
  return h.version_major * 100 + h.version_minor;
}
EMSCRIPTEN_KEEPALIVE int32_t dtm_header_qbits(Session* s) { return s->viewer.decoder().header().grid.qbits; }
EMSCRIPTEN_KEEPALIVE double dtm_header_step(Session* s) { return s->viewer.decoder().header().grid.step; }
// The grid's centre in input units, axis 0-2: what the positions are relative to.
EMSCRIPTEN_KEEPALIVE double dtm_header_centre(Session* s, int32_t axis) {
  return dtm::grid_centre(s->viewer.decoder().header().grid)[axis % 3];
}
EMSCRIPTEN_KEEPALIVE int32_t dtm_header_levels(Session* s) {
  return s->viewer.decoder().header().level_count;
}
EMSCRIPTEN_KEEPALIVE double dtm_header_vertices(Session* s) {
  return s->viewer.decoder().header().vertex_count;
}
EMSCRIPTEN_KEEPALIVE int32_t dtm_header_flags(Session* s) { return s->viewer.decoder().header().flags; }

// The fields, once the field table is in (a level has been decoded).
EMSCRIPTEN_KEEPALIVE int32_t dtm_field_count(Session* s) {
  return static_cast<int32_t>(s->viewer.decoder().fields().size());
}
EMSCRIPTEN_KEEPALIVE const char* dtm_field_name(Session* s, int32_t f) {
  return field(s, f) ? keep(s, field(s, f)->name) : "";
}
EMSCRIPTEN_KEEPALIVE const char* dtm_field_type(Session* s, int32_t f) {
  return field(s, f) ? dtm::value_type_name(field(s, f)->type) : "";
}
EMSCRIPTEN_KEEPALIVE int32_t dtm_field_components(Session* s, int32_t f) {
  return field(s, f) ? field(s, f)->components : 0;
}

// The regions (flag regions), once a level has been decoded: none without.
EMSCRIPTEN_KEEPALIVE int32_t dtm_region_count(Session* s) {
  return static_cast<int32_t>(s->viewer.decoder().regions().size());
}
EMSCRIPTEN_KEEPALIVE int32_t dtm_region_label(Session* s, int32_t r) {
  const auto& regions = s->viewer.decoder().regions();
  return r >= 0 && static_cast<size_t>(r) < regions.size() ? regions[r].label : 0;
}
EMSCRIPTEN_KEEPALIVE const char* dtm_region_name(Session* s, int32_t r) {
  const auto& regions = s->viewer.decoder().regions();
  return r >= 0 && static_cast<size_t>(r) < regions.size() ? keep(s, regions[r].name) : "";
}

// Makes the oldest completed level not yet taken the current one: 1, or 0
// when there is none.
EMSCRIPTEN_KEEPALIVE int32_t dtm_session_next_level(Session* s) {
  if (!s->viewer.has_level()) return 0;
  s->level = s->viewer.take_level();
  return 1;
}

// The current level.
EMSCRIPTEN_KEEPALIVE int32_t dtm_level(Session* s) { return s->level.level; }
EMSCRIPTEN_KEEPALIVE uint32_t dtm_level_vertices(Session* s) { return s->level.vertices; }
EMSCRIPTEN_KEEPALIVE uint32_t dtm_level_first_new(Session* s) { return s->level.first_new; }
EMSCRIPTEN_KEEPALIVE double dtm_level_stream_bytes(Session* s) {
  return static_cast<double>(s->level.stream_bytes);
}
EMSCRIPTEN_KEEPALIVE uint32_t dtm_level_tetrahedra(Session* s) {
  return static_cast<uint32_t>(s->level.cells.size());
}
EMSCRIPTEN_KEEPALIVE const uint32_t* dtm_level_cells(Session* s) {
  return reinterpret_cast<const uint32_t*>(s->level.cells.data());
}
EMSCRIPTEN_KEEPALIVE const int32_t* dtm_level_neighbors(Session* s) {
  return reinterpret_cast<const int32_t*>(s->level.cell_neighbors.data());
}
// Per cell, 1 + its index among the regions (1 without regions).
EMSCRIPTEN_KEEPALIVE const uint8_t* dtm_level_cell_regions(Session* s) {
  return s->level.cell_regions.data();
}
EMSCRIPTEN_KEEPALIVE uint32_t dtm_level_triangles(Session* s) {
  return static_cast<uint32_t>(s->level.surface.size());
}
EMSCRIPTEN_KEEPALIVE const uint32_t* dtm_level_surface(Session* s) {
  return reinterpret_cast<const uint32_t*>(s->level.surface.data());
}
// Per surface face, its cell's region as above.
EMSCRIPTEN_KEEPALIVE const uint8_t* dtm_level_surface_regions(Session* s) {
  return s->level.surface_regions.data();
}
EMSCRIPTEN_KEEPALIVE const uint8_t* dtm_level_boundary(Session* s) { return s->level.boundary.data(); }
EMSCRIPTEN_KEEPALIVE const float* dtm_level_positions(Session* s) { return s->level.new_positions.data(); }
EMSCRIPTEN_KEEPALIVE const float* dtm_level_values(Session* s, int32_t f) {
  return f >= 0 && static_cast<size_t>(f) < s->level.new_values.size() ? s->level.new_values[f].data()
                                                                       : nullptr;
}
EMSCRIPTEN_KEEPALIVE const char* dtm_level_summary(Session* s) {
  return keep(s, dtm::level_summary_json(s->viewer.decoder(), s->level));
}

// How the stream ended, as the native level_summary's last line prints it.
EMSCRIPTEN_KEEPALIVE const char* dtm_session_end_summary(Session* s) {
  return keep(s, dtm::end_summary_json(end_status(s)));
}

// For the speed benchmark (bench/viewer.sh): decodes a whole stream to its
// finest mesh only, as meshdec does, and returns its tetrahedra, or -1.
EMSCRIPTEN_KEEPALIVE double dtm_decode_finest(const uint8_t* bytes, uint32_t n) {
  try {
    dtm::ProgressiveDecoder decoder;
    if (!dtm::decode_stream(std::span(bytes, n), decoder).ok()) return -1;
    const auto cells = decoder.carved_cells();
    return decoder.mesh_status().ok() ? static_cast<double>(cells.size()) : -1;
  } catch (const std::exception&) {
    return -1;
  }
}

}  // extern "C"
