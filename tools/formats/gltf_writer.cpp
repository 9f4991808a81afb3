#include "tools/formats/gltf_writer.h"

#include <draco/compression/encode.h>
#include <draco/io/gltf_encoder.h>
#include <draco/material/material_library.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "codec/sections/value_fields.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"
#include "tools/field_types.h"

namespace dtm {
namespace {

// A file name as a relative URI (glTF's are RFC 3986 references): every
// byte but the unreserved percent-encoded, so that "my part #1.bin" is not
// read as a fragment.
std::string uri_of(const std::string& name) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : name) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

// Viridis at nine stops (sRGB), as the viewer's colours.js has it.
constexpr std::array<std::array<double, 3>, 9> kRamp = {{{0.267, 0.005, 0.329},
                                                         {0.283, 0.141, 0.458},
                                                         {0.254, 0.265, 0.530},
                                                         {0.207, 0.372, 0.553},
                                                         {0.164, 0.471, 0.558},
                                                         {0.128, 0.567, 0.551},
                                                         {0.135, 0.659, 0.518},
                                                         {0.478, 0.821, 0.318},
                                                         {0.993, 0.906, 0.144}}};

std::array<double, 3> ramp(double t) {
  const double x = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * (kRamp.size() - 1);
  const size_t i = std::min(kRamp.size() - 2, static_cast<size_t>(x));
  const double f = x - static_cast<double>(i);
  std::array<double, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = kRamp[i][k] + f * (kRamp[i + 1][k] - kRamp[i][k]);
  return c;
}

// Regions' colours (sRGB), as the viewer's colours.js has them: Okabe and
// Ito's seven, then hues a golden angle apart.
constexpr std::array<std::array<double, 3>, 7> kRegionColours = {{{0.902, 0.624, 0.000},
                                                                  {0.337, 0.706, 0.914},
                                                                  {0.000, 0.620, 0.451},
                                                                  {0.941, 0.894, 0.259},
                                                                  {0.000, 0.447, 0.698},
                                                                  {0.835, 0.369, 0.000},
                                                                  {0.800, 0.475, 0.655}}};

std::array<double, 3> region_colour(size_t r) {
  if (r < kRegionColours.size()) return kRegionColours[r];
  const double hue = std::fmod(static_cast<double>(r - kRegionColours.size()) * 137.508 + 20, 360.0);
  const double s = 0.6, l = 0.5 + 0.1 * (static_cast<double>(r % 3) - 1), a = s * std::min(l, 1 - l);
  const auto f = [&](double n) {
    const double k = std::fmod(n + hue / 30, 12.0);
    return l - a * std::max(-1.0, std::min({k - 3, 9 - k, 1.0}));
  };
  return {f(0), f(8), f(4)};
}

// glTF's COLOR_0 is linear light; the ramp is sRGB.
uint8_t linear_byte(double srgb) {
  const double linear = srgb <= 0.04045 ? srgb / 12.92 : std::pow((srgb + 0.055) / 1.055, 2.4);
  return static_cast<uint8_t>(std::lround(255 * std::clamp(linear, 0.0, 1.0)));
}

// Per surface vertex, a value on [0, 1] for the ramp.
std::vector<double> ramp_positions(const OutputMesh& m, const BoundarySurface& s, const std::string& colour) {
  std::vector<double> t(s.vertices.size(), 1.0);
  if (colour == "level") {
    if (m.level.empty()) throw std::invalid_argument("--color level: the mesh has no levels");
    const int coarsest = *std::max_element(m.level.begin(), m.level.end());
    for (size_t i = 0; i < t.size(); ++i)
      t[i] = coarsest > 0 ? static_cast<double>(coarsest - m.level[s.vertices[i]]) / coarsest : 1.0;
    return t;
  }
  if (colour == "boundary") {
    if (m.boundary.empty()) throw std::invalid_argument("--color boundary: the mesh has no boundary flags");
    for (size_t i = 0; i < t.size(); ++i) t[i] = m.boundary[s.vertices[i]] ? 1.0 : 0.0;
    return t;
  }
  const auto field =
      std::find_if(m.fields.begin(), m.fields.end(), [&](const OutputField& f) { return f.name == colour; });
  if (field == m.fields.end()) {
    std::string known = m.region.empty() ? "level, boundary" : "level, boundary, region";
    for (const OutputField& f : m.fields) known += ", " + f.name;
    throw std::invalid_argument("--color " + colour + ": no such field (known: " + known + ")");
  }
  double low = INFINITY, high = -INFINITY;
  for (size_t i = 0; i < t.size(); ++i) {
    // A scalar's value, a vector's length.
    const auto value = [&](int c) {
      return value_of(field->bits[size_t{s.vertices[i]} * field->components + c], value_type(field->type));
    };
    double sum = 0;
    for (int c = 0; c < field->components; ++c) sum += value(c) * value(c);
    t[i] = field->components == 1 ? value(0) : std::sqrt(sum);
    if (std::isfinite(t[i])) low = std::min(low, t[i]), high = std::max(high, t[i]);
  }
  for (double& x : t) x = high > low ? (x - low) / (high - low) : 0.5;
  return t;
}

template <class T, size_t N>
int add_attribute(draco::Mesh& mesh, draco::GeometryAttribute::Type type, draco::DataType data_type,
                  bool normalized, const std::vector<std::array<T, N>>& values) {
  draco::GeometryAttribute a;
  a.Init(type, nullptr, N, data_type, normalized, sizeof(T) * N, 0);
  const int id = mesh.AddAttribute(a, true, static_cast<uint32_t>(values.size()));
  for (uint32_t i = 0; i < values.size(); ++i)
    mesh.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), values[i].data());
  return id;
}

