// The bad-input corpus (tests/bad/): every reader rejects each file with its
// name, where (line, or byte offset in binary data) and the problem, and
// meshenc exits non-zero with the same message and leaves no file behind.
#include <gtest/gtest.h>

#include <filesystem>

#include "format_test_support.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"

namespace dtm {
namespace {

struct BadInput {
  const char* file;
  const char* message;  // a part of the expected error, after the file name
  friend void PrintTo(const BadInput& b, std::ostream* os) { *os << b.file; }
};

class BadInputs : public ::testing::TestWithParam<BadInput> {};

bool is_volume(const std::string& path) {
  const auto ext = std::filesystem::path(path).extension();
  return ext == ".nrrd" || ext == ".nhdr";
}

TEST_P(BadInputs, TheReaderRejectsItNamingFileWhereAndProblem) {
  const std::string path = test::bad_file(GetParam().file);
  VolumeOptions volume;
  if (is_volume(path)) volume.threshold = 1;
  try {
    read_input(path, {}, volume);
    FAIL() << path << " was accepted";
  } catch (const FormatError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path, 0), 0u) << what;  // starts with the file name
    EXPECT_NE(what.find(GetParam().message), std::string::npos) << what;
  }
}

TEST_P(BadInputs, MeshencFailsWithTheMessageAndWritesNothing) {
  const std::string path = test::bad_file(GetParam().file);
  const std::string out = ::testing::TempDir() + "/bad_input.dtm",
                    report = ::testing::TempDir() + "/bad_input.json";
  std::filesystem::remove(out);
  std::filesystem::remove(report);
  const auto r =
      test::run_command(std::string(DTM_MESHENC) + " " + path + (is_volume(path) ? " --threshold 1" : "") +
                        " -o " + out + " --report " + report);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("meshenc: error: " + path), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(GetParam().message), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(report));
}

