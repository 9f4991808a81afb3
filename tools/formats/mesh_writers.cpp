#include "mesh_writers.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <climits>
#include <filesystem>
#include <stdexcept>
#include <type_traits>

#include "abaqus.h"
#include "exodus.h"
#include "gltf_writer.h"
#include "gmsh.h"
#include "medit.h"
#include "netgen_vol.h"
#include "render_util.h"
#include "surface_writers.h"
#include "vtk_cells.h"
#include "vtk_legacy.h"

namespace dtm {
namespace {

constexpr std::string_view kNodeExt = ".node";
constexpr std::string_view kProducer = "dtmesh";

void validate(const OutputMesh& m) {
  const size_t n = m.points.size();
  if (!m.level.empty() && m.level.size() != n)
    throw std::invalid_argument("mesh writer: " + std::to_string(m.level.size()) + " levels for " +
                                std::to_string(n) + " points");
  if (!m.boundary.empty() && m.boundary.size() != n)
    throw std::invalid_argument("mesh writer: " + std::to_string(m.boundary.size()) + " boundary flags for " +
                                std::to_string(n) + " points");
  for (const OutputField& f : m.fields)
    if (f.components < 1 || f.bits.size() != n * f.components)
      throw std::invalid_argument("mesh writer: field '" + f.name + "' has " + std::to_string(f.bits.size()) +
                                  " values for " + std::to_string(n) + " points");
  if (m.face_tags.size() != m.faces.size())
    throw std::invalid_argument("mesh writer: " + std::to_string(m.face_tags.size()) + " tags for " +
                                std::to_string(m.faces.size()) + " faces");
  for (const auto& f : m.faces)
    for (uint32_t v : f)
      if (v >= n) throw std::invalid_argument("mesh writer: a face names vertex " + std::to_string(v));
  for (const OutputField& f : m.cell_fields)
    if (f.components < 1 || f.bits.size() != m.cells.size() * f.components)
      throw std::invalid_argument("mesh writer: cell array '" + f.name + "' has " +
                                  std::to_string(f.bits.size()) + " values for " +
                                  std::to_string(m.cells.size()) + " cells");
  if (!m.region.empty() && m.region.size() != m.cells.size())
    throw std::invalid_argument("mesh writer: " + std::to_string(m.region.size()) + " regions for " +
                                std::to_string(m.cells.size()) + " cells");
  for (size_t c = 0; c < m.cells.size(); ++c)
    for (uint32_t v : m.cells[c])
      if (v >= n)
        throw std::invalid_argument("mesh writer: cell " + std::to_string(c) + " names vertex " +
                                    std::to_string(v) + " of " + std::to_string(n));
  if (m.edge_nodes > n || (!m.cell_edge_nodes.empty() && m.cell_edge_nodes.size() != m.cells.size()) ||
      (!m.face_edge_nodes.empty() && m.face_edge_nodes.size() != m.faces.size()))
    throw std::invalid_argument("mesh writer: edge nodes that are not the cells' and faces'");
  if (!m.node_labels.empty() && m.node_labels.size() != n)
    throw std::invalid_argument("mesh writer: " + std::to_string(m.node_labels.size()) + " node labels for " +
                                std::to_string(n) + " points");
  if (m.cell_edge_nodes.empty() && m.face_edge_nodes.empty()) return;
  std::vector<uint8_t> corner(n, 0);
  for (const auto& c : m.cells)
    for (uint32_t v : c) corner[v] = 1;
  for (const auto& f : m.faces)
    for (uint32_t v : f) corner[v] = 1;
  for (const auto& e : m.cell_edge_nodes)
    for (uint32_t v : e)
      if (v != kNoEdgePoint && (v >= n || corner[v]))
        throw std::invalid_argument("mesh writer: a cell's edge node is not one of the edge nodes");
  for (const auto& e : m.face_edge_nodes)
    for (uint32_t v : e)
      if (v != kNoEdgePoint && (v >= n || corner[v]))
        throw std::invalid_argument("mesh writer: a face's edge node is not one of the edge nodes");
}

bool has_node_extension(const std::string& path) { return lower_extension(path) == kNodeExt; }

// --- TetGen -----------------------------------------------------------------

// The field TetGen's marker column carries back, if the stream has it.
const OutputField* marker_field(const OutputMesh& m) {
  for (const OutputField& f : m.fields)
    if (f.name == "boundary_marker" && f.components == 1 && is_integer(f.type)) return &f;
  return nullptr;
}

std::string render_node(const OutputMesh& m) {
  const OutputField* marker = marker_field(m);
  const bool markers = marker || !m.boundary.empty();
  // Every other field's components are attributes (TetGen's are doubles).
  size_t attributes = 0;
  for (const OutputField& f : m.fields)
    if (&f != marker) attributes += f.components;
  std::string out;
  out.reserve(m.points.size() * 64);
  append_number(out, m.points.size());
  out += " 3 " + std::to_string(attributes) + (markers ? " 1\n" : " 0\n");
  append_lines(out, m.points.size(), [&](size_t i, std::string& line) {
    const InputPoint p = m.grid.to_input(m.points[i]);
    append_number(line, i);
    for (double x : {p.x, p.y, p.z}) {
      line += ' ';
      append_number(line, x);
    }
    for (const OutputField& f : m.fields)
      if (&f != marker)
        for (int c = 0; c < f.components; ++c) {
          line += ' ';
          append_scalar_text(line, f.bits[i * f.components + c], f.type);
        }
    if (markers) {
      line += ' ';
      if (marker)
        append_scalar_text(line, marker->bits[i], marker->type);
      else
        append_number(line, unsigned{m.boundary[i]});
    }
    line += '\n';
  });
  out += "# written by " + std::string(kProducer) + "\n";
  return out;
}

std::string render_ele(const OutputMesh& m) {
  std::string out;
  out.reserve(m.cells.size() * 40);
  append_number(out, m.cells.size());
  // The region, where there is one, as TetGen's region attribute.
  out += m.region.empty() ? " 4 0\n" : " 4 1\n";
  append_lines(out, m.cells.size(), [&](size_t i, std::string& line) {
    append_number(line, i);
    for (uint32_t v : m.cells[i]) {
      line += ' ';
      append_number(line, v);
    }
    if (!m.region.empty()) {
      line += ' ';
      append_number(line, m.region[i]);
    }
    line += '\n';
  });
  out += "# written by " + std::string(kProducer) + "\n";
  return out;
}

// The tagged faces as a TetGen .face, each tag its boundary marker (as
// meshenc reads a .face beside a .node).
std::string render_face(const OutputMesh& m) {
  std::string out;
  append_number(out, m.faces.size());
  out += " 1\n";
  append_lines(out, m.faces.size(), [&](size_t i, std::string& line) {
    append_number(line, i);
    for (uint32_t v : m.faces[i]) {
      line += ' ';
      append_number(line, v);
    }
    line += ' ';
    line += std::to_string(m.face_tags[i]);
    line += '\n';
  });
  out += "# written by " + std::string(kProducer) + "\n";
  return out;
}

// --- VTK XML ----------------------------------------------------------------

// One <DataArray> of `components`-tuples. `values` is flat; ascii puts
// `per_line` values on a line (connectivity is a 1-component array to VTK,
// but reads best 4 to a line).
template <class T>
void data_array(std::string& out, const char* type, const char* name, int components, size_t per_line,
                const std::vector<T>& values, bool binary) {
  out += "        <DataArray type=\"" + std::string(type) + "\" Name=\"" + name + "\"";
  if (components > 1) out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  out += binary ? " format=\"binary\">\n          " : " format=\"ascii\">\n";
  if (binary) {
    // One uncompressed block: the UInt64 byte count (header_type), then the data,
    // base64-encoded together as VTK's own writer does.
    std::string raw;
    raw.reserve(8 + values.size() * sizeof(T));
    append_binary(raw, uint64_t{values.size() * sizeof(T)});
    for (T v : values) append_binary(raw, v);
    out += base64_encode(raw);
    out += '\n';
  } else {
    for (size_t i = 0; i < values.size(); ++i) {
      out += i % per_line == 0 ? "          " : " ";
      append_number(out, values[i]);
      if ((i + 1) % per_line == 0) out += '\n';
    }
  }
  out += "        </DataArray>\n";
}

// A name inside an XML attribute.
std::string xml_escaped(const std::string& name) {
  std::string out;
  for (char ch : name) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

const char* vtu_type(ScalarType t) {
  constexpr const char* kNames[] = {"Int8",   "UInt8", "Int16",  "UInt16",  "Int32",
                                    "UInt32", "Int64", "UInt64", "Float32", "Float64"};
  return kNames[static_cast<int>(t)];
}

// A field's <DataArray>, its values written in their own type.
void field_array(std::string& out, const OutputField& f, bool binary) {
  out += "        <DataArray type=\"" + std::string(vtu_type(f.type)) + "\" Name=\"" + xml_escaped(f.name) +
         "\"";
  if (f.components > 1) out += " NumberOfComponents=\"" + std::to_string(f.components) + "\"";
  out += binary ? " format=\"binary\">\n          " : " format=\"ascii\">\n";
  if (binary) {
    std::string raw;
    raw.reserve(8 + f.bits.size() * scalar_size(f.type));
    append_binary(raw, uint64_t{f.bits.size() * scalar_size(f.type)});
    for (uint64_t b : f.bits) append_scalar_binary(raw, b, f.type);
    out += base64_encode(raw);
    out += '\n';
  } else {
    for (size_t i = 0; i < f.bits.size(); ++i) {
      out += i % f.components == 0 ? "          " : " ";
      append_scalar_text(out, f.bits[i], f.type);
      if ((i + 1) % f.components == 0) out += '\n';
    }
  }
  out += "        </DataArray>\n";
}

}  // namespace

std::vector<int32_t> physical_tags(const OutputMesh& m) {
  if (m.region.empty() && m.faces.empty()) return {};
  std::vector<int32_t> out = m.region;
  out.resize(m.cells.size(), 0);
  out.insert(out.end(), m.face_tags.begin(), m.face_tags.end());
  return out;
}

std::vector<std::string> not_written(const OutputMesh& m, MeshFormat format, const SurfaceStyle& style) {
  std::vector<std::string> out;
  const auto names = [](const std::vector<OutputField>& fields, const auto& dropped) {
    std::string list;
    for (const OutputField& f : fields)
      if (dropped(f)) list += (list.empty() ? "'" : ", '") + f.name + "'";
    return list;
  };
  // (vertex_id: meshdec's numbering of a box or a piece, derived too.)
  const auto all = [](const OutputField& f) { return f.name != "vertex_id"; };
  // gmsh's $NodeData and $ElementData: scalars, vectors, tensors.
  const auto not_gmsh = [](const OutputField& f) {
    return f.components != 1 && f.components != 3 && f.components != 9 && f.name != "vertex_id";
  };
  const auto add = [&](const std::string& what, const std::string& list) {
    if (!list.empty()) out.push_back(what + " " + list);
  };
  const bool surface = format == MeshFormat::kPly || format == MeshFormat::kOff ||
                       format == MeshFormat::kXyz || format == MeshFormat::kGlb ||
                       format == MeshFormat::kGltf || format == MeshFormat::kDrc;
  // The labels' names: gmsh's $PhysicalNames, Netgen's materials and
  // boundary condition names, Abaqus's set names and Exodus's block and set
  // names hold them; VTK's arrays, Medit's refs and TetGen's attributes are
  // numbers only.
  const auto label_names = [](const std::map<int32_t, std::string>& names) {
    std::string list;
    size_t listed = 0;
    for (const auto& [label, name] : names)
      if (++listed <= 8) list += (list.empty() ? "" : ", ") + std::to_string(label) + " \"" + name + "\"";
    if (listed > 8) list += " and " + std::to_string(listed - 8) + " more";
    return list;
  };
  if (!surface && format != MeshFormat::kGmsh && format != MeshFormat::kNetgen &&
      format != MeshFormat::kAbaqus && format != MeshFormat::kExodus) {
    if (!m.region.empty() && !m.region_names.empty())
      out.push_back("the regions' names (" + label_names(m.region_names) + ")");
    if (!m.faces.empty() && !m.face_tag_names.empty())
      out.push_back("the face tags' names (" + label_names(m.face_tag_names) + ")");
  }
  switch (format) {
    case MeshFormat::kVtu:
    case MeshFormat::kVtuAscii:
    case MeshFormat::kVtk:
    case MeshFormat::kVtkAscii:
      break;
    case MeshFormat::kGmsh:
      add("the point fields (gmsh holds 1, 3 or 9 components)", names(m.fields, not_gmsh));
      add("the cell arrays (gmsh holds 1, 3 or 9 components)", names(m.cell_fields, not_gmsh));
      break;
    case MeshFormat::kAbaqus:
      add("the point fields (an .inp holds node sets only)",
          names(m.fields, [&](const OutputField& f) { return all(f) && !is_node_set_field(f); }));
      add("the cell arrays", names(m.cell_fields, all));
      break;
    case MeshFormat::kMedit:
    case MeshFormat::kNetgen:
      add("the point fields", names(m.fields, all));
      add("the cell arrays", names(m.cell_fields, all));
      break;
    case MeshFormat::kTetgen: {
      // (A .face marker 0 is no tag, and markers all 1 are TetGen's own
      // marking, to meshenc: such tags are written, and do not read back.)
      if (const auto zeros = std::count(m.face_tags.begin(), m.face_tags.end(), 0); zeros > 0)
        out.push_back("the tag 0 of " + std::to_string(zeros) +
                      " faces as a tag (written in the .face, where marker 0 reads back as no tag)");
      else if (!m.faces.empty() &&
               std::all_of(m.face_tags.begin(), m.face_tags.end(), [](int32_t t) { return t == 1; }))
        out.push_back(
            "the faces' tag 1 as a tag (written in the .face, where markers all 1 read back as "
            "TetGen's default marking)");
      // (Their values are the .node's attributes, in order: only what they
      // were is lost.)
      const OutputField* marker = marker_field(m);
      add("the point fields' names, components and types (a .node's attributes are numbers only, written in "
          "this order)",
          names(m.fields, [&](const OutputField& f) { return all(f) && &f != marker; }));
      add("the cell arrays", names(m.cell_fields, all));
      break;
    }
    default:
      break;
  }
  // (A surface's point fields are PLY's properties, glTF's colour; OFF and
  // XYZ hold none.)
  if (format == MeshFormat::kOff || format == MeshFormat::kXyz) add("the point fields", names(m.fields, all));
  if (format == MeshFormat::kGlb || format == MeshFormat::kGltf || format == MeshFormat::kDrc)
    add("the point fields (a glTF or Draco surface's colours come from --color)",
        names(m.fields, [&](const OutputField& f) { return all(f) && f.name != style.colour; }));
  if (surface) {
    const bool coloured =
        format == MeshFormat::kGlb || format == MeshFormat::kGltf || format == MeshFormat::kDrc;
    if (!m.region.empty() && !draws_regions(m, format, style))
      out.push_back(coloured ? "the cells' regions (--color region draws each region's surface)"
                             : "the cells' regions");
    if (!m.faces.empty()) out.push_back(std::to_string(m.faces.size()) + " tagged faces");
    add("the cell arrays", names(m.cell_fields, all));
  }
  return out;
}

ListedNodes cell_nodes(const OutputMesh& m, size_t cell, const std::array<uint8_t, 6>& edge_slots) {
  ListedNodes out;
  for (uint32_t v : m.cells[cell]) out.nodes[out.count++] = v;
  if (m.cell_edge_nodes.empty()) return out;
  const auto& e = m.cell_edge_nodes[cell];
  if (std::find(e.begin(), e.end(), kNoEdgePoint) != e.end()) return out;
  for (uint8_t slot : edge_slots) out.nodes[out.count++] = e[slot];
  return out;
}

ListedNodes face_nodes(const OutputMesh& m, size_t face) {
  ListedNodes out;
  for (uint32_t v : m.faces[face]) out.nodes[out.count++] = v;
  if (m.face_edge_nodes.empty()) return out;
  const auto& e = m.face_edge_nodes[face];
  if (std::find(e.begin(), e.end(), kNoEdgePoint) != e.end()) return out;
  for (uint32_t v : e) out.nodes[out.count++] = v;
  return out;
}

bool writes_edge_nodes(MeshFormat format) {
  return format == MeshFormat::kVtu || format == MeshFormat::kVtuAscii || format == MeshFormat::kVtk ||
         format == MeshFormat::kVtkAscii || format == MeshFormat::kGmsh || format == MeshFormat::kAbaqus ||
         format == MeshFormat::kExodus;
}

OutputMesh without_edge_nodes(OutputMesh mesh) {
  if (mesh.edge_nodes == 0) return mesh;
  // The points that are no edge node keep their order (with --keep-order,
  // the input's numbering of its corners).
  const size_t all = mesh.points.size();
  std::vector<uint8_t> node(all, 0);
  for (const auto& e : mesh.cell_edge_nodes)
    for (uint32_t v : e)
      if (v < all) node[v] = 1;
  for (const auto& e : mesh.face_edge_nodes)
    for (uint32_t v : e)
      if (v < all) node[v] = 1;
  std::vector<uint32_t> index(all, kNoEdgePoint);
  uint32_t n = 0;
  for (size_t p = 0; p < all; ++p)
    if (!node[p]) index[p] = n++;
  const auto keep = [&](auto& values, size_t per) {
    if (values.empty()) return;
    size_t to = 0;
    for (size_t p = 0; p < all; ++p)
      if (!node[p])
        for (size_t c = 0; c < per; ++c) values[to++] = values[p * per + c];
    values.resize(to);
  };
  keep(mesh.points, 1);
  keep(mesh.level, 1);
  keep(mesh.boundary, 1);
  keep(mesh.node_labels, 1);
  for (OutputField& f : mesh.fields) keep(f.bits, static_cast<size_t>(f.components));
  for (auto& c : mesh.cells)
    for (uint32_t& v : c) v = index[v];
  for (auto& f : mesh.faces)
    for (uint32_t& v : f) v = index[v];
  mesh.edge_nodes = 0;
  mesh.cell_edge_nodes.clear();
  mesh.face_edge_nodes.clear();
  return mesh;
}

std::vector<OutputField> cell_and_face_fields(const OutputMesh& m) {
  std::vector<OutputField> out = m.cell_fields;
  for (OutputField& f : out) f.bits.resize((m.cells.size() + m.faces.size()) * f.components, 0);
  return out;
}

namespace {

std::string render_vtu(const OutputMesh& m, bool binary) {
  std::vector<double> coords;
  coords.reserve(3 * m.points.size());
  for (const GridPoint& g : m.points) {
    const InputPoint p = m.grid.to_input(g);
    coords.insert(coords.end(), {p.x, p.y, p.z});
  }
  // Our positive orientation (det(b-a, c-a, d-a) > 0) is VTK_TETRA's: the
  // fourth point lies on the right-hand normal side of the first three.
  // (A second-order one's edge nodes after its corners: VTK_QUADRATIC_TETRA.)
  std::vector<int64_t> connectivity, offsets;
  std::vector<uint8_t> types;
  connectivity.reserve(4 * m.cells.size());
  offsets.reserve(m.cells.size() + m.faces.size());
  types.reserve(m.cells.size() + m.faces.size());
  for (size_t c = 0; c < m.cells.size(); ++c) {
    const ListedNodes e = cell_nodes(m, c, kVtkEdgeSlots);
    connectivity.insert(connectivity.end(), e.nodes.begin(),
                        e.nodes.begin() + static_cast<std::ptrdiff_t>(e.count));
    offsets.push_back(static_cast<int64_t>(connectivity.size()));
    types.push_back(e.second_order() ? kVtkQuadraticTetra : kVtkTetra);
  }
  // The tagged faces after the tetrahedra, as triangles.
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const ListedNodes e = face_nodes(m, f);
    connectivity.insert(connectivity.end(), e.nodes.begin(),
                        e.nodes.begin() + static_cast<std::ptrdiff_t>(e.count));
    offsets.push_back(static_cast<int64_t>(connectivity.size()));
    types.push_back(e.second_order() ? kVtkQuadraticTriangle : kVtkTriangle);
  }
  const std::vector<int32_t> physical = physical_tags(m);

  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <Piece NumberOfPoints=\"" +
      std::to_string(m.points.size()) + "\" NumberOfCells=\"" + std::to_string(types.size()) + "\">\n";
  const bool level = !m.level.empty() || m.declare_level;
  if (level || !m.boundary.empty() || !m.fields.empty()) {
    out += "      <PointData>\n";
    if (level) data_array(out, "Int32", "level", 1, 1, m.level, binary);
    if (!m.boundary.empty()) data_array(out, "UInt8", "boundary", 1, 1, m.boundary, binary);
    for (const OutputField& f : m.fields) field_array(out, f, binary);
    out += "      </PointData>\n";
  }
  const bool region = !physical.empty() || m.declare_region;
  if (region || !m.cell_fields.empty()) {
    out += region ? "      <CellData Scalars=\"region\">\n" : "      <CellData>\n";
    if (region) data_array(out, "Int32", "region", 1, 1, physical, binary);
    for (const OutputField& f : cell_and_face_fields(m)) field_array(out, f, binary);
    out += "      </CellData>\n";
  }
  out += "      <Points>\n";
  data_array(out, "Float64", "Points", 3, 3, coords, binary);
  out += "      </Points>\n      <Cells>\n";
  data_array(out, "Int64", "connectivity", 1, 4, connectivity, binary);
  data_array(out, "Int64", "offsets", 1, 1, offsets, binary);
  data_array(out, "UInt8", "types", 1, 1, types, binary);
  out +=
      "      </Cells>\n"
      "    </Piece>\n"
      "  </UnstructuredGrid>\n"
      "</VTKFile>\n";
  return out;
}

}  // namespace

std::string render_pvtu(const OutputMesh& like, std::span<const std::string> pieces) {
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  const auto declare = [&](const OutputField& f) {
    out += "      <PDataArray type=\"" + std::string(vtu_type(f.type)) + "\" Name=\"" + xml_escaped(f.name) +
           "\"";
    if (f.components > 1) out += " NumberOfComponents=\"" + std::to_string(f.components) + "\"";
    out += "/>\n";
  };
  const bool level = !like.level.empty() || like.declare_level;
  if (level || !like.boundary.empty() || !like.fields.empty()) {
    out += "    <PPointData>\n";
    if (level) out += "      <PDataArray type=\"Int32\" Name=\"level\"/>\n";
    if (!like.boundary.empty()) out += "      <PDataArray type=\"UInt8\" Name=\"boundary\"/>\n";
    for (const OutputField& f : like.fields) declare(f);
    out += "    </PPointData>\n";
  }
  const bool region = !like.region.empty() || !like.faces.empty() || like.declare_region;
  if (region || !like.cell_fields.empty()) {
    out += region ? "    <PCellData Scalars=\"region\">\n" : "    <PCellData>\n";
    if (region) out += "      <PDataArray type=\"Int32\" Name=\"region\"/>\n";
    for (const OutputField& f : like.cell_fields) declare(f);
    out += "    </PCellData>\n";
  }
  out +=
      "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    "
      "</PPoints>\n";
  for (const std::string& piece : pieces) out += "    <Piece Source=\"" + xml_escaped(piece) + "\"/>\n";
  out += "  </PUnstructuredGrid>\n</VTKFile>\n";
  return out;
}

std::string base64_encode(std::string_view bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out((bytes.size() + 2) / 3 * 4, '=');
  // Every 3 bytes are 4 characters of their own: ranges on every core.
  const size_t whole = bytes.size() / 3;
  parallel_ranges(whole, size_t{1} << 18, [&](size_t first, size_t last) {
    for (size_t g = first; g < last; ++g) {
      const size_t i = 3 * g;
      const uint32_t w = uint32_t{static_cast<uint8_t>(bytes[i])} << 16 |
                         uint32_t{static_cast<uint8_t>(bytes[i + 1])} << 8 |
                         uint32_t{static_cast<uint8_t>(bytes[i + 2])};
      for (int k = 0; k < 4; ++k) out[4 * g + static_cast<size_t>(k)] = kAlphabet[(w >> (18 - 6 * k)) & 63];
    }
  });
  if (const size_t rest = bytes.size() - 3 * whole; rest > 0) {
    const size_t i = 3 * whole, o = 4 * whole;
    uint32_t w = uint32_t{static_cast<uint8_t>(bytes[i])} << 16;
    if (rest == 2) w |= uint32_t{static_cast<uint8_t>(bytes[i + 1])} << 8;
    out[o] = kAlphabet[(w >> 18) & 63];
    out[o + 1] = kAlphabet[(w >> 12) & 63];
    if (rest == 2) out[o + 2] = kAlphabet[(w >> 6) & 63];
  }
  return out;
}

// ".VTU" names a .vtu, as meshenc reads its inputs' extensions in any case.
std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

MeshFormat format_for_path(const std::string& path) {
  // extension() gives "" for "dir/.node" (a hidden file without a stem), so
  // that is rejected too.
  const std::string ext = lower_extension(path);
  if (ext == kNodeExt) return MeshFormat::kTetgen;
  if (ext == ".vtu") return MeshFormat::kVtu;
  if (ext == ".vtk") return MeshFormat::kVtk;
  if (ext == ".mesh") return MeshFormat::kMedit;
  if (ext == ".msh") return MeshFormat::kGmsh;
  if (ext == ".vol") return MeshFormat::kNetgen;
  if (ext == ".inp") return MeshFormat::kAbaqus;
  if (ext == ".e" || ext == ".exo") return MeshFormat::kExodus;
  if (ext == ".ply") return MeshFormat::kPly;
  if (ext == ".off") return MeshFormat::kOff;
  if (ext == ".xyz") return MeshFormat::kXyz;
  if (ext == ".glb") return MeshFormat::kGlb;
  if (ext == ".gltf") return MeshFormat::kGltf;
  if (ext == ".drc") return MeshFormat::kDrc;
  throw std::invalid_argument(
      path +
      ": unknown output format (expected a .node, .vtu, .vtk, .mesh, .msh, .vol, .inp, .e, .exo, "
      ".ply, .off, .xyz, .glb, .gltf "
      "or .drc file name)");
}

MeshFormat format_named(const std::string& name) {
  static const std::pair<const char*, MeshFormat> kNames[] = {{"node", MeshFormat::kTetgen},
                                                              {"vtu", MeshFormat::kVtu},
                                                              {"vtu-ascii", MeshFormat::kVtuAscii},
                                                              {"vtk", MeshFormat::kVtk},
                                                              {"vtk-ascii", MeshFormat::kVtkAscii},
                                                              {"mesh", MeshFormat::kMedit},
                                                              {"msh", MeshFormat::kGmsh},
                                                              {"vol", MeshFormat::kNetgen},
                                                              {"inp", MeshFormat::kAbaqus},
                                                              {"e", MeshFormat::kExodus},
                                                              {"ply", MeshFormat::kPly},
                                                              {"off", MeshFormat::kOff},
                                                              {"xyz", MeshFormat::kXyz},
                                                              {"glb", MeshFormat::kGlb},
                                                              {"gltf", MeshFormat::kGltf},
                                                              {"drc", MeshFormat::kDrc}};
  for (const auto& [n, f] : kNames)
    if (name == n) return f;
  throw std::invalid_argument("unknown output format '" + name + "' (known: " + kOutputFormatNames + ")");
}

std::vector<std::pair<std::string, std::string>> render_mesh(const OutputMesh& mesh, MeshFormat format,
                                                             const std::string& path,
                                                             const SurfaceStyle& style) {
  validate(mesh);
  // (The formats without second-order cells: the linear ones.)
  if (mesh.edge_nodes > 0 && !writes_edge_nodes(format))
    return render_mesh(without_edge_nodes(mesh), format, path, style);
  // (Abaqus and CalculiX read node numbers, and Exodus II's node number
  // map holds them, as 32-bit integers; a stream's ids go to 2^62 - 1.)
  if ((format == MeshFormat::kAbaqus || format == MeshFormat::kExodus) && !mesh.node_labels.empty() &&
      *std::max_element(mesh.node_labels.begin(), mesh.node_labels.end()) > INT32_MAX)
    throw std::invalid_argument(path +
                                ": node ids above 2^31 - 1, which this format holds in 32 bits: write a .msh "
                                "(gmsh's node tags hold them)");
  switch (format) {
    case MeshFormat::kTetgen: {
      if (!has_node_extension(path))
        throw std::invalid_argument(path + ": a TetGen output path must end in .node");
      // (X.NODE's elements in X.ELE, as TetGen names them in the .node's case.)
      const bool upper = path.substr(path.size() - kNodeExt.size()) == ".NODE";
      const std::string stem = path.substr(0, path.size() - kNodeExt.size());
      std::vector<std::pair<std::string, std::string>> files = {
          {path, render_node(mesh)}, {stem + (upper ? ".ELE" : ".ele"), render_ele(mesh)}};
      // The tagged faces with their tags as boundary markers; none, where an
      // earlier .face is there (meshenc would read its markers as this
      // mesh's tags).
      const std::string face = stem + (upper ? ".FACE" : ".face");
      std::error_code ec;
      if (!mesh.faces.empty() || std::filesystem::exists(face, ec))
        files.push_back({face, render_face(mesh)});
      return files;
    }
    case MeshFormat::kVtu:
      return {{path, render_vtu(mesh, true)}};
    case MeshFormat::kVtuAscii:
      return {{path, render_vtu(mesh, false)}};
    case MeshFormat::kVtk:
      return {{path, render_vtk_legacy(mesh, true)}};
    case MeshFormat::kVtkAscii:
      return {{path, render_vtk_legacy(mesh, false)}};
    case MeshFormat::kMedit:
      return {{path, render_medit(mesh)}};
    case MeshFormat::kGmsh:
      return {{path, render_gmsh(mesh)}};
    case MeshFormat::kNetgen:
      return {{path, render_netgen_vol(mesh)}};
    case MeshFormat::kAbaqus:
      return {{path, render_abaqus(mesh)}};
    case MeshFormat::kExodus:
      return {{path, render_exodus(mesh)}};
    case MeshFormat::kPly:
      return {{path, render_ply(mesh)}};
    case MeshFormat::kOff:
      return {{path, render_off(mesh)}};
    case MeshFormat::kXyz:
      return {{path, render_xyz(mesh)}};
    case MeshFormat::kGlb:
    case MeshFormat::kGltf:
    case MeshFormat::kDrc:
      return render_surface_gltf(mesh, format, path, style);
  }
  throw std::invalid_argument(path + ": unknown mesh format");
}

}  // namespace dtm
