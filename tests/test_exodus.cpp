// Exodus II files (.e): what the reader takes from a file written through
// libexodusii as Cubit and MOOSE write theirs (blocks, side sets, node
// sets, variables over time steps), what it names as left out, what it
// refuses, and the writer's files read back to the same mesh. (ParaView's
// and meshio's files: tests/mesher_outputs.sh.)

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "mesh/topology.h"
#include "output_mesh_support.h"
#include "tools/formats/exodus.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"

#ifdef DTM_WITH_EXODUS
#include <exodusII.h>
#include <netcdf.h>
#endif

namespace dtm {
namespace {

bool leaves_out(const InputMesh& m, const std::string& what) {
  return std::any_of(m.left_out.begin(), m.left_out.end(),
                     [&](const std::string& l) { return l.find(what) != std::string::npos; });
}

std::string exodus_error(const std::string& path) {
  try {
    read_input(path);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "no error";
}

std::array<uint32_t, 3> corners_sorted(std::array<uint32_t, 3> f) {
  std::sort(f.begin(), f.end());
  return f;
}

#ifdef DTM_WITH_EXODUS

// Writes a file through libexodusii; `body` puts what the test wants.
template <class Body>
std::string exodus_file(const std::string& name, int dimensions, int64_t nodes, int64_t elements,
                        int64_t blocks, int64_t node_sets, int64_t side_sets, const Body& body) {
  const std::string path = ::testing::TempDir() + "/" + name;
  int cpu = 8, io = 8;
  const int id = ex_create(path.c_str(), EX_CLOBBER | EX_LARGE_MODEL, &cpu, &io);
  EXPECT_GE(id, 0);
  ex_set_int64_status(id, EX_ALL_INT64_API);
  EXPECT_EQ(ex_put_init(id, "test", dimensions, nodes, elements, blocks, node_sets, side_sets), 0);
  body(id);
  EXPECT_EQ(ex_close(id), 0);
  return path;
}

void put_names(int id, ex_entity_type type, std::vector<std::string> names) {
  std::vector<char*> p;
  for (auto& n : names) p.push_back(n.data());
  EXPECT_EQ(ex_put_names(id, type, p.data()), 0);
}

// The nodes of a unit tetrahedron and block 1 of one TETRA over nodes 1, 2,
// 3 and `last` (5: a node the file lacks).
void put_one_tetrahedron(int id, int64_t last) {
  const std::vector<double> x = {0, 1, 0, 0}, y = {0, 0, 1, 0}, z = {0, 0, 0, 1};
  EXPECT_EQ(ex_put_coord(id, x.data(), y.data(), z.data()), 0);
  EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 1, "TETRA", 1, 4, 0, 0, 0), 0);
  const std::vector<int64_t> conn = {1, 2, 3, last};
  EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 1, conn.data(), nullptr, nullptr), 0);
}

