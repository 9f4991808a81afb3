// Abaqus and CalculiX input files (.inp): what the reader takes from a model
// (nodes, solids, regions, tagged faces, node sets), what it names as left
// out, what it refuses, and the writer's files read back to the same mesh.
// (tests/mesher_outputs.sh reads gmsh's and meshio's .inp files, and gives
// meshdec's to meshio.)

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "format_test_support.h"
#include "output_mesh_support.h"
#include "tools/formats/abaqus.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"

namespace dtm {
namespace {

std::string inp_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string inp_error(const std::string& name, const std::string& text) {
  try {
    read_input(inp_file(name, text));
  } catch (const FormatError& e) {
    return e.what();
  }
  return "no error";
}

bool names(const InputMesh& m, const std::string& what) {
  return std::any_of(m.left_out.begin(), m.left_out.end(),
                     [&](const std::string& l) { return l.find(what) != std::string::npos; });
}

std::set<std::array<uint32_t, 3>> sorted_faces(const std::vector<std::array<uint32_t, 3>>& faces) {
  std::set<std::array<uint32_t, 3>> out;
  for (auto f : faces) {
    std::sort(f.begin(), f.end());
    out.insert(f);
  }
  return out;
}

// A CalculiX model: a 10-node tetrahedron (its record over two lines),
// a linear one, a hexahedron, a 3-node shell in a set; the nodes partly
// from an included file; sets by number, by GENERATE and by name; two
// solid sections; surfaces on a face of a set's elements and of one
// element; the model's material and step. Keywords in either case, with or without
// their blanks.
const char* kModel = R"(** a model as CalculiX reads it
*HEADING
 test model
*INCLUDE, INPUT=abaqus_nodes.inp
*Node, nset=Top
5, 1, 1, 1
6, 2, 0, 0
7, 2, 1, 0
8, 2., 0, 1
9, 2, 1, 1
*NODE
21, 0.5, 0, 0
22, 0.5, 0.5, 0
23, 0, 0.5, 0
24, 0, 0, 0.5
25, 0.5, 0, 0.5
26, 0, 0.5, 0.5
*ELEMENT, TYPE=C3D10, ELSET=Quadratic
1, 1, 2, 3, 4, 21, 22, 23, 24,
 25, 26
*element, type=C3D4
2, 2, 3, 4, 5
*ELEMENT, TYPE=C3D8R, ELSET=Brick
3, 2, 6, 7, 3, 4, 8, 9, 5
*ELEMENT, TYPE=S3, ELSET=Shell
4, 6, 7, 9
*ELSET, ELSET=Tets, GENERATE
1, 2
*ELSET, ELSET=Eall
Tets, Brick
*NSET, NSET=Fixed
1, 3
*SURFACE, NAME=Load, TYPE=ELEMENT
Brick, S2
*Surface, name="Bottom"
1, S1
*MATERIAL, NAME=Steel
*ELASTIC
210000, 0.3
*SOLID SECTION, ELSET=Tets, MATERIAL=Steel
*SolidSection, elset=Brick, material=Steel
*STEP
*STATIC
*BOUNDARY
Fixed, 1, 3
*END STEP
)";

TEST(Abaqus, ReadsACalculixModel) {
  inp_file("abaqus_nodes.inp", "*NODE, NSET=Fixed\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n");
  const InputMesh m = read_input(inp_file("abaqus_model.inp", kModel));
  // The points in file order, the included file's first, the edge nodes
  // set aside.
  ASSERT_EQ(m.points.size(), 9u);
  EXPECT_EQ(m.points[7].x, 2);
  EXPECT_EQ(m.points[7].z, 1);
  ASSERT_EQ(m.edge_points.size(), 6u);
  // The tetrahedra: the quadratic one's corners, the linear one, the
  // hexahedron's six.
  ASSERT_EQ(m.tets.size(), 8u);
  EXPECT_EQ(m.tets[0], (std::array<uint32_t, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.tets[1], (std::array<uint32_t, 4>{1, 2, 3, 4}));
  ASSERT_EQ(m.tet_edge_nodes.size(), 8u);
  // (Abaqus's edge nodes (0,1) (1,2) (0,2) (0,3) (1,3) (2,3): nodes 21-26.)
  const std::array<InputPoint, 6> mid = {
      {{0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}}};
  for (size_t k = 0; k < 6; ++k) {
    const InputPoint p = m.edge_points.at(m.tet_edge_nodes[0][k]);
    EXPECT_TRUE(p.x == mid[k].x && p.y == mid[k].y && p.z == mid[k].z) << k;
  }
  // The regions: the solid sections' sets, in their order.
  EXPECT_EQ(m.region_source, "solid sections' element sets");
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 1, 2, 2, 2, 2, 2, 2}));
  EXPECT_EQ(m.region_names, (std::map<int32_t, std::string>{{1, "Tets"}, {2, "Brick"}}));
  // The tagged faces: the hexahedron's S2 (4-8-9-5 as two triangles), the
  // tetrahedron's S1 (1-2-3), the shell's triangle (its set's tag).
  std::map<std::array<uint32_t, 3>, int32_t> tags;
  for (size_t i = 0; i < m.tagged_faces.size(); ++i) {
    auto f = m.tagged_faces[i];
    std::sort(f.begin(), f.end());
    tags[f] = m.face_tags[i];
  }
  EXPECT_EQ(tags, (std::map<std::array<uint32_t, 3>, int32_t>{
                      {{3, 4, 8}, 1}, {{3, 7, 8}, 1}, {{0, 1, 2}, 2}, {{5, 6, 8}, 3}}));
  EXPECT_EQ(m.face_tag_names, (std::map<int32_t, std::string>{{1, "Load"}, {2, "Bottom"}, {3, "Shell"}}));
  // The node sets as 0/1 fields, in order.
  ASSERT_EQ(m.fields.size(), 2u);
  EXPECT_EQ(m.fields[0].name, "nset:Fixed");
  EXPECT_EQ(m.fields[0].type, ScalarType::kUInt8);
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{1, 1, 1, 1, 0, 0, 0, 0, 0}));
  EXPECT_EQ(m.fields[1].name, "nset:Top");
  EXPECT_EQ(m.fields[1].values, (std::vector<double>{0, 0, 0, 0, 1, 1, 1, 1, 1}));
  EXPECT_EQ(m.fields[1].edge_values, std::vector<double>(6, 0.0));
  // Named: the sets not kept, the materials, the model's other keywords.
  EXPECT_TRUE(names(m, "element sets Quadratic, Eall")) << m.left_out.at(0);
  EXPECT_TRUE(names(m, "the solid sections' materials (Tets: Steel, Brick: Steel)"));
  EXPECT_TRUE(names(m, "keywords *BOUNDARY, *ELASTIC, *END STEP, *MATERIAL, *STATIC, *STEP"));
  EXPECT_TRUE(names(m, "the shapes of its 1 hexahedra"));
}