INSTANTIATE_TEST_SUITE_P(
    Corpus, BadInputs,
    ::testing::Values(
        // Missing files, one per reader family.
        BadInput{"missing.mesh", "cannot open file"}, BadInput{"missing.vtu", "cannot open file"},
        BadInput{"missing.ply", "cannot open file"}, BadInput{"missing.nrrd", "cannot open file"},
        BadInput{"missing_data_file.nhdr", ": data file: "},
        // Medit
        BadInput{"truncated.mesh", ":4: a vertex count 4 is more than the file can hold"},
        BadInput{"bad_header.mesh", ":1: expected 'MeshVersionFormatted'"},
        BadInput{"count_mismatch.mesh", ":9: expected a coordinate, found 'Tetrahedra'"},
        BadInput{"index_out_of_range.mesh", ":11: vertex index 5 out of range 1..4"},
        BadInput{"nan.mesh", ":6: coordinate is not finite"},
        BadInput{"three_points.mesh", "3 distinct points (of 4); a tetrahedral mesh needs at least 4"},
        BadInput{"coplanar.mesh", "all 5 distinct points are coplanar"},
        // Netgen .vol
        BadInput{"bad_header.vol", ":1: expected 'mesh3d', found 'mesh2d'"},
        BadInput{"wrong_dimension.vol", ":3: a 2D mesh: only 3D (volume) meshes are read"},
        BadInput{"index_out_of_range.vol", ":11: point index 7 out of range 1..5"},
        BadInput{"short_element.vol", ":6: a volume element of 4 points needs as many indices"},
        BadInput{"nan.vol", ":10: coordinate is not a finite number: 'nan'"},
        BadInput{"truncated.vol", ":8: a record count 6 is more than the file can hold"},
        BadInput{"no_endmesh.vol", ":9: file ends without 'endmesh'"},
        // VTK legacy
        BadInput{"bad_header.vtk", ":1: not a VTK legacy file"},
        BadInput{"wrong_dataset.vtk", ":4: only UNSTRUCTURED_GRID datasets are supported"},
        BadInput{"truncated_binary.vtk", ":5: file ends: 12 values of type double need 96 bytes, 70 left"},
        BadInput{"count_mismatch.vtk", "2 CELL_TYPES for 1 CELLS"},
        BadInput{"field_count_mismatch.vtk", ":9: file ends before the 5 values it announces"},
        BadInput{"index_out_of_range.vtk", "cell 0: point index 7 out of range"},
        BadInput{"inf.vtk", ":6: a point coordinate is not finite"},
        BadInput{"coplanar.vtk", "all 5 distinct points are coplanar"},
        // VTU
        BadInput{"bad_root.vtu", ":2: root element is <VTKFiles>"},
        BadInput{"truncated.vtu", ":6: unterminated tag <DataArray>"},
        BadInput{"cut_inside_data.vtu", ":8: file ends inside <DataArray>"},
        BadInput{"not_xml.vtu", ":1: no XML element: not a VTK XML file"},
        BadInput{"truncated_appended.vtu", ": byte 377: a DataArray: 96 bytes announced, 83 left"},
        BadInput{"count_mismatch.vtu", ":6: a DataArray holds 12 values, expected 15"},
        BadInput{"field_count_mismatch.vtu", ":6: DataArray \"pressure\" holds 4 values, expected 5"},
        BadInput{"index_out_of_range.vtu", ":11: cell 0: point index 4 out of range"},
        BadInput{"nan.vtu", ":5: point 3 is not finite"},
        BadInput{"unknown_compressor.vtu", ":2: unknown compressor \"vtkFooCompressor\""},
        BadInput{"corrupt_zlib.vtu", ":6: a DataArray: block 1 of 1: a zlib block is corrupt"},
        BadInput{"huge_block.vtu",
                 ":6: a DataArray: blocks of 1073741824 bytes announced (at most 67108864 are read)"},
        BadInput{"all_equal.vtu", "1 distinct point (of 4)"},
        // gmsh
        BadInput{"bad_version.msh", ":2: unsupported version 3.0"},
        BadInput{"binary_without_byte_order.msh", ": byte 20: the int after the header is not 1"},
        BadInput{"truncated.msh", ":5: a node count 4 is more than the file can hold"},
        BadInput{"count_mismatch.msh", ":5: $Nodes announces 5 nodes, its blocks hold 4"},
        BadInput{"index_out_of_range.msh", ":13: node tag 9 out of range"},
        BadInput{"inf.msh", ":9: coordinate is not finite"},
        // (Read as 4, 1 and 0 until 2026-12-07: a region the file never had.)
        BadInput{"gmsh2_type_not_a_number.msh", ":13: expected an element type, found '4x'"},
        BadInput{"gmsh2_physical_not_a_number.msh", ":13: expected a physical tag, found '1.5'"},
        BadInput{"gmsh2_garbage_not_a_number.msh", ":13: expected a physical tag, found 'x'"},
        // What CGAL's point-set readers passed over (until 2026-12-07: wrong
        // points, values dropped, in silence).
        BadInput{"number_with_suffix.xyz", ":3: expected a number, found '0.5L7'"},
        BadInput{"eight_columns.xyz", ":1: expected 3 numbers (x y z) or 6 (x y z nx ny nz), found 8"},
        BadInput{"two_vertices_a_line.obj", ":3: expected a number, found 'v'"},
        BadInput{"extra_value.ply", ":9: a vertex has 3 properties, this line 4 numbers"},
        BadInput{"more_vertices_than_announced.off",
                 ":8: more lines than the header's 5 vertices and no faces"},
        // PLY, OFF, OBJ, XYZ (CGAL's readers give no position: the message says what they need)
        BadInput{"bad_header.ply", "bad_header.ply:1: not a PLY file"},
        BadInput{"property_before_element.ply",
                 "property_before_element.ply:3: 'property' before any 'element'"},
        BadInput{"integer_coordinates.ply", "integer_coordinates.ply:4: vertex property 'x' is 'int'"},
        BadInput{"huge_count.ply", "huge_count.ply:3: element 'vertex' announces 4000000000 items"},
        BadInput{"truncated_binary.ply", "not a valid PLY file"},
        BadInput{"count_mismatch.ply", "not a valid PLY file"},
        BadInput{"nan.ply", "vertex 2: coordinate is not finite"},
        BadInput{"coplanar.ply", "all 5 distinct points are coplanar"},
        BadInput{"bad_header.off", "not a valid OFF file"},
        BadInput{"truncated.off", "the header announces 4 vertices, the file holds 3"},
        BadInput{"coplanar.off", "all 5 distinct points are coplanar"},
        BadInput{"bad_vertex.obj", "not a valid OBJ file"},
        BadInput{"face_out_of_range.obj", "a face names vertex 7 of 4"},
        BadInput{"three_points.obj", "3 distinct points (of 3)"},
        BadInput{"garbage.xyz", "not a valid XYZ file"},
        BadInput{"coplanar.xyz", "all 5 distinct points are coplanar"},
        // NRRD
        BadInput{"bad_magic.nrrd", ":1: not a NRRD file"},
        BadInput{"bad_type.nrrd", "unsupported type 'complex'"},
        BadInput{"truncated.nrrd", "truncated: holds 40 bytes of data, the 4x4x4 volume needs 64"},
        BadInput{"damaged_gzip.nrrd", "gzip data is damaged or truncated"},
        BadInput{"empty_selection.nrrd", "--threshold 1 selects no voxel (values range from 0 to 0)"},
        BadInput{"flat_selection.nrrd", "all 9 distinct points are coplanar"},
        // TetGen, through the same entry point
        BadInput{"count_too_low.vol", ":10: '1' where a section keyword should be"},
        BadInput{"gmsh_v1.msh", ":1: gmsh's format 1.0 ($NOD), which is not read"},
        BadInput{"fluent.msh", ":1: not a gmsh file: a Fluent or ANSYS mesh"},
        BadInput{"order3.msh", "20-node tetrahedra: volume elements of order 3 or more are not read"},
        BadInput{"truncated.node", "file ends after 2 of 4 points"}, BadInput{"coplanar.node", "coplanar"},
        BadInput{"three_points.node", "at least 4"}),
    [](const auto& info) {
      std::string n = info.param.file;
      for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

}  // namespace
}  // namespace dtm

