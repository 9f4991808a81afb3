#include "input.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>

#include "abaqus.h"
#include "exodus.h"
#include "gmsh.h"
#include "medit.h"
#include "netgen_vol.h"
#include "nrrd.h"
#include "point_sets.h"
#include "second_order.h"
#include "tagged_faces.h"
#include "tetgen.h"
#include "vtk_legacy.h"
#include "vtu_reader.h"

namespace dtm {

std::optional<InputFormat> input_format_named(std::string_view name) {
  std::string n(name);
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (n == "node" || n == "tetgen") return InputFormat::kTetgen;
  if (n == "mesh" || n == "medit") return InputFormat::kMedit;
  if (n == "vtk") return InputFormat::kVtk;
  if (n == "vtu") return InputFormat::kVtu;
  if (n == "pvtu") return InputFormat::kPvtu;
  if (n == "msh" || n == "gmsh") return InputFormat::kGmsh;
  if (n == "vol" || n == "netgen") return InputFormat::kNetgen;
  if (n == "inp" || n == "abaqus" || n == "calculix") return InputFormat::kAbaqus;
  if (n == "e" || n == "exo" || n == "ex2" || n == "g" || n == "gen" || n == "exodus")
    return InputFormat::kExodus;
  if (n == "nrrd" || n == "nhdr") return InputFormat::kNrrd;
  if (n == "ply") return InputFormat::kPly;
  if (n == "off") return InputFormat::kOff;
  if (n == "obj") return InputFormat::kObj;
  if (n == "xyz") return InputFormat::kXyz;
  return std::nullopt;
}

InputFormat input_format_for_path(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (const auto f = ext.size() > 1 ? input_format_named(ext.substr(1)) : std::nullopt) return *f;
  std::string lower = ext;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower == ".gz") {
    std::string inner = std::filesystem::path(path).stem().extension().string();
    std::transform(inner.begin(), inner.end(), inner.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (inner == ".vol") return InputFormat::kNetgen;  // Netgen saves x.vol.gz so
  }
  throw FormatError(path + ": unknown input format '" + ext + "' (known: " + kInputFormatNames +
                    "; or give --format)");
}

namespace {

// A TetGen file beside the .node (its .ele, .face): named in the .node's
// case where that one exists (X.NODE's X.ELE), else in lower case.
std::filesystem::path beside(const std::string& node, const std::string& ext) {
  std::filesystem::path p = node;
  const std::string own = p.extension().string();
  if (own.size() > 1 &&
      std::all_of(own.begin() + 1, own.end(), [](unsigned char c) { return std::isupper(c); })) {
    std::string upper = ext;
    std::transform(upper.begin(), upper.end(), upper.begin(),
                   [](unsigned char c) { return std::toupper(c); });
    if (std::filesystem::path q = std::filesystem::path(node).replace_extension(upper);
        std::filesystem::exists(q))
      return q;
  }
  return p.replace_extension(ext);
}

}  // namespace

bool tetgen_face_is_marked(const std::string& path) {
  const std::filesystem::path face = beside(path, ".face");
  std::error_code ec;
  if (!std::filesystem::exists(face, ec)) return false;
  try {
    // (Indices unchecked here: the whole read checks them.)
    const FaceFile faces = read_tetgen_face(face.string(), std::numeric_limits<size_t>::max(), 0);
    return std::any_of(faces.markers.begin(), faces.markers.end(), [](int32_t m) { return m != 1; });
  } catch (const std::exception&) {
    return false;
  }
}

namespace {

InputMesh read_tetgen(const std::string& path, bool with_ele,
                      const std::function<NodeFile(const std::string&)>& read_node) {
  NodeFile node = read_node ? read_node(path) : read_tetgen_node(path);
  InputMesh out;
  out.points = std::move(node.points);
  if (node.attribute_count > 0)
    out.fields.push_back(
        {"attributes", node.attribute_count, std::move(node.attributes), ScalarType::kFloat64});
  if (!node.markers.empty())
    out.fields.push_back({"boundary_marker", 1, std::vector<double>(node.markers.begin(), node.markers.end()),
                          ScalarType::kInt32});
  const std::filesystem::path ele = beside(path, ".ele");
  if (std::filesystem::exists(ele)) {
    const int a = tetgen_ele_attributes(ele.string());
    if (a > 1)
      out.left_out.push_back(ele.string() + "'s attributes after the first (" + std::to_string(a - 1) +
                             " per tetrahedron; the first is kept, as the region or as cell data)");
    if (with_ele) {
      std::vector<double> first;
      out.tets = read_tetgen_ele(ele.string(), out.points.size(), node.index_base, {}, nullptr,
                                 &out.tet_edge_nodes, &first);
      // TetGen's regional attributes (-A) are real numbers: integers, as
      // a .poly's regions mostly number them, are the regions; any other
      // value makes the attribute cell data (a material constant, say).
      const bool labels = std::all_of(first.begin(), first.end(), [](double a) {
        return a == std::floor(a) && a >= INT32_MIN && a <= INT32_MAX;
      });
      if (labels && !first.empty()) {
        out.tet_regions.resize(first.size());
        std::transform(first.begin(), first.end(), out.tet_regions.begin(),
                       [](double a) { return static_cast<int32_t>(a); });
        out.region_source = "region attributes (TetGen -A)";
      } else if (!first.empty()) {
        out.cell_fields.push_back({"attribute", 1, std::move(first), ScalarType::kFloat64});
      }
    } else {
      // (Its tetrahedra and their regions are read by the ranks in parts.)
      if (a > 0) out.region_source = "region attributes (TetGen -A)";
      out.tetgen_ele = ele.string(), out.tetgen_index_base = node.index_base;
    }
    // TetGen's faces beside them (tetgen -p writes the boundary's with their
    // facet markers, the boundary conditions): those with a marker other
    // than 0 are the tagged faces, unless every face of the boundary is
    // marked 1, TetGen's default where the input has no facet markers (an
    // .off or .stl), -f's inner faces 0: nothing to keep then. Without the
    // tetrahedra at hand (under mpirun, where the ranks read the .ele in
    // parts, or --no-reference), markers that may be more than that are
    // named. (A .face without markers, like TetGen's .edge and .neigh, is
    // the mesh's own, which the decoder makes again.)
    if (const auto face = beside(path, ".face"); std::filesystem::exists(face)) {
      const FaceFile faces = read_tetgen_face(face.string(), out.points.size(), node.index_base);
      bool marked =
          std::any_of(faces.markers.begin(), faces.markers.end(), [](int32_t m) { return m != 0 && m != 1; });
      const bool zeros = std::find(faces.markers.begin(), faces.markers.end(), 0) != faces.markers.end();
      if (!marked && zeros && with_ele) {
        // (A face marked 0 on the boundary, which tagged_faces_inside()
        // does not count: a .poly that marks some facets and leaves others
        // 0, not -f's inner faces.)
        std::vector<std::array<uint32_t, 3>> zero;
        for (size_t i = 0; i < faces.faces.size(); ++i)
          if (faces.markers[i] == 0) zero.push_back(faces.faces[i]);
        marked = tagged_faces_inside(out.tets, {}, zero) < zero.size();
      }
      if (!marked && zeros && !with_ele) marked = true;  // (which faces are the boundary's: not known here)
      if (marked && !with_ele) {
        out.left_out.push_back(
            face.string() +
            "'s boundary markers (the tetrahedra are read in parts, or not at all: meshenc "
            "on one process with them keeps the markers as tagged faces)");
      } else if (marked) {
        for (size_t i = 0; i < faces.markers.size(); ++i)
          if (faces.markers[i] != 0) {
            out.tagged_faces.push_back(faces.faces[i]);
            out.face_tags.push_back(faces.markers[i]);
          }
        out.face_tag_source = "the .face's boundary markers";
      }
    }
  }
  return out;
}

InputMesh read_any(const std::string& path, InputFormat format, const VolumeOptions& volume, bool tetgen_ele,
                   const std::function<NodeFile(const std::string&)>& read_node, int time_step) {
  switch (format) {
    case InputFormat::kTetgen:
      return read_tetgen(path, tetgen_ele, read_node);
    case InputFormat::kAbaqus:
      return read_abaqus(path);
    case InputFormat::kExodus:
      return read_exodus(path, time_step);
    case InputFormat::kMedit:
      return read_medit(path);
    case InputFormat::kVtk:
      return read_vtk_legacy(path);
    case InputFormat::kVtu:
      return read_vtu(path);
    case InputFormat::kPvtu:
      return read_pvtu(path);
    case InputFormat::kGmsh:
      return read_gmsh(path);
    case InputFormat::kNetgen:
      return read_netgen_vol(path);
    case InputFormat::kNrrd:
      return voxel_points(read_nrrd(path), volume, path);
    case InputFormat::kPly:
      return read_point_set(path, PointSetFormat::kPly);
    case InputFormat::kOff:
      return read_point_set(path, PointSetFormat::kOff);
    case InputFormat::kObj:
      return read_point_set(path, PointSetFormat::kObj);
    case InputFormat::kXyz:
      return read_point_set(path, PointSetFormat::kXyz);
  }
  throw FormatError(path + ": unknown input format");
}

}  // namespace

InputMesh read_input(const std::string& path, std::optional<InputFormat> format, const VolumeOptions& volume,
                     bool tetgen_ele, const std::function<NodeFile(const std::string&)>& read_node,
                     int time_step) {
  if (!std::filesystem::exists(path)) throw FormatError(path + ": cannot open file (it does not exist)");
  if (std::filesystem::is_directory(path)) throw FormatError(path + ": a directory, not a mesh file");
  InputMesh mesh = read_any(path, format ? *format : input_format_for_path(path), volume, tetgen_ele,
                            read_node, time_step);
  set_edge_nodes_aside(mesh);
  check_spans_3d(mesh.points, path);
  // A tetrahedron that names a point twice has no volume: no cell of the
  // solid (the encoder's reference shape leaves it out), said here.
  uint64_t flat = 0;
  for (const auto& t : mesh.tets)
    flat += t[0] == t[1] || t[0] == t[2] || t[0] == t[3] || t[1] == t[2] || t[1] == t[3] || t[2] == t[3];
  if (flat > 0)
    mesh.left_out.push_back(std::to_string(flat) + " tetrahedr" + (flat == 1 ? "on" : "a") +
                            " naming a point twice (no volume: not a cell of the solid)");
  return mesh;
}

}  // namespace dtm