// Without sections: the *ELSET groups before the *ELEMENT lines' sets (gmsh
// writes both, the same elements twice), a set of every element not a
// region when others are; the 2D elements' sets the face tags.
TEST(Abaqus, ElementSetsAsGmshAndMeshioWriteThem) {
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n5, 1, 1, 1\n";
  const InputMesh gmsh = read_input(inp_file(
      "abaqus_gmsh.inp", "*Heading\n x.inp\n" + nodes +
                             "******* E L E M E N T S *************\n"
                             "*ELEMENT, type=CPS3, ELSET=Surface5\n1, 1, 2, 3\n"
                             "*ELEMENT, type=C3D4, ELSET=Volume1\n2, 1, 2, 3, 4\n"
                             "*ELEMENT, type=C3D4, ELSET=Volume2\n3, 2, 3, 4, 5\n"
                             "*ELSET,ELSET=base\n1, \n*ELSET,ELSET=steel\n2, \n*ELSET,ELSET=aluminium\n3, \n"
                             "*ELSET,ELSET=EALL\n2, 3, \n"));
  EXPECT_EQ(gmsh.region_source, "element sets");
  EXPECT_EQ(gmsh.tet_regions, (std::vector<int32_t>{1, 2}));
  EXPECT_EQ(gmsh.region_names, (std::map<int32_t, std::string>{{1, "steel"}, {2, "aluminium"}}));
  EXPECT_EQ(gmsh.face_tags, std::vector<int32_t>{1});
  EXPECT_EQ(gmsh.face_tag_names, (std::map<int32_t, std::string>{{1, "base"}}));
  EXPECT_TRUE(names(gmsh, "element sets Surface5, Volume1, Volume2, EALL"));
  // One set of every tetrahedron, and a 2D element in no set: the one
  // region; the face tagged 0.
  const InputMesh one = read_input(
      inp_file("abaqus_one.inp", nodes + "*ELEMENT, TYPE=C3D4, ELSET=PART1\n1, 1, 2, 3, 4\n2, 2, 3, 4, 5\n"
                                         "*ELEMENT, TYPE=STRI3\n3, 1, 2, 3\n"));
  EXPECT_EQ(one.tet_regions, (std::vector<int32_t>{1, 1}));
  EXPECT_EQ(one.region_names, (std::map<int32_t, std::string>{{1, "PART1"}}));
  EXPECT_EQ(one.face_tags, std::vector<int32_t>{0});
  EXPECT_TRUE(one.left_out.empty()) << one.left_out.at(0);
  // Other elements are named; a file without sets has no regions.
  const InputMesh plain = read_input(
      inp_file("abaqus_plain.inp",
               nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=T3D2\n2, 1, 2\n3, 2, 3\n"));
  EXPECT_TRUE(plain.tet_regions.empty());
  EXPECT_TRUE(names(plain, "elements other than solids and 2D elements (2 T3D2)"));
}

// An Abaqus/CAE file: the mesh in a *PART, the assembly's instance of it
// unmoved, the assembly's reference point (numbered as the part's first
// node) and its sets: an instance's set kept apart from the part's of the
// same name, the reference point's named as left out. A set a surface
// names, or one Abaqus/CAE made for itself, is no region.
TEST(Abaqus, ReadsAnAbaqusCaeFile) {
  const InputMesh m = read_input(inp_file("abaqus_cae.inp", R"(*Heading
** Job name: Job-1 Model name: Model-1
*Part, name=Part-1
*Node
      1,           0.,           0.,           0.
      2,           1.,           0.,           0.
      3,           0.,           1.,           0.
      4,           0.,           0.,           1.
      5,           1.,           1.,           1.
*Element, type=C3D4
1, 1, 2, 3, 4
2, 2, 3, 4, 5
*Nset, nset=Set-1, generate
 1,  5,  1
*Elset, elset=Set-1, generate
 1,  2,  1
*Elset, elset=_Surf-1_S1, internal
 1,
*Surface, type=ELEMENT, name=Surf-1
_Surf-1_S1, S1
** Section: Section-1
*Solid Section, elset=Set-1, material=Material-1
,
*End Part
*Assembly, name=Assembly
*Instance, name=Part-1-1, part=Part-1
*End Instance
*Node
      1,           2.,           2.,           2.
*Nset, nset=Set-1, instance=Part-1-1
 5,
*Nset, nset=RP
 1,
*End Assembly
*Material, name=Material-1
*Elastic
210000., 0.3
)"));
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 1}));
  EXPECT_EQ(m.region_names, (std::map<int32_t, std::string>{{1, "Set-1"}}));
  EXPECT_EQ(m.face_tag_names, (std::map<int32_t, std::string>{{1, "Surf-1"}}));
  ASSERT_EQ(m.fields.size(), 2u);
  EXPECT_EQ(m.fields[0].name, "nset:Set-1");
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{1, 1, 1, 1, 1}));
  EXPECT_EQ(m.fields[1].name, "nset:assembly.Set-1");
  EXPECT_EQ(m.fields[1].values, (std::vector<double>{0, 0, 0, 0, 1}));
  EXPECT_TRUE(names(m, "1 nodes of the assembly (its reference points)"));
  EXPECT_TRUE(names(m, "the assembly's sets of its own nodes and elements (RP)"));
  EXPECT_TRUE(names(m, "the solid sections' materials (Set-1: Material-1)"));
}

