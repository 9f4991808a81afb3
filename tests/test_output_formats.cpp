// meshdec's new outputs: VTK legacy (binary and ASCII), Medit, gmsh 4.1, the
// boundary surface as PLY and OFF, XYZ. Each is read back by our own reader
// (write -> read -> the same vertices and tetrahedra, bit for bit) and by an
// independent one: meshio for every format, VTK itself for .vtk and .vtu.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "format_test_support.h"
#include "mesh/geometry.h"
#include "output_mesh_support.h"
#include "test_support.h"
#include "tools/atomic_file.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"
#include "tools/formats/netgen_vol.h"
#include "tools/formats/surface_writers.h"

namespace dtm {
namespace {

using test::torus_mesh;  // torus_288 with its tetrahedra (output_mesh_support.h)
using test::write;

const VertexField* field(const InputMesh& m, const std::string& name) {
  for (const auto& f : m.fields)
    if (f.name == name) return &f;
  return nullptr;
}

// --- our own readers --------------------------------------------------------

struct VolumeOutput {
  MeshFormat format;
  const char* name;
  bool level;            // writes the level field
  const char* boundary;  // name of the field holding the boundary flag, or ""
};

const VolumeOutput kVolumeOutputs[] = {{MeshFormat::kVtk, "out_binary.vtk", true, "boundary"},
                                       {MeshFormat::kVtkAscii, "out_ascii.vtk", true, "boundary"},
                                       {MeshFormat::kVtu, "out_binary.vtu", true, "boundary"},
                                       {MeshFormat::kVtuAscii, "out_ascii.vtu", true, "boundary"},
                                       {MeshFormat::kMedit, "out.mesh", false, "ref"},
                                       {MeshFormat::kGmsh, "out.msh", true, "boundary"},
                                       {MeshFormat::kTetgen, "out.node", false, "boundary_marker"}};

TEST(OutputFormats, EveryVolumeFormatReadsBackToTheSameMeshBitForBit) {
  const OutputMesh m = torus_mesh();
  for (const VolumeOutput& o : kVolumeOutputs) {
    SCOPED_TRACE(o.name);
    const InputMesh back = read_input(write(m, o.format, o.name));
    ASSERT_EQ(back.points.size(), m.points.size());
    for (size_t i = 0; i < m.points.size(); ++i) {
      const InputPoint want = m.grid.to_input(m.points[i]);
      ASSERT_TRUE(test::same_double(back.points[i].x, want.x) &&
                  test::same_double(back.points[i].y, want.y) && test::same_double(back.points[i].z, want.z))
          << "point " << i;
    }
    EXPECT_EQ(back.tets, m.cells);
    if (o.level) {
      const VertexField* f = field(back, "level");
      ASSERT_NE(f, nullptr);
      EXPECT_EQ(f->values, std::vector<double>(m.level.begin(), m.level.end()));
    }
    const VertexField* b = field(back, o.boundary);
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->values, std::vector<double>(m.boundary.begin(), m.boundary.end()));
  }
}

TEST(OutputFormats, XyzHoldsEveryPoint) {
  const OutputMesh m = torus_mesh();
  const InputMesh back = read_input(write(m, MeshFormat::kXyz, "out.xyz"));
  ASSERT_EQ(back.points.size(), m.points.size());
  for (size_t i = 0; i < m.points.size(); ++i)
    EXPECT_TRUE(test::same_double(back.points[i].x, m.grid.to_input(m.points[i]).x));
}

// --- the boundary surface ----------------------------------------------------

// A closed, consistently oriented surface whose signed volume (divergence
// theorem) is the volume of the tetrahedra: normals point outward.
void expect_closed_and_outward(const OutputMesh& m, const std::vector<InputPoint>& pts,
                               const std::vector<std::array<uint32_t, 3>>& tris) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, n] : directed) {
    ASSERT_EQ(n, 1) << "edge used twice in one direction";
    ASSERT_EQ(directed.count({edge.second, edge.first}), 1u) << "open edge";
  }
  auto det = [](InputPoint a, InputPoint b, InputPoint c, InputPoint d) {
    const double u[3] = {b.x - a.x, b.y - a.y, b.z - a.z}, v[3] = {c.x - a.x, c.y - a.y, c.z - a.z},
                 w[3] = {d.x - a.x, d.y - a.y, d.z - a.z};
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
  };
  double surface = 0, cells = 0;
  const InputPoint o{0, 0, 0};
  for (const auto& t : tris) surface += det(o, pts[t[0]], pts[t[1]], pts[t[2]]);
  for (const auto& c : m.cells)
    cells += det(m.grid.to_input(m.points[c[0]]), m.grid.to_input(m.points[c[1]]),
                 m.grid.to_input(m.points[c[2]]), m.grid.to_input(m.points[c[3]]));
  EXPECT_GT(cells, 0);
  EXPECT_NEAR(surface, cells, 1e-9 * cells);
}