namespace dtm {

void choose_regions(InputMesh& in, const std::string& name, const std::string& path) {
  std::string chosen = name;
  if (chosen.empty())
    for (const char* known : kRegionArrayNames)
      if (in.tet_arrays.count(known)) {
        chosen = known;
        break;
      }
  if (!name.empty() && !in.tet_arrays.count(name)) {
    std::string have;
    for (const auto& [n, a] : in.tet_arrays) have += (have.empty() ? "'" : ", '") + n + "'";
    throw FormatError(path + ": --region-array " + name + ": no integer cell array of that name" +
                      (have.empty() ? std::string(" (the file has none)") : " (it has " + have + ")"));
  }
  // The integer arrays that are not the regions become the tetrahedra's
  // cell data below: their values on a .vtu's triangles are named.
  std::string on_triangles;
  for (const auto& array : in.triangle_arrays) {
    const std::vector<int32_t>& values = array.second;
    if (array.first != chosen && any_value_said(values.size(), [&](size_t i) { return values[i]; }))
      on_triangles += (on_triangles.empty() ? "'" : ", '") + array.first + "'";
  }
  if (!on_triangles.empty())
    in.left_out.push_back("the values of the integer cell arrays " + on_triangles +
                          " on the triangles (cell data is the tetrahedra's)");
  for (auto& [n, values] : in.tet_arrays) {
    if (n == chosen) {
      in.tet_regions = std::move(values);
      in.region_source = "cell array '" + n + "'";
    } else {
      // Not the regions: cell data, in the type the file stores.
      VertexField& f = in.cell_fields.emplace_back();
      f.name = n;
      f.values.assign(values.begin(), values.end());
      const auto type = in.tet_array_types.find(n);
      f.type = type != in.tet_array_types.end() ? type->second : ScalarType::kInt32;
    }
  }
  in.tet_arrays.clear();
  in.tet_array_types.clear();
  // (The cell data in the file's order, as Python's encode() keeps them.)
  if (!in.cell_array_order.empty()) {
    const auto place = [&](const VertexField& f) {
      return std::find(in.cell_array_order.begin(), in.cell_array_order.end(), f.name) -
             in.cell_array_order.begin();
    };
    std::stable_sort(in.cell_fields.begin(), in.cell_fields.end(),
                     [&](const VertexField& a, const VertexField& b) { return place(a) < place(b); });
  }
  // A .vtu's triangles: tagged by the same array (as gmsh's physical tags
  // are, through meshio), else named.
  if (!in.tagged_faces.empty() && in.face_tags.empty()) {
    if (auto it = in.triangle_arrays.find(chosen); !chosen.empty() && it != in.triangle_arrays.end()) {
      in.face_tags = std::move(it->second);
      in.face_tag_source = "cell array '" + chosen + "'";
    } else {
      in.left_out.push_back(std::to_string(in.tagged_faces.size()) + " triangles without a tag array");
      in.tagged_faces.clear();
    }
  }
  in.triangle_arrays.clear();
}

}  // namespace dtm