// A hexahedron (block 10 "core") under a pyramid (block 20 "cap"), a
// triangle shell on a pyramid face (block 3 "skin", whose id a side set
// has too), a beam (block 30); side sets 3 "bottom" (the hexahedron's
// side 5, a quadrilateral) and 4 (the pyramid's side 1); node set 7; nodal
// variables T and v_x, v_y, v_z and element variables stress (everywhere)
// and core_only (on block 10) at two time steps.
std::string hex_and_pyramid() {
  return exodus_file("hex_pyramid.e", 3, 9, 4, 4, 1, 2, [](int id) {
    const std::vector<double> x = {0, 1, 1, 0, 0, 1, 1, 0, 0.5}, y = {0, 0, 1, 1, 0, 0, 1, 1, 0.5},
                              z = {0, 0, 0, 0, 1, 1, 1, 1, 1.5};
    EXPECT_EQ(ex_put_coord(id, x.data(), y.data(), z.data()), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 10, "HEX8", 1, 8, 0, 0, 0), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 20, "PYRAMID", 1, 5, 0, 0, 0), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 3, "TRISHELL3", 1, 3, 0, 0, 0), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 30, "BEAM2", 1, 2, 0, 0, 0), 0);
    const std::vector<int64_t> hex = {1, 2, 3, 4, 5, 6, 7, 8}, pyramid = {5, 6, 7, 8, 9}, shell = {6, 7, 9},
                               beam = {1, 9};
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 10, hex.data(), nullptr, nullptr), 0);
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 20, pyramid.data(), nullptr, nullptr), 0);
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 3, shell.data(), nullptr, nullptr), 0);
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 30, beam.data(), nullptr, nullptr), 0);
    put_names(id, EX_ELEM_BLOCK, {"core", "cap", "skin", "rod"});
    const std::vector<int64_t> bottom_elements = {1}, bottom_sides = {5}, apex_elements = {2},
                               apex_sides = {1};
    EXPECT_EQ(ex_put_set_param(id, EX_SIDE_SET, 3, 1, 0), 0);
    EXPECT_EQ(ex_put_set(id, EX_SIDE_SET, 3, bottom_elements.data(), bottom_sides.data()), 0);
    EXPECT_EQ(ex_put_set_param(id, EX_SIDE_SET, 4, 1, 0), 0);
    EXPECT_EQ(ex_put_set(id, EX_SIDE_SET, 4, apex_elements.data(), apex_sides.data()), 0);
    put_names(id, EX_SIDE_SET, {"bottom", ""});
    const std::vector<int64_t> clamped = {1, 2};
    EXPECT_EQ(ex_put_set_param(id, EX_NODE_SET, 7, 2, 0), 0);
    EXPECT_EQ(ex_put_set(id, EX_NODE_SET, 7, clamped.data(), nullptr), 0);
    EXPECT_EQ(ex_put_variable_param(id, EX_NODAL, 4), 0);
    std::vector<std::string> nodal = {"T", "v_x", "v_y", "v_z"};
    std::vector<char*> p;
    for (auto& n : nodal) p.push_back(n.data());
    EXPECT_EQ(ex_put_variable_names(id, EX_NODAL, 4, p.data()), 0);
    EXPECT_EQ(ex_put_variable_param(id, EX_ELEM_BLOCK, 2), 0);
    std::vector<std::string> element = {"stress", "core_only"};
    p.clear();
    for (auto& n : element) p.push_back(n.data());
    EXPECT_EQ(ex_put_variable_names(id, EX_ELEM_BLOCK, 2, p.data()), 0);
    std::vector<int> truth = {1, 1, 1, 0, 1, 0, 1, 0};  // (blocks 10, 20, 3, 30 by 2 variables)
    EXPECT_EQ(ex_put_truth_table(id, EX_ELEM_BLOCK, 4, 2, truth.data()), 0);
    for (int step = 1; step <= 2; ++step) {
      const double time = 0.5 * step;
      EXPECT_EQ(ex_put_time(id, step, &time), 0);
      for (int v = 1; v <= 4; ++v) {
        std::vector<double> values;
        for (int i = 0; i < 9; ++i) values.push_back(100.0 * step + 10.0 * v + i);
        EXPECT_EQ(ex_put_var(id, step, EX_NODAL, v, 1, 9, values.data()), 0);
      }
      const double core = 1000.0 * step, cap = 2000.0 * step, skin = 3, only = 4;
      EXPECT_EQ(ex_put_var(id, step, EX_ELEM_BLOCK, 1, 10, 1, &core), 0);
      EXPECT_EQ(ex_put_var(id, step, EX_ELEM_BLOCK, 1, 20, 1, &cap), 0);
      EXPECT_EQ(ex_put_var(id, step, EX_ELEM_BLOCK, 1, 3, 1, &skin), 0);
      EXPECT_EQ(ex_put_var(id, step, EX_ELEM_BLOCK, 2, 10, 1, &only), 0);
    }
  });
}