TEST(OutputFormats, BoundarySurfaceIsClosedAndOrientedOutward) {
  const OutputMesh m = torus_mesh();
  const BoundarySurface s = boundary_surface(m);
  // The TetGen torus: 180 surface vertices, a closed genus-1 surface (V - E + F = 0, E = 3F/2).
  EXPECT_EQ(s.vertices.size(), 180u);
  EXPECT_EQ(s.triangles.size(), 360u);
  std::vector<InputPoint> pts;
  for (uint32_t v : s.vertices) pts.push_back(m.grid.to_input(m.points[v]));
  expect_closed_and_outward(m, pts, s.triangles);
}

// --- independent readers -------------------------------------------------------

struct Dump {
  std::vector<InputPoint> points;
  std::string cell_type;
  std::vector<std::vector<uint32_t>> cells;
  std::map<std::string, std::vector<double>> point_data;
};

double to_double(const std::string& token) {
  double v = 0;
  std::from_chars(token.data(), token.data() + token.size(), v);
  return v;
}

// What `reader` (meshio or vtk) reads in `path`, via dump_mesh.py.
Dump independent_read(const std::string& reader, const std::string& path) {
  const auto r =
      test::run_command(test::kPython + " " + DTM_TEST_SOURCE_DIR + "/dump_mesh.py " + reader + " " + path);
  Dump d;
  if (r.status != 0) {
    ADD_FAILURE() << reader << " could not read " << path
                  << " (scripts/setup.sh --all installs python3-meshio and "
                  << "python3-paraview, whose Python has VTK):\n"
                  << r.output.substr(0, 2000);
    return d;
  }
  std::istringstream in(r.output);
  std::string word, s;
  size_t n = 0;
  while (in >> word) {
    if (word == "points") {
      in >> n;
      for (size_t i = 0; i < n; ++i) {
        std::string x, y, z;
        in >> x >> y >> z;
        d.points.push_back({to_double(x), to_double(y), to_double(z)});
      }
    } else if (word == "cells") {
      in >> d.cell_type >> n;
      const size_t per = d.cell_type == "tetra" ? 4 : d.cell_type == "triangle" ? 3 : 1;
      for (size_t i = 0; i < n; ++i) {
        std::vector<uint32_t> c(per);
        for (auto& v : c) in >> v;
        d.cells.push_back(c);
      }
    } else if (word == "pointdata") {
      in >> s >> n;
      auto& values = d.point_data[s];
      for (size_t i = 0; i < n; ++i) {
        std::string v;
        in >> v;
        values.push_back(to_double(v));
      }
    } else if (word == "end") {
      return d;
    }
  }
  ADD_FAILURE() << "incomplete dump of " << path << ":\n" << r.output.substr(0, 2000);
  return d;
}

void expect_same_points(const Dump& d, const std::vector<InputPoint>& want) {
  ASSERT_EQ(d.points.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i)
    ASSERT_TRUE(test::same_double(d.points[i].x, want[i].x) && test::same_double(d.points[i].y, want[i].y) &&
                test::same_double(d.points[i].z, want[i].z))
        << "point " << i;
}

// A Netgen .vol numbers the domains 1 to K and names in one word: what it
// writes otherwise than the stream is said (meshdec prints it).
TEST(OutputFormats, WhatANetgenFileNumbersOrNamesOtherwiseIsSaid) {
  OutputMesh m = test::torus_mesh();
  for (size_t c = 0; c < m.cells.size(); ++c) m.region.push_back(c % 2 == 0 ? 10 : 20);
  m.region_names = {{10, "left part"}, {20, "right"}};
  EXPECT_EQ(
      netgen_renumbering(m),
      (std::vector<std::string>{"region 10 as material 1 (Netgen numbers its domains 1, 2, ...)",
                                "region 20 as material 2 (Netgen numbers its domains 1, 2, ...)",
                                "region 10's name \"left part\" as left_part (a Netgen name is one word)"}));
  m.region = std::vector<int32_t>(m.cells.size(), 1);
  m.region_names = {{1, "all"}};
  EXPECT_TRUE(netgen_renumbering(m).empty());
}