// Each surface vertex's position less `anchor`, in float32.
std::vector<std::array<float, 3>> float_positions(const OutputMesh& m, const BoundarySurface& s,
                                                  const InputPoint& anchor) {
  std::vector<std::array<float, 3>> positions(s.vertices.size());
  for (size_t i = 0; i < s.vertices.size(); ++i) {
    const InputPoint p = m.grid.to_input(m.points[s.vertices[i]]);
    positions[i] = {static_cast<float>(p.x - anchor.x), static_cast<float>(p.y - anchor.y),
                    static_cast<float>(p.z - anchor.z)};
  }
  return positions;
}

// The surface as a Draco mesh: positions (input units, less `anchor`),
// normals, colours; with `regions` (--color region) each vertex in its
// region's colour, and a MATERIAL attribute with a material per region,
// named as the region, which Draco's glTF encoder makes a primitive each.
std::unique_ptr<draco::Mesh> draco_surface(const OutputMesh& m, const BoundarySurface& s,
                                           const SurfaceStyle& style, const InputPoint& anchor,
                                           const RegionSurfaces* regions) {
  const std::vector<std::array<float, 3>> positions = float_positions(m, s, anchor);
  // Area-weighted: each triangle adds its cross product (twice its area
  // along its normal), in grid units, where the points are exact.
  std::vector<Vec3> sums(s.vertices.size(), Vec3{0, 0, 0});
  for (const auto& t : s.triangles) {
    const Vec3 a = to_vec(m.points[s.vertices[t[0]]]);
    const Vec3 n = cross(to_vec(m.points[s.vertices[t[1]]]) - a, to_vec(m.points[s.vertices[t[2]]]) - a);
    for (const uint32_t k : t) sums[k] += n;
  }
  std::vector<std::array<float, 3>> normals(s.vertices.size(), {0, 0, 1});
  for (size_t i = 0; i < sums.size(); ++i) {
    const double length = norm(sums[i]);
    if (length > 0)
      normals[i] = {static_cast<float>(sums[i].x / length), static_cast<float>(sums[i].y / length),
                    static_cast<float>(sums[i].z / length)};
  }
  // RGBA, not RGB: a plain glTF's vertex attributes must be 4-byte aligned.
  std::vector<std::array<uint8_t, 4>> colours(s.vertices.size());
  if (regions) {
    for (size_t i = 0; i < colours.size(); ++i) {
      const auto c = region_colour(regions->region[i]);
      colours[i] = {linear_byte(c[0]), linear_byte(c[1]), linear_byte(c[2]), 255};
    }
  } else {
    const std::vector<double> t = ramp_positions(m, s, style.colour);
    for (size_t i = 0; i < t.size(); ++i) {
      const auto c = ramp(t[i]);
      colours[i] = {linear_byte(c[0]), linear_byte(c[1]), linear_byte(c[2]), 255};
    }
  }

  auto mesh = std::make_unique<draco::Mesh>();
  mesh->set_num_points(static_cast<uint32_t>(s.vertices.size()));
  add_attribute(*mesh, draco::GeometryAttribute::POSITION, draco::DT_FLOAT32, false, positions);
  add_attribute(*mesh, draco::GeometryAttribute::NORMAL, draco::DT_FLOAT32, false, normals);
  add_attribute(*mesh, draco::GeometryAttribute::COLOR, draco::DT_UINT8, true, colours);
  if (regions) {
    // One value per material, each point mapped to its region's (Draco's
    // glTF encoder wants a value per material).
    draco::GeometryAttribute a;
    a.Init(draco::GeometryAttribute::MATERIAL, nullptr, 1, draco::DT_UINT8, false, 1, 0);
    const int id = mesh->AddAttribute(a, false, static_cast<uint32_t>(regions->labels.size()));
    for (uint32_t r = 0; r < regions->labels.size(); ++r) {
      const uint8_t value = static_cast<uint8_t>(r);
      mesh->attribute(id)->SetAttributeValue(draco::AttributeValueIndex(r), &value);
    }
    mesh->attribute(id)->SetExplicitMapping(s.vertices.size());
    for (uint32_t i = 0; i < s.vertices.size(); ++i)
      mesh->attribute(id)->SetPointMapEntry(draco::PointIndex(i),
                                            draco::AttributeValueIndex(regions->region[i]));
    for (size_t r = 0; r < regions->labels.size(); ++r) {
      const int32_t label = regions->labels[r];
      const auto name = m.region_names.find(label);
      draco::Material* material_r = mesh->GetMaterialLibrary().MutableMaterial(static_cast<int>(r));
      material_r->SetName(name != m.region_names.end() && !name->second.empty()
                              ? name->second
                              : "region " + std::to_string(label));
      material_r->SetMetallicFactor(0);  // (a metal shows black without an environment to reflect)
    }
  }
  for (const auto& tri : s.triangles)
    mesh->AddFace({draco::PointIndex(tri[0]), draco::PointIndex(tri[1]), draco::PointIndex(tri[2])});
  return mesh;
}