TEST(Exodus, ReadsBlocksSideSetsNodeSetsAndTheLastTimeStep) {
  const InputMesh m = read_input(hex_and_pyramid());
  ASSERT_EQ(m.points.size(), 9u);
  EXPECT_EQ(m.points[8].z, 1.5);
  // The hexahedron's 6 tetrahedra in block 10, the pyramid's 2 in block 20.
  ASSERT_EQ(m.tets.size(), 8u);
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{10, 10, 10, 10, 10, 10, 20, 20}));
  EXPECT_EQ(m.region_names, (std::map<int32_t, std::string>{{10, "core"}, {20, "cap"}}));
  EXPECT_EQ(m.region_source, "element blocks");
  // Side set 3: the hexahedron's bottom (nodes 1 4 3 2) as two triangles;
  // side set 4: the pyramid's side 1 (nodes 5 6 9); the shell block, its
  // id 3 a side set's, moved past the side sets' ids to 7.
  std::map<std::array<uint32_t, 3>, int32_t> faces;
  for (size_t i = 0; i < m.tagged_faces.size(); ++i)
    faces[corners_sorted(m.tagged_faces[i])] = m.face_tags[i];
  EXPECT_EQ(faces, (std::map<std::array<uint32_t, 3>, int32_t>{
                       {{0, 1, 2}, 3}, {{0, 2, 3}, 3}, {{4, 5, 8}, 4}, {{5, 6, 8}, 7}}));
  EXPECT_EQ(m.face_tag_names, (std::map<int32_t, std::string>{{3, "bottom"}, {7, "skin"}}));
  // The last time step's values; v as one vector.
  ASSERT_EQ(m.fields.size(), 3u);
  EXPECT_EQ(m.fields[0].name, "T");
  EXPECT_EQ(m.fields[0].values[4], 214.0);
  EXPECT_EQ(m.fields[1].name, "v");
  ASSERT_EQ(m.fields[1].components, 3);
  EXPECT_EQ(m.fields[1].values[3 * 4 + 2], 244.0);  // v_z at node 5
  EXPECT_EQ(m.fields[1].type, ScalarType::kFloat64);
  EXPECT_EQ(m.fields[2].name, "nset:7");
  EXPECT_EQ(m.fields[2].values, (std::vector<double>{1, 1, 0, 0, 0, 0, 0, 0, 0}));
  ASSERT_EQ(m.cell_fields.size(), 1u);
  EXPECT_EQ(m.cell_fields[0].name, "stress");
  EXPECT_EQ(m.cell_fields[0].values, (std::vector<double>{2000, 2000, 2000, 2000, 2000, 2000, 4000, 4000}));
  // What is not kept is named.
  EXPECT_TRUE(leaves_out(m, "element block 30 'rod' (1 BEAM2)"));
  EXPECT_TRUE(leaves_out(m, "the variables at its 1 other time steps (time step 2 of 2, time 1, is read"));
  EXPECT_TRUE(leaves_out(m, "'core_only'"));
  EXPECT_TRUE(leaves_out(m, "'stress' on the face blocks"));
  EXPECT_TRUE(leaves_out(m, "1 pyramids, 1 hexahedra"));
  EXPECT_TRUE(leaves_out(m, "moved by 4"));
}

// --time-step: the first step's values instead; a step the file lacks
// refused.
TEST(Exodus, ReadsTheTimeStepAsked) {
  const std::string path = hex_and_pyramid();
  const InputMesh m = read_input(path, {}, {}, true, {}, 1);
  ASSERT_EQ(m.fields.size(), 3u);
  EXPECT_EQ(m.fields[0].values[4], 114.0);
  EXPECT_EQ(m.cell_fields[0].values[0], 1000.0);
  EXPECT_TRUE(leaves_out(m, "(time step 1 of 2, time 0.5, is read"));
  try {
    read_input(path, {}, {}, true, {}, 3);
    ADD_FAILURE() << "time step 3 of 2 read";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("hex_pyramid.e: time step 3 asked, the file has 2"),
              std::string::npos)
        << e.what();
  }
}