namespace dtm {
namespace {

// The prefixes of a small valid file in each of our own readers' formats are
// either still a valid file or rejected with a FormatError: never a crash,
// a hang or another exception.
TEST(TruncatedInputs, EveryPrefixIsRejectedCleanlyOrStillValid) {
  OutputMesh m;
  m.grid.step = 0.25;
  m.grid.origin = {1, 2, 3};
  m.points = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {4, 4, 4}};
  m.cells = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.level = {0, 1, 1, 0, 2};
  m.boundary = {1, 1, 1, 1, 0};
  const std::string dir = ::testing::TempDir();
  for (const auto& [format, name] :
       {std::pair{MeshFormat::kVtk, "t.vtk"}, std::pair{MeshFormat::kVtkAscii, "t_ascii.vtk"},
        std::pair{MeshFormat::kVtu, "t.vtu"}, std::pair{MeshFormat::kVtuAscii, "t_ascii.vtu"},
        std::pair{MeshFormat::kMedit, "t.mesh"}, std::pair{MeshFormat::kGmsh, "t.msh"}}) {
    const std::string bytes = render_mesh(m, format, name).front().second;
    const std::string path = dir + "/prefix_" + name;
    size_t accepted = 0;
    // Every cut in the headers, then every third one (each cut is a file write).
    for (size_t n = 0; n < bytes.size(); n += n < 256 ? 1 : 3) {
      std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, n);
      try {
        const InputMesh back = read_input(path);
        ++accepted;
        EXPECT_EQ(back.points.size(), m.points.size()) << name << " cut at " << n;
      } catch (const FormatError& e) {
        ASSERT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
      }
    }
    EXPECT_LT(accepted, 8u) << name << ": only a cut in the final whitespace may still be valid";
  }
}

}  // namespace
}  // namespace dtm