// Forms real files use: a keyword line continued, numbers in Fortran's
// notation, nodes with normals, quoted set names, GENERATE over numbers
// not all defined, a node set of an element set's nodes, a surface named
// twice in two cases, a shell's side, a surface line without a face.
TEST(Abaqus, ReadsTheLessCommonForms) {
  std::string includes;
  for (int i = 0; i < 20; ++i) {
    inp_file("abaqus_piece" + std::to_string(i) + ".inp", "** piece " + std::to_string(i) + "\n");
    includes += "*INCLUDE, INPUT=abaqus_piece" + std::to_string(i) + ".inp\n";
  }
  const InputMesh m = read_input(inp_file("abaqus_forms.inp", includes + R"(*NODE,
 NSET=All
1, 0.0D0, 0, 0, 0, 0, 1
2, 1.0d0, 0, 0
3, 0, 1, 0
4, 0, 0, 1
5, 1, 1, 1
7, 1, 1, 0
*ELEMENT, TYPE=C3D4, ELSET="Solid one"
1, 1, 2, 3, 4
2, 2, 3, 4, 5
*ELEMENT, TYPE=S3R, ELSET=Skin
3, 2, 3, 7
*NSET, NSET=Odd, GENERATE
1, 1000000000000000, 2
*NSET, NSET=OfSkin, ELSET=Skin
*SURFACE, NAME=Top
2, S3
*SURFACE, NAME=TOP
Skin, SPOS
"Solid one"
)"));
  ASSERT_EQ(m.points.size(), 6u);
  EXPECT_EQ(m.points[1].x, 1.0);
  ASSERT_EQ(m.fields.size(), 3u);
  EXPECT_EQ(m.fields[0].name, "nset:All");
  EXPECT_EQ(m.fields[1].values, (std::vector<double>{1, 0, 1, 0, 1, 1}));  // 1, 3, 5, 7
  EXPECT_EQ(m.fields[2].values, (std::vector<double>{0, 1, 1, 0, 0, 1}));  // 2, 3, 7
  // One surface of two faces; the shell's set no region, its triangle the
  // surface's.
  EXPECT_EQ(m.face_tag_names, (std::map<int32_t, std::string>{{1, "Top"}}));
  EXPECT_EQ(m.face_tags, (std::vector<int32_t>{1, 1}));
  EXPECT_EQ(m.region_names, (std::map<int32_t, std::string>{{1, "Solid one"}}));
  EXPECT_TRUE(names(m, "surface Top: 1 lines without a solid's face S1..S6"));
  EXPECT_TRUE(names(m, "the normals of 1 nodes"));
}

// What a small file must not make the reader do: count past 2^63, hold a
// range's every number, read a device, nest includes without end.
TEST(Abaqus, HostileFilesEndCleanly) {
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n";
  // (Each range's numbers that are nodes: 1 and 1 + 2^62; none; 1; all.)
  for (const auto& [range, want] : std::vector<std::pair<std::string, std::vector<double>>>{
           {"1, 9223372036854775807, 4611686018427387904", {1, 0, 0, 0}},
           {"9223372036854775800, 9223372036854775807, 5", {0, 0, 0, 0}},
           {"1, 10, 9223372036854775807", {1, 0, 0, 0}},
           {"-9223372036854775807, 9223372036854775807, 1", {1, 1, 1, 1}}}) {
    SCOPED_TRACE(range);
    const InputMesh m =
        read_input(inp_file("abaqus_range.inp", nodes + "*NSET, NSET=A, GENERATE\n" + range + "\n"));
    ASSERT_EQ(m.fields.size(), 1u);
    EXPECT_EQ(m.fields[0].values, want);
  }
  EXPECT_NE(inp_error("abaqus_dev.inp", "*INCLUDE, INPUT=/dev/zero\n").find("not a file that can be read"),
            std::string::npos);
  EXPECT_NE(inp_error("abaqus_dir.inp", "*INCLUDE, INPUT=/tmp\n").find("not a file that can be read"),
            std::string::npos);
  const std::string long_path =
      inp_error("abaqus_long.inp", "*INCLUDE, INPUT=" + std::string(5000, 'x') + "\n");
  EXPECT_NE(long_path.find("not a file that can be read"), std::string::npos);
  EXPECT_LT(long_path.size(), 300u);  // (the path shortened)
  EXPECT_NE(inp_error("abaqus_gen.inp", nodes + "*NGEN, NSET=X\n1, 4, 1\n").find("*NGEN makes nodes"),
            std::string::npos);
  EXPECT_NE(inp_error("abaqus_sys.inp", "*NODE, SYSTEM=C\n1, 1, 0, 0\n").find("rectangular coordinates only"),
            std::string::npos);
  // A chain of sets, each naming the one before.
  std::string chain = nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*ELSET, ELSET=S0\n1\n";
  for (int i = 1; i < 3000; ++i)
    chain += "*ELSET, ELSET=S" + std::to_string(i) + "\nS" + std::to_string(i - 1) + "\n";
  EXPECT_EQ(read_input(inp_file("abaqus_chain.inp", chain)).region_names,
            (std::map<int32_t, std::string>{{1, "S0"}}));
  // More node sets than a stream has fields: the first 32 kept.
  std::string many = nodes;
  for (int i = 0; i < 40; ++i) many += "*NSET, NSET=N" + std::to_string(i) + "\n1\n";
  const InputMesh kept = read_input(inp_file("abaqus_many.inp", many));
  EXPECT_EQ(kept.fields.size(), 32u);
  EXPECT_TRUE(names(kept, "node sets N32, N33"));
}

TEST(Abaqus, BadFilesAreRefusedNamingTheLine) {
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n";
  const auto error = [&](const std::string& text) { return inp_error("abaqus_bad.inp", text); };
  EXPECT_NE(
      error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 9\n").find("abaqus_bad.inp:7: node 9 is not defined"),
      std::string::npos);
  EXPECT_NE(error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3\n*NODE\n")
                .find(":7: element 1 of type C3D4 needs 4 nodes, found 3"),
            std::string::npos);
  EXPECT_NE(error(nodes + "*ELEMENT, TYPE=C3D10\n1, 1, 2, 3, 4\n").find("needs 10 nodes, found 4"),
            std::string::npos);
  EXPECT_NE(error(nodes + "*ELEMENT\n1, 1, 2, 3, 4\n").find(":6: *ELEMENT without TYPE="), std::string::npos);
  EXPECT_NE(error("*NODE\n1, 0, 0, 0\n1, 1, 0, 0\n").find(":3: node 1 is defined twice"), std::string::npos);
  EXPECT_NE(error("*NODE\n1, 0, x, 0\n").find(":2: expected a coordinate, found 'x'"), std::string::npos);
  EXPECT_NE(error("1, 0, 0, 0\n").find(":1: expected a keyword line"), std::string::npos);
  EXPECT_NE(error("*PART, NAME=A\n*END PART\n*PART, NAME=B\n").find(":3: a second *PART"), std::string::npos);
  EXPECT_NE(error("*PART, NAME=A\n" + nodes + "*END PART\n*ASSEMBLY\n*INSTANCE, NAME=A-1, PART=A\n1, 0, 0\n")
                .find("an *INSTANCE moved or rotated"),
            std::string::npos);
  EXPECT_NE(error("*INCLUDE, INPUT=abaqus_nowhere.inp\n")
                .find(":1: *INCLUDE, INPUT=abaqus_nowhere.inp: not a file that can be read"),
            std::string::npos);
  EXPECT_NE(error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*SURFACE, NAME=S\nNOSET, S1\n")
                .find("*SURFACE S names the element set NOSET"),
            std::string::npos);
  EXPECT_NE(
      error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*SURFACE, NAME=S\n1, S5\n").find("has no face S5"),
      std::string::npos);
  EXPECT_NE(error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*SOLID SECTION, ELSET=X, MATERIAL=M\n")
                .find("names the element set X, which the file does not define"),
            std::string::npos);
  EXPECT_NE(error(nodes + "*NSET, NSET=A\n7\n").find("node set A names node 7"), std::string::npos);
  EXPECT_NE(error(nodes + "*ELSET, ELSET=A, GENERATE\n5, 1\n").find("GENERATE needs first <= last"),
            std::string::npos);
  // An include of itself ends.
  EXPECT_NE(error("*INCLUDE, INPUT=abaqus_bad.inp\n").find("*INCLUDE nested more than 16 deep"),
            std::string::npos);
  // A deck of no nodes.
  EXPECT_NE(error("*HEADING\nnothing\n").find("no *NODE lines"), std::string::npos);
}

// meshdec's .inp read back: the same points, cells, regions, tagged faces
// and node sets; the other fields named as not written.
TEST(Abaqus, WrittenFilesReadBackToTheSameMesh) {
  OutputMesh m = test::torus_mesh();
  for (size_t c = 0; c < m.cells.size(); ++c) m.region.push_back(c % 3 == 0 ? 1 : 2);
  m.region_names = {{1, "inner part"}, {2, "clamped"}};
  // Every boundary face of the cells, tagged by which way it faces.
  std::map<std::array<uint32_t, 3>, std::pair<std::array<uint32_t, 3>, int>> faces;
  static constexpr std::array<std::array<int, 3>, 4> kOutward = {
      {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}};
  for (const auto& t : m.cells)
    for (const auto& s : kOutward) {
      std::array<uint32_t, 3> f = {t[s[0]], t[s[1]], t[s[2]]}, key = f;
      std::sort(key.begin(), key.end());
      if (faces.erase(key) == 0) faces[key] = {f, 0};
    }
  // And a face between two cells (of two regions: an interface).
  {
    const auto& t = m.cells[0];
    std::array<uint32_t, 3> f = {t[0], t[1], t[2]}, key = f;
    std::sort(key.begin(), key.end());
    faces[key] = {f, 0};
  }
  for (const auto& [key, face] : faces) {
    m.faces.push_back(face.first);
    m.face_tags.push_back(m.grid.to_input(m.points[key[0]]).z > 0 ? 7 : 9);
  }
  m.face_tag_names = {{7, "top"}};
  OutputField nset{"nset:clamped", ScalarType::kUInt8, 1, {}},
      other{"temperature", ScalarType::kFloat64, 1, {}};
  for (size_t i = 0; i < m.points.size(); ++i) nset.bits.push_back(i % 5 == 0), other.bits.push_back(0);
  m.fields = {nset, other};
  const std::string path = test::write(m, MeshFormat::kAbaqus, "out.inp");
  const InputMesh back = read_input(path);
  ASSERT_EQ(back.points.size(), m.points.size());
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint want = m.grid.to_input(m.points[i]);
    ASSERT_TRUE(test::same_double(back.points[i].x, want.x) && test::same_double(back.points[i].y, want.y) &&
                test::same_double(back.points[i].z, want.z))
        << i;
  }
  EXPECT_EQ(back.tets, m.cells);
  EXPECT_EQ(back.tet_regions, m.region);
  // (An element set and a node set may share a name, as in Abaqus.)
  EXPECT_EQ(back.region_names, (std::map<int32_t, std::string>{{1, "inner_part"}, {2, "clamped"}}));
  // The faces come back with their tags.
  ASSERT_EQ(back.tagged_faces.size(), m.faces.size());
  std::map<std::array<uint32_t, 3>, int32_t> want, got;
  for (size_t i = 0; i < m.faces.size(); ++i) want[*sorted_faces({m.faces[i]}).begin()] = m.face_tags[i];
  for (size_t i = 0; i < back.tagged_faces.size(); ++i)
    got[*sorted_faces({back.tagged_faces[i]}).begin()] = back.face_tags[i];
  EXPECT_EQ(got.size(), want.size());
  for (const auto& [f, tag] : want)
    EXPECT_EQ(back.face_tag_names.at(got.at(f)), tag == 7 ? "top" : "FACES_9");
  ASSERT_EQ(back.fields.size(), 1u);
  EXPECT_EQ(back.fields[0].name, "nset:clamped");
  for (size_t i = 0; i < m.points.size(); ++i) EXPECT_EQ(back.fields[0].values[i], i % 5 == 0 ? 1 : 0);
  // What an .inp has no place for is named.
  const auto lost = not_written(m, MeshFormat::kAbaqus);
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_NE(lost[0].find("'temperature'"), std::string::npos);
  EXPECT_EQ(lost[0].find("clamped"), std::string::npos);
  // A name written as another label is said (meshdec prints it).
  EXPECT_EQ(abaqus_renaming(m), std::vector<std::string>{"region 1 \"inner part\" as inner_part"});
  // Two tags of one name (Netgen's several face numbers of one boundary):
  // the second surface told apart, and said.
  OutputMesh twice = m;
  twice.face_tag_names = {{7, "outer"}, {9, "outer"}};
  EXPECT_EQ(abaqus_renaming(twice), (std::vector<std::string>{"region 1 \"inner part\" as inner_part",
                                                              "face tag 9 \"outer\" as outer_2"}));
  const std::string text = render_abaqus(twice);
  EXPECT_NE(text.find("*SURFACE, NAME=outer, TYPE=ELEMENT"), std::string::npos);
  EXPECT_NE(text.find("*SURFACE, NAME=outer_2, TYPE=ELEMENT"), std::string::npos);
}

}  // namespace
}  // namespace dtm