TEST(Exodus, KeepsATenNodeTetrahedronsEdgeNodes) {
  // Corners, then the nodes of the edges 1-2, 2-3, 1-3, 1-4, 2-4, 3-4 (Exodus's order).
  const std::string path = exodus_file("tet10.e", 3, 10, 1, 1, 0, 0, [](int id) {
    const std::vector<double> x = {0, 2, 0, 0, 1, 1, 0, 0, 1, 0}, y = {0, 0, 2, 0, 0, 1, 1, 0, 0, 1},
                              z = {0, 0, 0, 2, 0, 0, 0, 1, 1, 1};
    EXPECT_EQ(ex_put_coord(id, x.data(), y.data(), z.data()), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 1, "TETRA10", 1, 10, 0, 0, 0), 0);
    const std::vector<int64_t> conn = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 1, conn.data(), nullptr, nullptr), 0);
  });
  const InputMesh m = read_input(path);
  ASSERT_EQ(m.points.size(), 4u);
  ASSERT_EQ(m.edge_points.size(), 6u);
  ASSERT_EQ(m.tet_edge_nodes.size(), 1u);
  for (size_t e = 0; e < 6; ++e) {
    // Each edge's node at its midpoint.
    const auto [a, b] =
        std::array<std::array<int, 2>, 6>{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}}[e];
    const InputPoint& p = m.edge_points[m.tet_edge_nodes[0][e]];
    const InputPoint& pa = m.points[m.tets[0][static_cast<size_t>(a)]];
    const InputPoint& pb = m.points[m.tets[0][static_cast<size_t>(b)]];
    EXPECT_EQ(p.x, 0.5 * (pa.x + pb.x)) << e;
    EXPECT_EQ(p.y, 0.5 * (pa.y + pb.y)) << e;
    EXPECT_EQ(p.z, 0.5 * (pa.z + pb.z)) << e;
  }
}

TEST(Exodus, BadFilesAreRefusedNamingTheFile) {
  const std::string text = ::testing::TempDir() + "/text.e";
  std::ofstream(text) << "not netCDF\n";
  EXPECT_NE(exodus_error(text).find("text.e: not an Exodus II file"), std::string::npos)
      << exodus_error(text);
  const std::string flat = exodus_file("flat.e", 2, 3, 1, 1, 0, 0, [](int id) {
    const std::vector<double> x = {0, 1, 0}, y = {0, 0, 1};
    EXPECT_EQ(ex_put_coord(id, x.data(), y.data(), nullptr), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 1, "TRI3", 1, 3, 0, 0, 0), 0);
    const std::vector<int64_t> conn = {1, 2, 3};
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 1, conn.data(), nullptr, nullptr), 0);
  });
  EXPECT_NE(exodus_error(flat).find("flat.e: a 2D mesh"), std::string::npos) << exodus_error(flat);
  const std::string beyond = exodus_file("beyond.e", 3, 4, 1, 1, 0, 1, [](int id) {
    put_one_tetrahedron(id, 5);
    const std::vector<int64_t> elements = {2}, sides = {1};
    EXPECT_EQ(ex_put_set_param(id, EX_SIDE_SET, 1, 1, 0), 0);
    EXPECT_EQ(ex_put_set(id, EX_SIDE_SET, 1, elements.data(), sides.data()), 0);
  });
  EXPECT_NE(exodus_error(beyond).find("beyond.e: element block 1: element 1 names node 5 of 4"),
            std::string::npos)
      << exodus_error(beyond);
  // An element type longer than libexodusii 6.02's buffer for it (33
  // bytes), which it would overrun.
  // (libexodusii itself writes no such file: netCDF's calls do.)
  const std::string long_type =
      exodus_file("long_type.e", 3, 4, 1, 1, 0, 0, [](int id) { put_one_tetrahedron(id, 4); });
  {
    int nc = -1, connect = -1;
    ASSERT_EQ(nc_open(long_type.c_str(), NC_WRITE, &nc), NC_NOERR);
    ASSERT_EQ(nc_inq_varid(nc, "connect1", &connect), NC_NOERR);
    ASSERT_EQ(nc_redef(nc), NC_NOERR);
    const std::string type = "TETRA_OF_A_NAME_LONGER_THAN_THIRTY_TWO";
    ASSERT_EQ(nc_put_att_text(nc, connect, "elem_type", type.size() + 1, type.c_str()), NC_NOERR);
    ASSERT_EQ(nc_close(nc), NC_NOERR);
  }
  EXPECT_NE(exodus_error(long_type).find("long_type.e: its attribute 'elem_type' holds 39 values"),
            std::string::npos)
      << exodus_error(long_type);
  // 33 bytes without their end: 6.02's strcpy() of them would run on.
  {
    int nc = -1, connect = -1;
    ASSERT_EQ(nc_open(long_type.c_str(), NC_WRITE, &nc), NC_NOERR);
    ASSERT_EQ(nc_inq_varid(nc, "connect1", &connect), NC_NOERR);
    ASSERT_EQ(nc_redef(nc), NC_NOERR);
    ASSERT_EQ(nc_put_att_text(nc, connect, "elem_type", 33, "TETRA____________________________X"), NC_NOERR);
    ASSERT_EQ(nc_close(nc), NC_NOERR);
  }
  EXPECT_NE(
      exodus_error(long_type).find("long_type.e: its attribute 'elem_type' fills 33 bytes without its end"),
      std::string::npos)
      << exodus_error(long_type);
}