// Draco's speed 3 (compression level 7): its glTF encoder's default.
constexpr int kDracoSpeed = 3;

std::string bytes_of(const draco::EncoderBuffer& buffer) { return {buffer.data(), buffer.size()}; }

void check(const draco::Status& s, const std::string& path) {
  if (!s.ok()) throw std::invalid_argument(path + ": Draco: " + s.error_msg_string());
}

uint32_t read_u32(const std::string& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);  // GLB is little-endian, as this machine
  return v;
}

void append_u32(std::string& out, uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); }

// A GLB's two chunks: its JSON and its binary buffer.
std::pair<nlohmann::json, std::string> split_glb(const std::string& glb) {
  const uint32_t json_length = read_u32(glb, 12);
  std::string bin;
  if (glb.size() > 20 + size_t{json_length} + 8)
    bin = glb.substr(20 + size_t{json_length} + 8, read_u32(glb, 20 + json_length));
  return {nlohmann::json::parse(glb.substr(20, json_length)), bin};
}

// GLB: a 12-byte header, the JSON chunk padded with spaces and the BIN chunk
// padded with zeros to 4 bytes (glTF 2.0, "GLB File Format Specification").
std::string assemble_glb(const nlohmann::json& json, const std::string& bin) {
  std::string text = json.dump();
  text.resize((text.size() + 3) / 4 * 4, ' ');
  std::string data = bin;
  data.resize((data.size() + 3) / 4 * 4, '\0');
  std::string out = "glTF";
  append_u32(out, 2);
  append_u32(out, static_cast<uint32_t>(12 + 8 + text.size() + (data.empty() ? 0 : 8 + data.size())));
  append_u32(out, static_cast<uint32_t>(text.size()));
  append_u32(out, 0x4E4F534A);  // "JSON"
  out += text;
  if (!data.empty()) {
    append_u32(out, static_cast<uint32_t>(data.size()));
    append_u32(out, 0x004E4942);  // "BIN\0"
    out += data;
  }
  return out;
}

}  // namespace