TEST(OutputFormats, VolumeFormatsReadByMeshioAndVtk) {
  const OutputMesh m = torus_mesh();
  std::vector<InputPoint> want;
  for (const GridPoint& g : m.points) want.push_back(m.grid.to_input(g));
  struct Case {
    MeshFormat format;
    const char* name;
    const char* reader;
    bool fields;
  };
  for (const Case& c : {Case{MeshFormat::kVtk, "ind_binary.vtk", "meshio", true},
                        Case{MeshFormat::kVtkAscii, "ind_ascii.vtk", "meshio", true},
                        Case{MeshFormat::kVtk, "ind_binary.vtk", "vtk", true},
                        Case{MeshFormat::kVtkAscii, "ind_ascii.vtk", "vtk", true},
                        Case{MeshFormat::kVtu, "ind_binary.vtu", "vtk", true},
                        Case{MeshFormat::kVtuAscii, "ind_ascii.vtu", "vtk", true},
                        Case{MeshFormat::kMedit, "ind.mesh", "meshio", false},
                        Case{MeshFormat::kGmsh, "ind.msh", "meshio", true}}) {
    SCOPED_TRACE(std::string(c.name) + " read by " + c.reader);
    const Dump d = independent_read(c.reader, write(m, c.format, c.name));
    expect_same_points(d, want);
    EXPECT_EQ(d.cell_type, "tetra");
    ASSERT_EQ(d.cells.size(), m.cells.size());
    for (size_t i = 0; i < m.cells.size(); ++i)
      ASSERT_EQ(d.cells[i], std::vector<uint32_t>(m.cells[i].begin(), m.cells[i].end())) << "cell " << i;
    if (c.fields) {
      EXPECT_EQ(d.point_data.at("level"), std::vector<double>(m.level.begin(), m.level.end()));
      EXPECT_EQ(d.point_data.at("boundary"), std::vector<double>(m.boundary.begin(), m.boundary.end()));
    }
  }
}

TEST(OutputFormats, BoundarySurfaceReadByMeshio) {
  const OutputMesh m = torus_mesh();
  const BoundarySurface s = boundary_surface(m);
  std::vector<InputPoint> want;
  for (uint32_t v : s.vertices) want.push_back(m.grid.to_input(m.points[v]));
  for (const auto& [format, name] :
       {std::pair{MeshFormat::kPly, "surface.ply"}, std::pair{MeshFormat::kOff, "surface.off"}}) {
    SCOPED_TRACE(name);
    const Dump d = independent_read("meshio", write(m, format, name));
    expect_same_points(d, want);
    EXPECT_EQ(d.cell_type, "triangle");
    std::vector<std::array<uint32_t, 3>> tris;
    for (const auto& c : d.cells) tris.push_back({c[0], c[1], c[2]});
    EXPECT_EQ(tris, s.triangles);
    expect_closed_and_outward(m, d.points, tris);
    // And our own (CGAL's) reader: the same vertices (for PLY, its `level`
    // read and left out, named: meshdec's own, which a decoder makes again;
    // the faces named, not read).
    const InputMesh back = read_input(::testing::TempDir() + "/" + name);
    ASSERT_EQ(back.points.size(), want.size());
    for (size_t i = 0; i < want.size(); ++i)
      ASSERT_TRUE(test::same_double(back.points[i].x, want[i].x) &&
                  test::same_double(back.points[i].z, want[i].z));
    const std::string faces = std::to_string(s.triangles.size()) + " faces (";
    if (format == MeshFormat::kPly) {
      EXPECT_EQ(field(back, "level"), nullptr);
      ASSERT_EQ(back.left_out.size(), 2u);
      EXPECT_NE(back.left_out[0].find("'level' (meshdec's own"), std::string::npos) << back.left_out[0];
      EXPECT_EQ(back.left_out[1].rfind(faces, 0), 0u) << back.left_out[1];
    } else {
      ASSERT_EQ(back.left_out.size(), 1u);
      EXPECT_EQ(back.left_out[0].rfind(faces, 0), 0u) << back.left_out[0];
    }
  }
}