// libnetcdf allocates what a classic header claims: the reader looks first.
TEST(Exodus, HeadersThatClaimMoreThanTheFileAreRefused) {
  const std::string path = test::write(test::torus_mesh(), MeshFormat::kExodus, "torus.e");
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ASSERT_EQ(bytes.substr(0, 4), std::string("CDF\x02", 4));
  const auto written = [](const std::string& name, const std::string& b) {
    const std::string p = ::testing::TempDir() + "/" + name;
    std::ofstream(p, std::ios::binary) << b;
    return p;
  };
  // The first dimension's name (after magic, numrecs, the list's tag and
  // count) two gigabytes long.
  std::string long_name = bytes;
  long_name[16] = '\x7f';
  EXPECT_NE(exodus_error(written("long_name.e", long_name))
                .find("long_name.e: byte 20: a name of 2130706442 bytes, more than netCDF's 256"),
            std::string::npos)
      << exodus_error(written("long_name.e", long_name));
  // A name within netCDF's 256 bytes but past the end of a file cut short.
  std::string past = bytes.substr(0, 100);
  past[16] = 0, past[17] = 0, past[18] = 0, past[19] = static_cast<char>(250);
  EXPECT_NE(
      exodus_error(written("past.e", past))
          .find(
              "past.e: byte 20: a name: 250 claimed (a netCDF header that claims more than the file holds)"),
      std::string::npos)
      << exodus_error(written("past.e", past));
  // Cut inside the header.
  EXPECT_NE(exodus_error(written("cut.e", bytes.substr(0, 200))).find("claims more than the file holds"),
            std::string::npos)
      << exodus_error(written("cut.e", bytes.substr(0, 200)));
  // Cut after it, inside the data: libexodusii's error, naming the file.
  const std::string data_cut = exodus_error(written("data_cut.e", bytes.substr(0, bytes.size() - 100)));
  EXPECT_EQ(data_cut.find(::testing::TempDir() + "/data_cut.e: "), 0u) << data_cut;
}