bool draws_regions(const OutputMesh& m, MeshFormat format, const SurfaceStyle& style) {
  if (format != MeshFormat::kGlb && format != MeshFormat::kGltf && format != MeshFormat::kDrc) return false;
  // (A field named "region" is drawn as a field where the mesh has no regions.)
  const bool region_field =
      std::any_of(m.fields.begin(), m.fields.end(), [](const OutputField& f) { return f.name == "region"; });
  return style.colour == "region" && (!m.region.empty() || !region_field);
}

RegionSurfaces region_surfaces(const OutputMesh& m) {
  if (m.region.empty())
    throw std::invalid_argument("--color region: the mesh has no regions (its stream was made without them)");
  RegionSurfaces out;
  out.labels = m.region;
  std::sort(out.labels.begin(), out.labels.end());
  out.labels.erase(std::unique(out.labels.begin(), out.labels.end()), out.labels.end());
  if (out.labels.size() > 255) throw std::invalid_argument("--color region: over 255 regions");
  // Each region's cells, in one pass.
  std::vector<std::vector<std::array<uint32_t, 4>>> cells(out.labels.size());
  for (size_t c = 0; c < m.cells.size(); ++c)
    cells[static_cast<size_t>(std::lower_bound(out.labels.begin(), out.labels.end(), m.region[c]) -
                              out.labels.begin())]
        .push_back(m.cells[c]);
  std::vector<int64_t> local(m.points.size(), -1);
  for (size_t r = 0; r < out.labels.size(); ++r) {
    const std::vector<std::array<uint32_t, 3>> faces = boundary_triangles(cells[r]);
    std::fill(local.begin(), local.end(), -1);
    for (const auto& f : faces)
      for (const uint32_t v : f) local[v] = 0;
    for (uint32_t v = 0; v < m.points.size(); ++v)
      if (local[v] == 0) {
        local[v] = static_cast<int64_t>(out.surface.vertices.size());
        out.surface.vertices.push_back(v);
        out.region.push_back(static_cast<uint8_t>(r));
      }
    for (const auto& f : faces)
      out.surface.triangles.push_back({static_cast<uint32_t>(local[f[0]]), static_cast<uint32_t>(local[f[1]]),
                                       static_cast<uint32_t>(local[f[2]])});
  }
  return out;
}