// gmsh itself opens our .msh and .mesh files and saves them again (as msh 2.2,
// which our reader reads back): the same vertices (gmsh prints 16 digits, so
// within 1e-15 relative) and the same tetrahedra.
TEST(OutputFormats, GmshOpensOurMshAndMeditFiles) {
  const OutputMesh m = torus_mesh();
  for (const auto& [format, name] :
       {std::pair{MeshFormat::kGmsh, "for_gmsh.msh"}, std::pair{MeshFormat::kMedit, "for_gmsh.mesh"}}) {
    SCOPED_TRACE(name);
    const std::string back = ::testing::TempDir() + "/" + name + ".gmsh22.msh";
    const auto r = test::run_command("gmsh -v 2 " + write(m, format, name) + " -0 -format msh22 -o " + back);
    ASSERT_EQ(r.status, 0) << "gmsh failed (scripts/setup.sh --all installs it):\n" << r.output;
    EXPECT_EQ(r.output.find("rror"), std::string::npos) << r.output;
    const InputMesh g = read_input(back);
    ASSERT_EQ(g.points.size(), m.points.size());
    for (size_t i = 0; i < m.points.size(); ++i) {
      const InputPoint want = m.grid.to_input(m.points[i]);
      ASSERT_NEAR(g.points[i].x, want.x, 1e-15 * (1 + std::abs(want.x)));
      ASSERT_NEAR(g.points[i].y, want.y, 1e-15 * (1 + std::abs(want.y)));
      ASSERT_NEAR(g.points[i].z, want.z, 1e-15 * (1 + std::abs(want.z)));
    }
    EXPECT_EQ(g.tets, m.cells);
  }
}

// --- meshdec end to end ----------------------------------------------------------

TEST(OutputFormats, MeshdecWritesEveryFormatByExtensionAndByName) {
  const std::string dir = ::testing::TempDir() + "/meshdec_formats";
  std::filesystem::create_directories(dir);
  const std::string stream = dir + "/torus.dtm";
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + test::data_path("torus_288.node") + " -q -o " +
                             stream);
  ASSERT_EQ(r.status, 0) << r.output;
  size_t tets = 0, points = 0;
  for (const char* ext : {".vtu", ".vtk", ".mesh", ".msh", ".node", ".vol"}) {
    const std::string out = dir + "/level1" + ext;
    r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " --level 1 -o " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    const InputMesh back = read_input(out);
    if (tets == 0) {
      tets = back.tets.size();
      points = back.points.size();
      EXPECT_LT(points, 288u);
    }
    EXPECT_EQ(back.points.size(), points) << ext;
    EXPECT_EQ(back.tets.size(), tets) << ext;
    EXPECT_GT(tets, 0u);
  }
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -o " + dir + "/surface.off");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(test::slurp(dir + "/surface.off").substr(0, 4), "OFF\n");
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -o " + dir + "/surface.ply");
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -q -o - --format vtk-ascii | head -c 26");
  EXPECT_EQ(r.output, "# vtk DataFile Version 4.2");
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -q -o - --format xyz | wc -l");
  EXPECT_EQ(std::stoi(r.output), 288);
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -o " + dir + "/x.stl");
  EXPECT_NE(r.status, 0);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.stl"));
}

// An output path that is a symbolic link writes its target (the link
// stays); a device or a named pipe is written into, never replaced by a
// plain file (`meshdec ... -o /dev/null` as root would otherwise break the
// system).
TEST(OutputFormats, LinksDevicesAndPipesAreWrittenThroughNotReplaced) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("dtm_targets_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path file = dir / "real.vtu", link = dir / "link.vtu";
  fs::create_symlink(file.filename(), link);
  write_files_atomically({{link.string(), "through the link"}});
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  std::ifstream in(file);
  std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(got, "through the link");
  // A link to a pipe's /proc entry (what /dev/stdout is in a pipeline)
  // names no path: written through the link as given.
  {
    int ends[2];
    ASSERT_EQ(::pipe(ends), 0);
    const std::string proc = "/proc/self/fd/" + std::to_string(ends[1]);
    const fs::path to_pipe = dir / "stdout_like";
    fs::create_symlink(proc, to_pipe);
    write_files_atomically({{to_pipe.string(), "into a pipe"}});
    ::close(ends[1]);
    char got_pipe[32] = {};
    const ssize_t n = ::read(ends[0], got_pipe, sizeof(got_pipe) - 1);
    ::close(ends[0]);
    EXPECT_EQ(std::string(got_pipe, n > 0 ? static_cast<size_t>(n) : 0), "into a pipe");
    fs::remove(to_pipe);
  }
  // A character device (/dev/null) stays one.
  ASSERT_TRUE(fs::is_character_file("/dev/null"));
  write_files_atomically({{"/dev/null", "into the device"}});
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // A named pipe: its reader gets the bytes, and it stays a pipe.
  const fs::path fifo = dir / "pipe.vtu";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string read_back;
  std::thread reader([&] {
    std::ifstream p(fifo);
    read_back.assign((std::istreambuf_iterator<char>(p)), std::istreambuf_iterator<char>());
  });
  write_files_atomically({{fifo.string(), "down the pipe"}});
  reader.join();
  EXPECT_EQ(read_back, "down the pipe");
  EXPECT_TRUE(fs::is_fifo(fifo));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  fs::remove_all(dir);
}