// What libexodusii 6.02 reads whole into buffers sized by the dimensions:
// a variable shaped otherwise is refused (here a block's connectivity over
// more elements than the block has).
TEST(Exodus, VariablesNotShapedAsExodusAreRefused) {
  const std::string path =
      exodus_file("reshaped.e", 3, 4, 1, 1, 0, 0, [](int id) { put_one_tetrahedron(id, 4); });
  int nc = -1, old = -1, big = -1, per = -1, connect = -1;
  ASSERT_EQ(nc_open(path.c_str(), NC_WRITE, &nc), NC_NOERR);
  ASSERT_EQ(nc_redef(nc), NC_NOERR);
  ASSERT_EQ(nc_inq_varid(nc, "connect1", &old), NC_NOERR);
  ASSERT_EQ(nc_rename_var(nc, old, "connect_old"), NC_NOERR);
  ASSERT_EQ(nc_def_dim(nc, "many", 1000, &big), NC_NOERR);
  ASSERT_EQ(nc_inq_dimid(nc, "num_nod_per_el1", &per), NC_NOERR);
  const int dims[2] = {big, per};
  ASSERT_EQ(nc_def_var(nc, "connect1", NC_INT, 2, dims, &connect), NC_NOERR);
  ASSERT_EQ(nc_put_att_text(nc, connect, "elem_type", 6, "TETRA"), NC_NOERR);
  ASSERT_EQ(nc_close(nc), NC_NOERR);
  EXPECT_NE(exodus_error(path).find("reshaped.e: its variable 'connect1' is not shaped as Exodus's "
                                    "(num_el_in_blk1, num_nod_per_el1)"),
            std::string::npos)
      << exodus_error(path);
}

// Variables defined, no time step written (a run stopped before its
// first): the mesh is read, the variables named; node sets of one name (a
// named set's id that meshdec's .e will not give it again said) and
// element variables beyond the stream's 32 kept apart or named; a QUAD's
// sides are its edges.
TEST(Exodus, TheStreamsLimitsAndTheLessCommonForms) {
  const std::string path = exodus_file("forms.e", 3, 5, 2, 2, 2, 1, [](int id) {
    const std::vector<double> x = {0, 1, 0, 0, 1}, y = {0, 0, 1, 0, 1}, z = {0, 0, 0, 1, 0};
    EXPECT_EQ(ex_put_coord(id, x.data(), y.data(), z.data()), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 1, "TETRA", 1, 4, 0, 0, 0), 0);
    EXPECT_EQ(ex_put_block(id, EX_ELEM_BLOCK, 2, "QUAD4", 1, 4, 0, 0, 0), 0);
    const std::vector<int64_t> tet = {1, 2, 3, 4}, quad = {1, 2, 5, 3};
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 1, tet.data(), nullptr, nullptr), 0);
    EXPECT_EQ(ex_put_conn(id, EX_ELEM_BLOCK, 2, quad.data(), nullptr, nullptr), 0);
    const std::vector<int64_t> a = {1}, b = {2};
    for (int64_t s : {1, 4}) {
      EXPECT_EQ(ex_put_set_param(id, EX_NODE_SET, s, 1, 0), 0);
      EXPECT_EQ(ex_put_set(id, EX_NODE_SET, s, s == 1 ? a.data() : b.data(), nullptr), 0);
    }
    put_names(id, EX_NODE_SET, {"fixed", "fixed"});
    const std::vector<int64_t> elements = {2}, sides = {2};
    EXPECT_EQ(ex_put_set_param(id, EX_SIDE_SET, 5, 1, 0), 0);
    EXPECT_EQ(ex_put_set(id, EX_SIDE_SET, 5, elements.data(), sides.data()), 0);
    EXPECT_EQ(ex_put_variable_param(id, EX_NODAL, 1), 0);
    std::string t = "T";
    char* names[] = {t.data()};
    EXPECT_EQ(ex_put_variable_names(id, EX_NODAL, 1, names), 0);
  });
  const InputMesh m = read_input(path);
  EXPECT_EQ(m.tets.size(), 1u);
  EXPECT_TRUE(leaves_out(m, "its variables' names (no time step holds values)"));
  EXPECT_TRUE(leaves_out(m, "1 sides of 2D elements that are their edges"));
  ASSERT_EQ(m.fields.size(), 2u);
  EXPECT_EQ(m.fields[0].name, "nset:fixed");
  EXPECT_EQ(m.fields[1].name, "nset:fixed_2");
  // meshdec's .e numbers named sets 1, 2, ...: set 4's id is said.
  EXPECT_TRUE(leaves_out(m, "the ids of node sets 4 'fixed' as 2"));
  EXPECT_FALSE(leaves_out(m, "the ids of node sets 1"));
  // (The quadrilateral itself is a tagged face, by its block's id.)
  EXPECT_EQ(std::set<int32_t>(m.face_tags.begin(), m.face_tags.end()), std::set<int32_t>{2});
}