SurfaceQuantization surface_quantization(const OutputMesh& mesh, const BoundarySurface& s,
                                         MeshFormat format) {
  SurfaceQuantization q;
  q.grid_step = mesh.grid.step;
  if (s.vertices.empty()) return q;
  GridPoint low = mesh.points[s.vertices[0]], high = low;
  for (const uint32_t v : s.vertices) {
    const GridPoint& p = mesh.points[v];
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  // A glTF file's positions are offsets from the surface's least corner.
  q.anchor = format == MeshFormat::kDrc ? InputPoint{0, 0, 0} : mesh.grid.to_input(low);
  const InputPoint& anchor = q.anchor;
  const std::vector<std::array<float, 3>> positions = float_positions(mesh, s, anchor);
  for (size_t i = 0; i < s.vertices.size(); ++i) {
    const InputPoint p = mesh.grid.to_input(mesh.points[s.vertices[i]]);
    const double d[3] = {p.x - anchor.x, p.y - anchor.y, p.z - anchor.z};
    for (int a = 0; a < 3; ++a)
      q.float_error = std::max(q.float_error, std::abs(static_cast<double>(positions[i][a]) - d[a]));
  }
  const int64_t extent =
      std::max({int64_t{high.x} - low.x, int64_t{high.y} - low.y, int64_t{high.z} - low.z});
  q.position_bits = 1;
  while ((int64_t{1} << q.position_bits) - 1 < extent) ++q.position_bits;
  q.draco_step =
      static_cast<double>(extent) * mesh.grid.step / static_cast<double>((int64_t{1} << q.position_bits) - 1);
  return q;
}

std::vector<std::pair<std::string, std::string>> render_surface_gltf(const OutputMesh& m, MeshFormat format,
                                                                     const std::string& path,
                                                                     const SurfaceStyle& style) {
  const BoundarySurface s = boundary_surface(m);
  if (s.triangles.empty())
    throw std::invalid_argument(
        path + ": the level's boundary surface is empty (no carved tetrahedron): nothing to write");
  const SurfaceQuantization q = surface_quantization(m, s, format);
  const InputPoint& anchor = q.anchor;
  // (Every region's vertices lie in the whole surface's box: its
  // quantization holds them.)
  std::optional<RegionSurfaces> regions;
  if (draws_regions(m, format, style)) regions = region_surfaces(m);
  std::unique_ptr<draco::Mesh> mesh =
      draco_surface(m, regions ? regions->surface : s, style, anchor, regions ? &*regions : nullptr);

  if (format == MeshFormat::kDrc) {
    draco::Encoder encoder;
    encoder.SetSpeedOptions(kDracoSpeed, kDracoSpeed);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, q.position_bits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, kNormalBits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::COLOR, kColourBits);
    draco::EncoderBuffer buffer;
    check(encoder.EncodeMeshToBuffer(*mesh, &buffer), path);
    return {{path, bytes_of(buffer)}};
  }

  mesh->SetCompressionEnabled(style.draco);
  if (style.draco) {
    draco::DracoCompressionOptions options;
    options.quantization_position.SetQuantizationBits(q.position_bits);
    options.quantization_bits_normal = kNormalBits;
    options.quantization_bits_color = kColourBits;
    options.compression_level = 10 - kDracoSpeed;
    mesh->SetCompressionOptions(options);
  }
  draco::GltfEncoder encoder;
  draco::EncoderBuffer buffer;
  check(encoder.EncodeToBuffer(*mesh, &buffer), path);
  // Draco's encoder names itself the generator and greys the vertex colours
  // (base colour 0.75): say who wrote the file, and show the colours as made.
  // Named, not a structured binding: a lambda below captures the JSON.
  std::pair<nlohmann::json, std::string> parts = split_glb(bytes_of(buffer));
  nlohmann::json& json = parts.first;
  const std::string& bin = parts.second;
  json["asset"]["generator"] = std::string("dtmesh meshdec ") + DTM_VERSION;
  // The positions are offsets from the anchor: the node puts them back.
  for (auto& node : json["nodes"])
    if (node.contains("mesh")) node["translation"] = {anchor.x, anchor.y, anchor.z};
  for (auto& material : json["materials"]) material["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 1};
  // Plain buffers: say which views hold indices and which vertices, as the
  // glTF validator advises (GPU uploads can then be typed ahead of use).
  for (const auto& mesh_json : json["meshes"])
    for (const auto& primitive : mesh_json["primitives"]) {
      if (primitive.contains("extensions")) continue;
      auto target = [&](int accessor, int kind) {
        const auto& a = json["accessors"][accessor];
        if (a.contains("bufferView")) json["bufferViews"][a["bufferView"].get<int>()]["target"] = kind;
      };
      if (primitive.contains("indices"))
        target(primitive["indices"].get<int>(), 34963);  // ELEMENT_ARRAY_BUFFER
      for (const auto& [name, accessor] : primitive["attributes"].items()) target(accessor.get<int>(), 34962);
    }
  if (format == MeshFormat::kGlb) return {{path, assemble_glb(json, bin)}};
  const std::filesystem::path bin_path = std::filesystem::path(path).replace_extension(".bin");
  json["buffers"][0]["uri"] = uri_of(bin_path.filename().string());
  return {{path, json.dump(1)}, {bin_path.string(), bin}};
}

}  // namespace dtm
