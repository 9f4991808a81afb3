// _dtmesh: the C++ library under the Python package `dtmesh` (python/dtmesh).
// It only moves arrays across: the encoder, the decoder, the report and the
// stream summary are the library's and the tools' own (no second codec), so
// a stream made here is byte for byte meshenc's, and a level decoded here is
// meshdec's. The GIL is released while the library works.
#include <oneapi/tbb/global_control.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unordered_set>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/region_decode.h"
#include "common/threads.h"
#include "tools/decoded_mesh.h"
#include "tools/field_types.h"
#include "tools/formats/cell_split.h"
#include "tools/formats/tagged_faces.h"
#include "tools/report.h"
#include "tools/stream_info.h"

namespace py = pybind11;

namespace {

// The library's errors, raised as dtmesh.Error (python/dtmesh/__init__.py
// gives it its place); set when the module is made.
py::object* error_type = nullptr;

[[noreturn]] void raise_error(const std::string& message) {
  PyErr_SetString(error_type->ptr(), message.c_str());
  throw py::error_already_set();
}

// One field as Python hands it over: its values already as doubles
// (point-major, `components` each) and its type's index (ScalarType order).
struct FieldIn {
  std::string name;
  int type = 0;
  int components = 1;
  py::array_t<double, py::array::c_style | py::array::forcecast> values;
};

py::bytes to_bytes(const std::vector<uint8_t>& v) {
  return py::bytes(reinterpret_cast<const char*>(v.data()), v.size());
}

// meshenc's options for its preset, then the arguments Python gave.
dtm::EncodeOptions encode_options(int qbits, std::optional<double> box, std::optional<double> scale,
                                  std::optional<double> dmax, const std::string& preset,
                                  const std::map<std::string, double>& field_errors) {
  if (preset != "codec" && preset != "paper")
    throw py::value_error("preset must be 'codec' or 'paper', got '" + preset + "'");
  dtm::EncodeOptions o = preset == "paper" ? dtm::EncodeOptions::paper() : dtm::EncodeOptions{};
  if (qbits < 1 || qbits > 24) throw py::value_error("qbits must be 1 to 24, got " + std::to_string(qbits));
  o.qbits = qbits;
  if (box && scale) throw py::value_error("give box or scale, not both");
  if (box) {
    if (!(*box > 0)) throw py::value_error("box must be positive");
    o.box = *box;
  }
  if (scale) {
    if (!(*scale > 0)) throw py::value_error("scale must be positive");
    o.scale = *scale;
  }
  if (dmax) {
    if (!(*dmax > 0)) throw py::value_error("dmax must be positive");
    o.dmax = *dmax;
  }
  for (const auto& [name, e] : field_errors)
    if (!(e > 0) || !std::isfinite(e))
      throw py::value_error("field_errors['" + name + "'] must be a positive number");
  o.field_errors = field_errors;
  return o;
}

// (stream bytes, meshenc --report's JSON text, each input point's vertex).
py::tuple encode(
    py::array_t<double, py::array::c_style | py::array::forcecast> points,
    std::optional<py::array_t<int64_t, py::array::c_style | py::array::forcecast>> tetrahedra,
    std::optional<py::array_t<int64_t, py::array::c_style | py::array::forcecast>> regions,
    const std::map<int32_t, std::string>& region_names,
    std::optional<py::array_t<int64_t, py::array::c_style | py::array::forcecast>> faces,
    std::optional<py::array_t<int64_t, py::array::c_style | py::array::forcecast>> face_tags,
    const std::map<int32_t, std::string>& face_tag_names, const std::vector<FieldIn>& fields,
    const std::vector<FieldIn>& cell_fields, int qbits, std::optional<double> box,
    std::optional<double> scale, std::optional<double> dmax, const std::string& preset,
    const std::map<std::string, double>& field_errors, bool keep_order, bool exact, bool bricks,
    uint64_t brick_points,
    std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>> edge_points,
    std::optional<py::array_t<int64_t, py::array::c_style | py::array::forcecast>> edge_nodes,
    const std::vector<FieldIn>& edge_fields,
    std::optional<py::array_t<int64_t, py::array::c_style | py::array::forcecast>> node_numbering) {
  if (points.ndim() != 2 || points.shape(1) != 3) throw py::value_error("points must be an N x 3 array");
  const size_t n = static_cast<size_t>(points.shape(0));
  std::vector<dtm::InputPoint> in_points(n);
  const double* p = points.data();
  for (size_t i = 0; i < n; ++i) in_points[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  std::vector<std::array<uint32_t, 4>> tets;
  if (tetrahedra) {
    const auto& t = *tetrahedra;
    if (t.ndim() != 2 || t.shape(1) != 4) throw py::value_error("tetrahedra must be an M x 4 array");
    const int64_t* v = t.data();
    tets.resize(static_cast<size_t>(t.shape(0)));
    for (size_t k = 0; k < tets.size(); ++k)
      for (int j = 0; j < 4; ++j) {
        const int64_t id = v[4 * k + j];
        if (id < 0 || static_cast<size_t>(id) >= n)
          throw py::value_error("tetrahedra[" + std::to_string(k) + "] names point " + std::to_string(id) +
                                ", there are " + std::to_string(n));
        tets[k][j] = static_cast<uint32_t>(id);
      }
  }
  std::vector<int32_t> labels;
  if (regions) {
    const auto& r = *regions;
    if (r.ndim() != 1 || static_cast<size_t>(r.shape(0)) != tets.size())
      throw py::value_error("regions must hold one label per tetrahedron (" + std::to_string(tets.size()) +
                            ")");
    const int64_t* v = r.data();
    for (size_t k = 0; k < tets.size(); ++k) {
      if (v[k] < INT32_MIN || v[k] > INT32_MAX)
        throw py::value_error("regions[" + std::to_string(k) + "] is not a 32-bit integer");
      labels.push_back(static_cast<int32_t>(v[k]));
    }
  }
  std::vector<std::array<uint32_t, 3>> tri;
  std::vector<int32_t> tri_tags;
  if (faces) {
    const auto& f = *faces;
    if (f.ndim() != 2 || f.shape(1) != 3) throw py::value_error("faces must be an F x 3 array");
    if (!face_tags || face_tags->ndim() != 1 || face_tags->shape(0) != f.shape(0))
      throw py::value_error("face_tags must hold one tag per face (" + std::to_string(f.shape(0)) + ")");
    const int64_t* v = f.data();
    const int64_t* t = face_tags->data();
    for (py::ssize_t k = 0; k < f.shape(0); ++k) {
      std::array<uint32_t, 3> tri_k;
      for (int j = 0; j < 3; ++j) {
        const int64_t id = v[3 * k + j];
        if (id < 0 || static_cast<size_t>(id) >= n)
          throw py::value_error("faces[" + std::to_string(k) + "] names point " + std::to_string(id));
        tri_k[static_cast<size_t>(j)] = static_cast<uint32_t>(id);
      }
      if (t[k] < INT32_MIN || t[k] > INT32_MAX)
        throw py::value_error("face_tags[" + std::to_string(k) + "] is not a 32-bit integer");
      tri.push_back(tri_k);
      tri_tags.push_back(static_cast<int32_t>(t[k]));
    }
  }
  std::vector<dtm::EncodeInput::Field> in_fields;
  for (const FieldIn& f : fields) {
    if (f.type < 0 || f.type > static_cast<int>(dtm::ScalarType::kFloat64))
      throw py::value_error("field '" + f.name + "': unknown type");
    if (static_cast<size_t>(f.values.size()) != n * static_cast<size_t>(f.components))
      throw py::value_error("field '" + f.name + "' has " + std::to_string(f.values.size()) +
                            " values, the points need " + std::to_string(n * f.components));
    in_fields.push_back({f.name, dtm::value_type(static_cast<dtm::ScalarType>(f.type)), f.components,
                         std::span<const double>(f.values.data(), static_cast<size_t>(f.values.size()))});
  }
  std::vector<dtm::EncodeInput::Field> in_cell_fields;
  for (const FieldIn& f : cell_fields) {
    if (f.type < 0 || f.type > static_cast<int>(dtm::ScalarType::kFloat64))
      throw py::value_error("cell_data '" + f.name + "': unknown type");
    if (static_cast<size_t>(f.values.size()) != tets.size() * static_cast<size_t>(f.components))
      throw py::value_error("cell_data '" + f.name + "' has " + std::to_string(f.values.size()) +
                            " values, the tetrahedra need " + std::to_string(tets.size() * f.components));
    in_cell_fields.push_back(
        {f.name, dtm::value_type(static_cast<dtm::ScalarType>(f.type)), f.components,
         std::span<const double>(f.values.data(), static_cast<size_t>(f.values.size()))});
  }
  // A second-order mesh's edge nodes (kept with exact: format 18.0): each
  // edge once, the first tetrahedron's that names it.
  std::vector<dtm::EncodeInput::EdgeNode> in_edge_nodes;
  std::vector<size_t> node_points;  // per node of in_edge_nodes, its edge point
  if (edge_nodes) {
    if (!edge_points || edge_points->ndim() != 2 || edge_points->shape(1) != 3)
      throw py::value_error("edge_nodes need edge_points, a K x 3 array");
    const auto& e = *edge_nodes;
    if (e.ndim() != 2 || e.shape(1) != 6 || static_cast<size_t>(e.shape(0)) != tets.size())
      throw py::value_error("edge_nodes must be an M x 6 array, a row per tetrahedron");
    const auto k = static_cast<int64_t>(edge_points->shape(0));
    const int64_t* v = e.data();
    const double* q = edge_points->data();
    std::unordered_set<uint64_t> seen;
    for (size_t t = 0; t < tets.size(); ++t)
      for (size_t s = 0; s < 6; ++s) {
        const int64_t node = v[6 * t + s];
        if (node < 0) continue;
        if (node >= k)
          throw py::value_error("edge_nodes[" + std::to_string(t) + "] names edge point " +
                                std::to_string(node) + ", there are " + std::to_string(k));
        const uint32_t a = tets[t][dtm::kCellEdges[s][0]], b = tets[t][dtm::kCellEdges[s][1]];
        if (seen.insert(dtm::edge_key(a, b)).second) {
          in_edge_nodes.push_back({{a, b}, {q[3 * node], q[3 * node + 1], q[3 * node + 2]}});
          node_points.push_back(static_cast<size_t>(node));
        }
      }
  }
  // The fields' values there (19.0), in the order of in_edge_nodes.
  std::vector<std::vector<double>> edge_values(fields.size());
  for (const FieldIn& e : edge_fields) {
    size_t f = 0;
    while (f < fields.size() && fields[f].name != e.name) ++f;
    if (f == fields.size()) throw py::value_error("edge_fields '" + e.name + "': not a field of fields");
    const auto c = static_cast<size_t>(fields[f].components);
    if (e.components != fields[f].components || e.type != fields[f].type || !edge_points ||
        static_cast<size_t>(e.values.size()) != static_cast<size_t>(edge_points->shape(0)) * c)
      throw py::value_error("edge_fields '" + e.name + "' must hold its field's values at each edge point");
    const double* v = e.values.data();
    for (size_t node : node_points)
      edge_values[f].insert(edge_values[f].end(), v + node * c, v + (node + 1) * c);
    in_fields[f].edge_values = edge_values[f];
  }
  // With keep_order (21.0): the file's numbering of the points and edge
  // points together, each edge point named as the node the stream keeps of
  // it (one a duplicate edge's is not).
  std::vector<uint32_t> numbering;
  if (node_numbering && keep_order && exact && edge_nodes) {
    const auto& order = *node_numbering;
    const auto k = static_cast<size_t>(edge_points->shape(0));
    if (order.ndim() != 1 || static_cast<size_t>(order.shape(0)) != n + k)
      throw py::value_error("node_numbering must hold one entry per point and edge point");
    std::vector<uint32_t> node_of_point(k, UINT32_MAX);
    for (size_t node = 0; node < node_points.size(); ++node)
      node_of_point[node_points[node]] = static_cast<uint32_t>(node);
    const int64_t* o = order.data();
    for (size_t i = 0; i < n + k; ++i) {
      if (o[i] < 0 || static_cast<size_t>(o[i]) >= n + k)
        throw py::value_error("node_numbering[" + std::to_string(i) + "] = " + std::to_string(o[i]) +
                              " names no point or edge point");
      const auto entry = static_cast<size_t>(o[i]);
      if (entry < n)
        numbering.push_back(static_cast<uint32_t>(entry));
      else if (node_of_point[entry - n] != UINT32_MAX)
        numbering.push_back(static_cast<uint32_t>(n + node_of_point[entry - n]));
    }
  }
  dtm::EncodeOptions options = encode_options(qbits, box, scale, dmax, preset, field_errors);
  options.keep_order = keep_order;
  options.exact = exact;
  options.bricks = bricks;
  if (brick_points < 1) throw py::value_error("brick_points must be positive");
  options.brick_points = brick_points;
  dtm::EncodeInput input;
  input.points = in_points;
  input.tetrahedra = tets;
  input.tetrahedron_regions = labels;
  input.region_names = region_names;
  input.tagged_faces = tri;
  input.face_tags = tri_tags;
  input.face_tag_names = face_tag_names;
  input.fields = in_fields;
  input.cell_fields = in_cell_fields;
  input.edge_nodes = in_edge_nodes;
  input.node_numbering = numbering;
  std::optional<dtm::StatusOr<dtm::EncodedMesh>> encoded;
  {
    py::gil_scoped_release release;
    encoded.emplace(dtm::encode(input, options));
  }
  if (!encoded->ok()) raise_error(encoded->status().message());
  // meshenc's report; arrays from numpy leave nothing out.
  nlohmann::json report_fields = dtm::report_json("", (*encoded)->report);
  report_fields["left_out"] = nlohmann::json::array();
  const std::string report = report_fields.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  const auto& of_input = (*encoded)->vertex_of_input;
  py::array_t<uint32_t> vertex_of_input(static_cast<py::ssize_t>(of_input.size()));
  std::memcpy(vertex_of_input.mutable_data(), of_input.data(), of_input.size() * sizeof(uint32_t));
  return py::make_tuple(to_bytes((*encoded)->bytes), report, vertex_of_input);
}

template <class T>
py::array_t<T> array_of(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(T));
  return a;
}

// A decoded level as Python's Mesh takes it: a dict of arrays.
py::dict level_dict(const dtm::OutputMesh& mesh, int level, int level_count) {
  const size_t n = mesh.points.size();
  py::array_t<double> xyz({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  double* out = xyz.mutable_data();
  for (size_t i = 0; i < n; ++i) {
    const dtm::InputPoint q = mesh.grid.to_input(mesh.points[i]);
    out[3 * i] = q.x, out[3 * i + 1] = q.y, out[3 * i + 2] = q.z;
  }
  py::array_t<uint32_t> cells({static_cast<py::ssize_t>(mesh.cells.size()), py::ssize_t{4}});
  if (!mesh.cells.empty()) std::memcpy(cells.mutable_data(), mesh.cells.data(), mesh.cells.size() * 16);
  // Each array as (name, type, components, the stored type's bytes: the low
  // bytes of each value's bits, two's complement or IEEE, little-endian as
  // the stream is).
  // A name from the stream as text: a hostile stream's bytes that are not
  // UTF-8 replaced (U+FFFD), not raised as a UnicodeDecodeError.
  const auto text = [](const std::string& name) {
    return py::reinterpret_steal<py::str>(
        PyUnicode_DecodeUTF8(name.data(), static_cast<py::ssize_t>(name.size()), "replace"));
  };
  const auto named = [&text](const std::map<int32_t, std::string>& names) {
    py::dict out;
    for (const auto& [label, name] : names) out[py::int_(label)] = text(name);
    return out;
  };
  const auto arrays = [&text](const std::vector<dtm::OutputField>& from) {
    py::list out;
    for (const dtm::OutputField& f : from) {
      const size_t size = static_cast<size_t>(dtm::scalar_size(f.type));
      std::string raw(f.bits.size() * size, '\0');
      for (size_t i = 0; i < f.bits.size(); ++i) std::memcpy(&raw[i * size], &f.bits[i], size);
      out.append(py::make_tuple(text(f.name), static_cast<int>(f.type), f.components, py::bytes(raw)));
    }
    return out;
  };
  const py::list fields = arrays(mesh.fields);
  py::dict d;
  d["points"] = xyz;
  d["tetrahedra"] = cells;
  // (A box's or piece's boundary is absent: empty, as the mesh has it.)
  d["vertex_levels"] = array_of(mesh.level, {static_cast<py::ssize_t>(mesh.level.size())});
  d["boundary"] = array_of(mesh.boundary, {static_cast<py::ssize_t>(mesh.boundary.size())});
  d["fields"] = fields;
  d["cell_data"] = arrays(mesh.cell_fields);
  d["regions"] = array_of(mesh.region, {static_cast<py::ssize_t>(mesh.region.size())});
  d["region_names"] = named(mesh.region_names);
  py::array_t<uint32_t> faces({static_cast<py::ssize_t>(mesh.faces.size()), py::ssize_t{3}});
  if (!mesh.faces.empty()) std::memcpy(faces.mutable_data(), mesh.faces.data(), mesh.faces.size() * 12);
  d["faces"] = faces;
  d["face_tags"] = array_of(mesh.face_tags, {static_cast<py::ssize_t>(mesh.face_tags.size())});
  d["face_tag_names"] = named(mesh.face_tag_names);
  // (18.0, level 0 of a second-order mesh's exact stream: the points on
  // each cell's and tagged face's edges, -1 for none; empty without.)
  const auto nodes = [](const auto& per_element, size_t width) {
    std::vector<int64_t> flat;
    flat.reserve(per_element.size() * width);
    for (const auto& e : per_element)
      for (uint32_t v : e) flat.push_back(v == dtm::kNoEdgePoint ? -1 : int64_t{v});
    return array_of(flat, {static_cast<py::ssize_t>(per_element.size()), static_cast<py::ssize_t>(width)});
  };
  d["edge_nodes"] = nodes(mesh.cell_edge_nodes, 6);
  d["face_edge_nodes"] = nodes(mesh.face_edge_nodes, 3);
  // (22.0, level 0 of a --keep-order stream of a file with its own node
  // ids: each point's; empty without.)
  d["node_ids"] = array_of(mesh.node_labels, {static_cast<py::ssize_t>(mesh.node_labels.size())});
  d["level"] = level;
  d["level_count"] = level_count;
  return d;
}

// The decoder's finest level, made with the GIL released.
py::dict finest_level_dict(const dtm::ProgressiveDecoder& decoder) {
  std::optional<dtm::OutputMesh> mesh;
  std::string failure;
  {
    py::gil_scoped_release release;
    try {
      mesh.emplace(dtm::decoded_mesh(decoder, "stream", true));
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  if (!mesh) raise_error(failure);
  return level_dict(*mesh, decoder.finest_level(), decoder.header().level_count);
}

// The progressive decoder, fed chunk by chunk; each call returns the levels
// its bytes completed.
class Decoder {
 public:
  explicit Decoder(int stop_after_level, uint64_t max_vertices) {
    dtm::DecoderOptions o;
    o.stop_after_level = stop_after_level;
    o.max_vertices = max_vertices;
    decoder_ = std::make_unique<dtm::ProgressiveDecoder>(o);
  }

  // The levels completed by `chunk`, each as level_dict() makes it, or only
  // their numbers when `meshes` is false. Raises dtmesh.Error for a damaged
  // stream.
  py::list feed(py::bytes chunk, bool meshes) {
    const std::string_view view = chunk;
    // Each completed level's mesh is made in the callback (the decoder then
    // shows that level), without the GIL; the arrays after the feed.
    std::vector<std::pair<int, dtm::OutputMesh>> levels;
    std::string failure;
    dtm::Status status;
    auto on_level = [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& l) {
      if (!failure.empty()) return;
      if (!meshes) return levels.emplace_back(l.level, dtm::OutputMesh{}), void();
      try {
        levels.emplace_back(l.level, dtm::decoded_mesh(d, "stream", true));
      } catch (const std::exception& e) {
        failure = e.what();
      }
    };
    {
      py::gil_scoped_release release;
      status = decoder_->feed({reinterpret_cast<const uint8_t*>(view.data()), view.size()}, on_level);
    }
    if (!failure.empty()) raise_error(failure);
    if (!status.ok()) raise_error(status.message());
    py::list out;
    const int count = decoder_->header().level_count;
    for (const auto& [level, mesh] : levels) {
      if (meshes)
        out.append(level_dict(mesh, level, count));
      else
        out.append(level);
    }
    return out;
  }

  // None when every level asked for is in; the reason when the input stopped
  // early (the levels decoded stand); raises for a damaged stream.
  std::optional<std::string> finish() const {
    const dtm::Status s = decoder_->finish();
    if (s.ok()) return std::nullopt;
    if (s.code() == dtm::StatusCode::kTruncated) return s.message();
    raise_error(s.message());
  }

  bool done() const { return decoder_->complete() || decoder_->stopped(); }
  int finest_level() const { return decoder_->finest_level(); }
  int level_count() const { return decoder_->has_header() ? decoder_->header().level_count : -1; }
  py::dict mesh() const {
    if (decoder_->finest_level() < 0) raise_error("no level is decoded yet");
    return finest_level_dict(*decoder_);
  }

 private:
  std::unique_ptr<dtm::ProgressiveDecoder> decoder_;
};

// Where a box or a piece is read from: a file by offset (only the bytes it
// needs), or a stream in memory (Python's bytes object, immutable, held
// while it reads: not copied).
class PartSource {
 public:
  explicit PartSource(const py::object& data) {
    if (py::isinstance<py::bytes>(data)) {
      bytes_ = py::reinterpret_borrow<py::bytes>(data);
      const std::string_view view = bytes_;
      held_ = {reinterpret_cast<const uint8_t*>(view.data()), view.size()};
      memory_.emplace(held_);
      return;
    }
    const std::string path = py::str(data);
    name_ = path;
    auto opened = dtm::FileSource::open(path);
    if (!opened.ok()) raise_error(opened.status().message());
    file_.emplace(std::move(*opened));
  }
  dtm::ByteSource& get() { return file_ ? static_cast<dtm::ByteSource&>(*file_) : *memory_; }
  // What an error names: the file's path, or nothing for bytes.
  std::string prefix() const { return name_.empty() ? "" : name_ + ": "; }
  // The stream whole: the bytes in memory, or the file read.
  std::span<const uint8_t> whole(std::vector<uint8_t>& read) {
    if (memory_) return held_;
    read.resize(file_->size());
    if (const dtm::Status s = file_->read(0, read); !s.ok()) throw std::runtime_error(s.message());
    return read;
  }

 private:
  std::string name_;
  py::bytes bytes_;
  std::span<const uint8_t> held_;  // its bytes
  std::optional<dtm::MemorySource> memory_;
  std::optional<dtm::FileSource> file_;
};

// A box (input units: x0 y0 z0 x1 y1 z1) or piece `piece` of `pieces` of a
// level, as meshdec --box and -o X.pvtu write them: level_dict()'s dict
// with, where a truncated stream gave a coarser level than 0, "truncated"
// (why). level -1: the finest whole level. A box of a stream
// that is not bricked is cut from the level decoded whole, with all it
// carries; a piece needs a bricked stream.
py::dict decode_part(const py::object& data, std::optional<std::array<double, 6>> box, int piece, int pieces,
                     int level, uint64_t max_vertices) {
  PartSource holder(data);
  std::optional<dtm::OutputMesh> mesh;
  std::string failure, truncated;
  int found = level, level_count = 0;
  {
    py::gil_scoped_release release;
    try {
      dtm::ByteSource& source = holder.get();
      std::vector<uint8_t> head(dtm::kHeaderSize);
      dtm::StreamHeader header;
      if (source.size() < head.size() || !source.read(0, head).ok() || !dtm::parse_header(head, header).ok())
        header = {};  // decode_region and decode_piece say what is wrong
      level_count = header.level_count;
      dtm::DecoderOptions options;
      options.max_vertices = max_vertices;
      std::array<double, 3> lo{}, hi{};
      if (box) lo = {(*box)[0], (*box)[1], (*box)[2]}, hi = {(*box)[3], (*box)[4], (*box)[5]};
      if (box && level_count > 0 && !(header.flags & dtm::kFlagBricks)) {
        std::vector<uint8_t> read;
        const std::span<const uint8_t> bytes = holder.whole(read);
        options.stop_after_level = level;
        dtm::ProgressiveDecoder decoder(options);
        const dtm::Status fed = decoder.feed(bytes);
        const dtm::Status s = fed.ok() ? decoder.finish() : fed;
        if (!s.ok() && s.code() != dtm::StatusCode::kTruncated) throw std::runtime_error(s.message());
        if (decoder.finest_level() < 0 || (level >= 0 && decoder.finest_level() != level))
          throw std::runtime_error(s.ok() ? "level " + std::to_string(level) +
                                                " asked, the stream has levels 0 to " +
                                                std::to_string(level_count - 1)
                                          : s.message());
        if (!s.ok()) truncated = s.message();
        found = decoder.finest_level();
        mesh.emplace(dtm::cut_to_box(dtm::decoded_mesh(decoder, "stream", dtm::numbers_edge_nodes(decoder)),
                                     lo, hi, dtm::in_input_numbering(decoder)));
      } else {
        const auto part = [&](int l) {
          return box ? dtm::decode_region(source, dtm::grid_box_of(header.grid, lo, hi), l, options)
                     : dtm::decode_piece(source, l, piece, pieces, options);
        };
        // Without a level, a truncated stream's finest whole level, as meshdec.
        found = std::max(level, 0);
        auto got = part(found);
        const dtm::Status first = got.status();
        while (level < 0 && !got.ok() && got.status().code() == dtm::StatusCode::kTruncated &&
               found + 1 < level_count)
          got = part(++found);
        if (!got.ok()) throw std::runtime_error(got.status().message());
        if (found > 0 && level < 0) truncated = first.message();
        mesh.emplace(dtm::region_output(*got, header.grid));
      }
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  if (!failure.empty()) raise_error(holder.prefix() + failure);
  py::dict d = level_dict(*mesh, found, level_count);
  if (!truncated.empty()) d["truncated"] = truncated;
  return d;
}

// meshinfo --json [--stats] as JSON text.
std::string info(py::bytes data, bool stats) {
  const std::string_view view = data;
  const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(view.data()), view.size());
  std::string text, failure;
  {
    py::gil_scoped_release release;
    try {
      const dtm::StreamSummary s = dtm::scan_for_info("stream", bytes);
      const std::vector<dtm::QualityRow> quality =
          stats ? dtm::decode_quality("stream", bytes) : std::vector<dtm::QualityRow>{};
      text = dtm::summary_json("", s, quality).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  if (!failure.empty()) raise_error(failure);
  return text;
}

// The threads the library's work uses in this process (common/threads.h),
// TBB held to the same; 0: the cores the process was given.
void set_threads(int n) {
  static std::optional<tbb::global_control>* limit = new std::optional<tbb::global_control>();
  n = dtm::threads_allowed(n);  // (more than a few a core only wait for each other)
  dtm::set_thread_count(n);
  limit->reset();
  if (n > 0) limit->emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(n));
}

// Hexahedra, wedges or pyramids (cells: n x 8, 6 or 5 corners) or
// quadrilaterals (n x 4) as meshenc's readers split them
// (tools/formats/cell_split.h): the tetrahedra (or triangles) and each
// one's cell.
py::tuple split_cells(py::array_t<int64_t, py::array::c_style | py::array::forcecast> cells,
                      py::array_t<double, py::array::c_style | py::array::forcecast> points) {
  if (cells.ndim() != 2 || points.ndim() != 2 || points.shape(1) != 3)
    throw py::value_error("split_cells: cells must be n x k, points n x 3");
  const auto n = static_cast<size_t>(cells.shape(0)), k = static_cast<size_t>(cells.shape(1));
  if (k != 4 && k != 5 && k != 6 && k != 8)
    throw py::value_error("split_cells: cells of 4, 5, 6 or 8 corners, not " + std::to_string(k));
  const int64_t* c = cells.data();
  const auto m = static_cast<size_t>(points.shape(0));
  for (size_t i = 0; i < n * k; ++i)
    if (c[i] < 0 || static_cast<size_t>(c[i]) >= m)
      throw py::value_error("split_cells: a corner out of range");
  // (The points as they are, not copied for each block of cells: rows of
  // three doubles are InputPoints.)
  static_assert(sizeof(dtm::InputPoint) == 3 * sizeof(double) && std::is_standard_layout_v<dtm::InputPoint>);
  const std::span<const dtm::InputPoint> at(reinterpret_cast<const dtm::InputPoint*>(points.data()), m);
  std::vector<int64_t> out, cell_of;
  std::vector<std::array<uint32_t, 4>> tets;
  std::array<uint32_t, 8> corners{};
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < k; ++j) corners[j] = static_cast<uint32_t>(c[i * k + j]);
    if (k == 4) {
      for (const auto& t : dtm::split_quad({corners[0], corners[1], corners[2], corners[3]}))
        out.insert(out.end(), t.begin(), t.end()), cell_of.push_back(static_cast<int64_t>(i));
      continue;
    }
    tets.clear();
    dtm::split_cell(std::span(corners).first(k), at, tets);
    for (const auto& t : tets)
      out.insert(out.end(), t.begin(), t.end()), cell_of.push_back(static_cast<int64_t>(i));
  }
  const py::ssize_t per = k == 4 ? 3 : 4;
  return py::make_tuple(array_of(out, {static_cast<py::ssize_t>(cell_of.size()), per}),
                        array_of(cell_of, {static_cast<py::ssize_t>(cell_of.size())}));
}

// The note on the tagged faces no level can carry (tools/formats/
// tagged_faces.h), for encode()'s warning ("" for none); the arrays as
// encode() checked them.
std::string faces_inside(py::array_t<int64_t, py::array::c_style | py::array::forcecast> tets,
                         py::array_t<int64_t, py::array::c_style | py::array::forcecast> regions,
                         py::array_t<int64_t, py::array::c_style | py::array::forcecast> faces) {
  std::vector<std::array<uint32_t, 4>> t(static_cast<size_t>(tets.size() / 4));
  for (size_t i = 0; i < t.size(); ++i)
    for (size_t k = 0; k < 4; ++k) t[i][k] = static_cast<uint32_t>(tets.data()[4 * i + k]);
  std::vector<int32_t> r(regions.data(), regions.data() + regions.size());
  std::vector<std::array<uint32_t, 3>> f(static_cast<size_t>(faces.size() / 3));
  for (size_t i = 0; i < f.size(); ++i)
    for (size_t k = 0; k < 3; ++k) f[i][k] = static_cast<uint32_t>(faces.data()[3 * i + k]);
  if (!r.empty() && r.size() != t.size()) r.clear();
  const uint64_t inside = dtm::tagged_faces_inside(t, r, f);
  return inside ? dtm::tagged_faces_inside_note(inside, f.size()) : std::string();
}

}  // namespace

PYBIND11_MODULE(_dtmesh, m) {
  m.doc() = "The dtmesh C++ library's encoder and decoder (use the package dtmesh, not this module).";
  // Never destroyed: it would outlive the interpreter.
  error_type = new py::object(py::reinterpret_borrow<py::object>(PyExc_RuntimeError));
  m.def("set_error_type", [](py::object type) { *error_type = std::move(type); });
  py::class_<FieldIn>(m, "FieldIn")
      .def(py::init<std::string, int, int, py::array_t<double, py::array::c_style | py::array::forcecast>>());
  m.def("encode", &encode, py::arg("points"), py::arg("tetrahedra"), py::arg("regions"),
        py::arg("region_names"), py::arg("faces"), py::arg("face_tags"), py::arg("face_tag_names"),
        py::arg("fields"), py::arg("cell_fields"), py::arg("qbits"), py::arg("box"), py::arg("scale"),
        py::arg("dmax"), py::arg("preset"), py::arg("field_errors"), py::arg("keep_order"), py::arg("exact"),
        py::arg("bricks"), py::arg("brick_points"), py::arg("edge_points"), py::arg("edge_nodes"),
        py::arg("edge_fields"), py::arg("node_numbering"));
  m.def("decode_part", &decode_part, py::arg("data"), py::arg("box"), py::arg("piece"), py::arg("pieces"),
        py::arg("level"), py::arg("max_vertices"));
  py::class_<Decoder>(m, "Decoder")
      .def(py::init<int, uint64_t>(), py::arg("stop_after_level"), py::arg("max_vertices"))
      .def("feed", &Decoder::feed, py::arg("chunk"), py::arg("meshes"))
      .def("finish", &Decoder::finish)
      .def("done", &Decoder::done)
      .def("finest_level", &Decoder::finest_level)
      .def("level_count", &Decoder::level_count)
      .def("mesh", &Decoder::mesh);
  m.def("info", &info, py::arg("data"), py::arg("stats"));
  m.def("split_cells", &split_cells, py::arg("cells"), py::arg("points"));
  m.def("faces_inside", &faces_inside, py::arg("tetrahedra"), py::arg("regions"), py::arg("faces"));
  m.def("set_threads", &set_threads, py::arg("threads"));
  m.def("threads", &dtm::thread_count);
  m.attr("default_max_vertices") = dtm::DecoderOptions{}.max_vertices;
  m.attr("version") = DTM_VERSION;
}