TEST(Exodus, WrittenFilesReadBackToTheSameMesh) {
  OutputMesh m = test::torus_mesh();
  for (size_t c = 0; c < m.cells.size(); ++c) m.region.push_back(c % 3 == 0 ? 1 : -2);
  m.region_names = {{1, "inner part"}};
  // Every boundary face of the cells, tagged by the side of z = 0 it lies.
  std::map<std::array<uint32_t, 3>, std::array<uint32_t, 3>> faces;
  static constexpr std::array<std::array<int, 3>, 4> kOutward = {
      {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}};
  for (const auto& t : m.cells)
    for (const auto& s : kOutward) {
      const std::array<uint32_t, 3> f = {t[s[0]], t[s[1]], t[s[2]]};
      if (faces.erase(corners_sorted(f)) == 0) faces[corners_sorted(f)] = f;
    }
  for (const auto& [key, face] : faces) {
    m.faces.push_back(face);
    m.face_tags.push_back(m.grid.to_input(m.points[key[0]]).z > 0 ? 7 : 9);
  }
  m.face_tag_names = {{7, "top"}};
  OutputField nset{"nset:clamped", ScalarType::kUInt8, 1, {}},
      velocity{"velocity", ScalarType::kFloat32, 3, {}}, count{"count", ScalarType::kInt32, 1, {}};
  for (size_t i = 0; i < m.points.size(); ++i) {
    nset.bits.push_back(i % 5 == 0);
    for (int c = 0; c < 3; ++c)
      velocity.bits.push_back(std::bit_cast<uint32_t>(0.25f * static_cast<float>(i + c)));
    count.bits.push_back(static_cast<uint32_t>(-static_cast<int32_t>(i)));
  }
  m.fields = {nset, velocity, count};
  OutputField pressure{"pressure", ScalarType::kFloat64, 1, {}};
  for (size_t c = 0; c < m.cells.size(); ++c)
    pressure.bits.push_back(std::bit_cast<uint64_t>(1.0 / (c + 1.0)));
  m.cell_fields = {pressure};
  EXPECT_TRUE(not_written(m, MeshFormat::kExodus).empty());
  EXPECT_EQ(exodus_renumbering(m),
            std::vector<std::string>{"region -2 as element block 2 (Exodus ids are positive)"});
  const InputMesh back = read_input(test::write(m, MeshFormat::kExodus, "out.e"));
  ASSERT_EQ(back.points.size(), m.points.size());
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint want = m.grid.to_input(m.points[i]);
    ASSERT_TRUE(back.points[i].x == want.x && back.points[i].y == want.y && back.points[i].z == want.z) << i;
  }
  // The cells, block by block (region 1 first, then -2, written as block 2:
  // the next id free), each with its region and value.
  ASSERT_EQ(back.tets.size(), m.cells.size());
  std::map<std::array<uint32_t, 4>, std::pair<int32_t, double>> want, got;
  for (size_t c = 0; c < m.cells.size(); ++c)
    want[m.cells[c]] = {m.region[c] == 1 ? 1 : 2, std::bit_cast<double>(pressure.bits[c])};
  ASSERT_EQ(back.cell_fields.size(), 1u);
  for (size_t c = 0; c < back.tets.size(); ++c)
    got[back.tets[c]] = {back.tet_regions[c], back.cell_fields[0].values[c]};
  EXPECT_EQ(got, want);
  EXPECT_EQ(back.region_names, (std::map<int32_t, std::string>{{1, "inner part"}}));
  // The faces come back with their tags.
  std::map<std::array<uint32_t, 3>, int32_t> want_faces, got_faces;
  for (size_t i = 0; i < m.faces.size(); ++i) want_faces[corners_sorted(m.faces[i])] = m.face_tags[i];
  for (size_t i = 0; i < back.tagged_faces.size(); ++i)
    got_faces[corners_sorted(back.tagged_faces[i])] = back.face_tags[i];
  EXPECT_EQ(got_faces, want_faces);
  EXPECT_EQ(back.face_tag_names, (std::map<int32_t, std::string>{{7, "top"}}));
  // meshdec's level and boundary, then the fields (velocity as one vector;
  // every value a double, exactly), then the node set.
  ASSERT_EQ(back.fields.size(), 5u);
  EXPECT_EQ(back.fields[0].name, "level");
  EXPECT_EQ(back.fields[1].name, "boundary");
  EXPECT_EQ(back.fields[2].name, "velocity");
  ASSERT_EQ(back.fields[2].components, 3);
  EXPECT_EQ(back.fields[3].name, "count");
  EXPECT_EQ(back.fields[4].name, "nset:clamped");
  for (size_t i = 0; i < m.points.size(); ++i) {
    EXPECT_EQ(back.fields[0].values[i], m.level[i]);
    EXPECT_EQ(back.fields[2].values[3 * i + 2], 0.25 * static_cast<double>(i + 2));
    EXPECT_EQ(back.fields[3].values[i], -static_cast<double>(i));
    EXPECT_EQ(back.fields[4].values[i], i % 5 == 0 ? 1 : 0);
  }
}