// Files written together (.node and .ele, .gltf and .bin): where one cannot
// be replaced (a directory of its name), none is written, nor left as a
// temporary.
TEST(OutputFormats, FilesWrittenTogetherAreAllWrittenOrNone) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("dtm_together_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "x.ele");
  try {
    write_files_atomically({{(dir / "x.node").string(), "nodes"}, {(dir / "x.ele").string(), "cells"}});
    ADD_FAILURE() << "a directory replaced";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("x.ele: cannot replace"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "x.node"));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  fs::remove_all(dir);
}

// A rename that fails partway for another reason than a directory (an
// immutable file, a sticky folder's file of another owner): the files
// replaced before it are put back, those that were not there are gone,
// and nothing is left beside them.
TEST(OutputFormats, AFailedRenamePutsBackTheFilesBeforeIt) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("dtm_put_back_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto read = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  std::ofstream(dir / "x.node") << "old nodes";
  std::ofstream(dir / "x.ele") << "old cells";
  // Fails on the third file: the first two are in place by then.
  const RenameFile refuse_the_face = [](const char* from, const char* to) {
    if (std::string(to).ends_with(".face")) {
      errno = EPERM;
      return -1;
    }
    return std::rename(from, to);
  };
  try {
    write_files_atomically({{(dir / "x.node").string(), "nodes"},
                            {(dir / "x.edge").string(), "edges"},
                            {(dir / "x.ele").string(), "cells"},
                            {(dir / "x.face").string(), "faces"}},
                           refuse_the_face);
    ADD_FAILURE() << "the failed rename was not said";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("x.face: cannot replace"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read(dir / "x.node"), "old nodes");
  EXPECT_EQ(read(dir / "x.ele"), "old cells");
  EXPECT_FALSE(fs::exists(dir / "x.edge"));
  EXPECT_FALSE(fs::exists(dir / "x.face"));
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
    EXPECT_EQ(e.path().filename().string().find(".old."), std::string::npos) << e.path();
  }
  EXPECT_EQ(files, 2u);
  // And when every rename succeeds, the new files and nothing else.
  write_files_atomically({{(dir / "x.node").string(), "nodes"}, {(dir / "x.ele").string(), "cells"}});
  EXPECT_EQ(read(dir / "x.node"), "nodes");
  EXPECT_EQ(read(dir / "x.ele"), "cells");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
  // Staged files (meshdec's pieces on ranks): left as they were if never
  // committed; committed, then undone (another rank failed), put back.
  {
    StagedFiles staged;
    staged.stage({{(dir / "x.node").string(), "staged nodes"}, {(dir / "y.vtu").string(), "piece"}});
  }
  EXPECT_EQ(read(dir / "x.node"), "nodes");
  EXPECT_FALSE(fs::exists(dir / "y.vtu"));
  {
    StagedFiles staged;
    staged.stage({{(dir / "x.node").string(), "staged nodes"}, {(dir / "y.vtu").string(), "piece"}});
    staged.commit();
    EXPECT_EQ(read(dir / "x.node"), "staged nodes");
    EXPECT_EQ(read(dir / "y.vtu"), "piece");
    staged.undo();
  }
  EXPECT_EQ(read(dir / "x.node"), "nodes");
  EXPECT_FALSE(fs::exists(dir / "y.vtu"));
  {
    StagedFiles staged;
    staged.stage({{(dir / "x.node").string(), "committed"}});
    staged.commit();
  }
  EXPECT_EQ(read(dir / "x.node"), "committed");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dtm