// ParaView's Exodus reader (IOSS) refuses a file where two blocks or sets
// share a name: Netgen names several face numbers "outer", gmsh a volume
// and a surface alike. Each later one is written with "_2", ..., and said.
TEST(Exodus, NamesAreUniqueOverBlocksAndSetsAndTheRenamedAreSaid) {
  OutputMesh m = test::torus_mesh();
  for (size_t c = 0; c < m.cells.size(); ++c) m.region.push_back(c % 2 == 0 ? 1 : 2);
  m.region_names = {{1, "outer"}, {2, "core"}};
  // Every boundary face, tagged 3, 4, 5 in turn.
  int k = 0;
  for (const auto& face : boundary_triangles(m.cells)) {
    m.faces.push_back(face);
    m.face_tags.push_back(3 + k++ % 3);
  }
  m.face_tag_names = {{3, "outer"}, {4, "outer"}, {5, "outer_2"}};
  EXPECT_EQ(
      exodus_renumbering(m),
      (std::vector<std::string>{
          "side set 3's name \"outer\" as \"outer_3\" (a name is unique over an Exodus file's blocks and "
          "sets: ParaView refuses the file otherwise)",
          "side set 4's name \"outer\" as \"outer_4\" (a name is unique over an Exodus file's blocks and "
          "sets: ParaView refuses the file otherwise)"}));
  const InputMesh back = read_input(test::write(m, MeshFormat::kExodus, "names.e"));
  EXPECT_EQ(back.region_names, (std::map<int32_t, std::string>{{1, "outer"}, {2, "core"}}));
  EXPECT_EQ(back.face_tag_names,
            (std::map<int32_t, std::string>{{3, "outer_3"}, {4, "outer_4"}, {5, "outer_2"}}));
}

#else

TEST(Exodus, ABuildWithoutLibexodusiiSaysHowToGetIt) {
  const std::string path = ::testing::TempDir() + "/any.e";
  std::ofstream(path) << "x";
  EXPECT_NE(exodus_error(path).find("apt-get install libexodusii-dev"), std::string::npos)
      << exodus_error(path);
}

#endif

}  // namespace
}  // namespace dtm
