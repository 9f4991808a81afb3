// meshenc as a user runs it: the table, the JSON report and its field names,
// and clear failures on bad input with no report left behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "codec/stream/format.h"
#include "test_support.h"
#include "tools/formats/input.h"

namespace dtm {
namespace {

using test::CommandRun;
using test::run_command;

CommandRun meshenc(const std::string& args) { return run_command(std::string(DTM_MESHENC) + " " + args); }
const std::string kMeshdec = DTM_MESHDEC;
const std::string kMeshinfo = DTM_MESHINFO;

TEST(Meshenc, WritesTheReportWithTheAgreedFieldNames) {
  const std::string report = ::testing::TempDir() + "/torus.json";
  const CommandRun r =
      meshenc(test::data_path("torus_288.node") + " --scale 25 --dmax 3 --preset paper --report " + report);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("level"), std::string::npos);
  std::ifstream in(report);
  const auto j = nlohmann::json::parse(in);
  for (const char* key : {"input", "qbits", "origin", "step", "duplicates_merged", "levels"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["qbits"], 14);
  EXPECT_EQ(j["origin"].size(), 3u);
  ASSERT_GE(j["levels"].size(), 3u);
  for (const auto& level : j["levels"])
    for (const char* key :
         {"level", "vertices", "boundary_vertices", "removed_interior", "removed_boundary", "alpha",
          "tetrahedra", "avg_min_solid_angle", "min_solid_angle", "max_boundary_error"})
      EXPECT_TRUE(level.contains(key)) << key;
  EXPECT_EQ(j["levels"][0]["vertices"], 288);
  EXPECT_EQ(j["levels"][0]["boundary_vertices"], 180);
  // alpha in input units: the torus scaled by 25 has the paper's alpha_0 of about 19.6.
  EXPECT_NEAR(j["levels"][0]["alpha"].get<double>(), 19.63, 0.05);
}

TEST(Meshenc, BadInputFailsClearlyAndLeavesNoReport) {
  const std::string report = ::testing::TempDir() + "/bad.json";
  for (const char* name : {"nan.node", "truncated.node", "coplanar.node", "three_points.node",
                           "all_equal.node", "does_not_exist.node"}) {
    std::filesystem::remove(report);
    const std::string path = std::string(DTM_TEST_SOURCE_DIR) + "/bad/" + name;
    const CommandRun r = meshenc(path + " --report " + report);
    EXPECT_NE(r.status, 0) << name;
    EXPECT_NE(r.output.find("meshenc: error: " + path), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(report)) << name;
  }
}

// What the stream does not hold is said on standard error and in the
// report; --strict refuses such an input and writes nothing.
TEST(Meshenc, WhatIsLeftOutIsSaidAndStrictRefusesIt) {
  const std::string dir = ::testing::TempDir();
  const std::string vtk = dir + "/left_out.vtk", out = dir + "/left_out.dtm", report = dir + "/left_out.json";
  std::ofstream(vtk) << "# vtk DataFile Version 3.0\nc\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n"
                        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\nCELLS 3 14\n4 0 1 2 3\n4 1 2 3 4\n3 0 1 2\n"
                        "CELL_TYPES 3\n10\n10\n5\n";
  std::filesystem::remove(out);
  // (Standard output to /dev/null: what comes back is standard error.)
  const CommandRun plain = run_command("(" + std::string(DTM_MESHENC) + " " + vtk + " -o " + out +
                                       " --report " + report + " >/dev/null)");
  ASSERT_EQ(plain.status, 0) << plain.output;
  // (A triangle is a tagged face where a cell array tags it: here none does.)
  EXPECT_NE(
      plain.output.find(vtk + ": left out (the stream does not hold it): 1 triangles without a tag array"),
      std::string::npos)
      << plain.output;
  std::ifstream in(report);
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["left_out"].size(), 1u);
  // A cell array whose name a stream cannot hold (meshio's .vtk or .vtu of
  // a gmsh mesh joins its groups' names into one array's): left out, named;
  // the rest encoded. Its table on a full disk: an error.
  const std::string long_name(70, 'g'), named_vtk = dir + "/long_name.vtk";
  std::ofstream(named_vtk)
      << "# vtk DataFile Version 3.0\nc\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n"
         "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\nCELLS 2 10\n4 0 1 2 3\n4 1 2 3 4\n"
         "CELL_TYPES 2\n10\n10\nCELL_DATA 2\nSCALARS "
      << long_name << " double 1\nLOOKUP_TABLE default\n1.5\n2.5\n";
  const CommandRun long_array =
      run_command("(" + std::string(DTM_MESHENC) + " " + named_vtk + " -o " + out + " >/dev/null)");
  ASSERT_EQ(long_array.status, 0) << long_array.output;
  EXPECT_NE(long_array.output.find("left out (the stream does not hold it): the cell array '" + long_name +
                                   "' (a stream names an array in at most 64 bytes)"),
            std::string::npos)
      << long_array.output;
  const CommandRun full = run_command("(" + std::string(DTM_MESHENC) + " " + named_vtk + " >/dev/full)");
  EXPECT_NE(full.status, 0) << full.output;
  EXPECT_NE(full.output.find("cannot write to standard output"), std::string::npos) << full.output;
  const CommandRun info = run_command("(" + std::string(DTM_MESHINFO) + " " + out + " --json >/dev/full)");
  EXPECT_NE(info.status, 0) << info.output;
  EXPECT_NE(info.output.find("cannot write to standard output"), std::string::npos) << info.output;
  std::filesystem::remove(out);
  const CommandRun strict = meshenc(vtk + " -q --strict -o " + out);
  EXPECT_NE(strict.status, 0);
  EXPECT_NE(strict.output.find("--strict"), std::string::npos) << strict.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  // gmsh's names of physical groups no tetrahedron or triangle is in.
  const std::string msh = dir + "/left_out.msh";
  std::ofstream(msh) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n3 1 \"steel\"\n"
                        "3 5 \"empty\"\n2 7 \"base\"\n2 9 \"ghost\"\n$EndPhysicalNames\n$Nodes\n5\n"
                        "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$EndNodes\n$Elements\n3\n"
                        "1 4 2 1 1 1 2 3 4\n2 4 2 1 1 2 3 4 5\n3 2 2 7 1 1 2 3\n$EndElements\n";
  const CommandRun named =
      run_command("(" + std::string(DTM_MESHENC) + " " + msh + " -o " + out + " >/dev/null)");
  ASSERT_EQ(named.status, 0) << named.output;
  EXPECT_NE(
      named.output.find("left out (the stream does not hold it): the name \"empty\" of region 5, which no "
                        "tetrahedron has"),
      std::string::npos)
      << named.output;
  EXPECT_NE(named.output.find("the name \"ghost\" of face tag 9, which no triangle has"), std::string::npos)
      << named.output;
  EXPECT_EQ(named.output.find("steel"), std::string::npos) << named.output;
  EXPECT_EQ(named.output.find("base"), std::string::npos) << named.output;
  std::filesystem::remove(out);
  EXPECT_NE(meshenc(msh + " -q --strict -o " + out).status, 0);
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A bricked level keeps no cell above its kept radius (twice alpha, from
// the mean spacing): hand_10k's coarse inside holds larger cells, so its
// bricked level 0 lacks them, far beyond D_max: meshenc says so. bunny_10k's
// level 0 keeps the input's solid: nothing is said.
// A bricked level keeps no cell above its kept radius, which follows the
// mean spacing; a graded mesh's coarse inside holds larger cells (hand_10k:
// 1,083 of its 61,919 tetrahedra above level 0's kept radius of 18 in the
// 256 box). The encoder raises level 0's radius to keep them: its bricked
// level 0 is as far from the input's surface as the whole-level encoder's
// (before: 48.43 against 2.28, D_max 2, and one level), with coarser levels
// under it; a mesh of even spacing keeps the radius its spacing gives.
TEST(Meshenc, ABrickedLevelZeroKeepsTheLargeCellsOfAGradedMeshsSolid) {
  const std::string dir = ::testing::TempDir() + "/bricked_level0";
  std::filesystem::create_directories(dir);
  for (const std::string model : {"hand_10k", "bunny_10k"}) {
    std::filesystem::copy_file(test::data_path(model + ".node"), dir + "/" + model + ".node",
                               std::filesystem::copy_options::overwrite_existing);
    const std::string ele = model == "hand_10k" ? "cells/" + model + ".ele" : model + ".ele";
    std::filesystem::copy_file(test::data_path(ele), dir + "/" + model + ".ele",
                               std::filesystem::copy_options::overwrite_existing);
    std::map<std::string, nlohmann::json> reports;
    for (const std::string how : {"whole", "bricked"}) {
      const std::string out = dir + "/" + model + "." + how;
      const CommandRun run = run_command("(" + std::string(DTM_MESHENC) + " " + dir + "/" + model +
                                         ".node --box 256 --dmax 2 --no-fields -q " +
                                         (how == "bricked" ? "--bricks --block-points 4000 " : "") + "-o " +
                                         out + ".dtm --report " + out + ".json)");
      ASSERT_EQ(run.status, 0) << run.output;
      EXPECT_EQ(run.output.find("level 0's surface is up to"), std::string::npos)
          << model << ": " << run.output;
      std::ifstream in(out + ".json");
      reports[how] = nlohmann::json::parse(in);
    }
    const nlohmann::json& whole = reports["whole"]["levels"][0];
    const nlohmann::json& bricked = reports["bricked"]["levels"][0];
    EXPECT_LE(bricked["reference_max_error"].get<double>(), whole["reference_max_error"].get<double>() + 1e-9)
        << model;
    EXPECT_NEAR(bricked["tetrahedra"].get<double>(), whole["tetrahedra"].get<double>(),
                1e-3 * whole["tetrahedra"].get<double>())
        << model;
    EXPECT_GE(reports["bricked"]["levels"].size(), 3u) << model;
    // bunny_10k's level 0 drops a cell or so of its solid, within D_max.
    const nlohmann::json& radius = reports["bricked"]["level0_kept_radius"];
    if (model == "hand_10k") {
      EXPECT_GT(radius["used"].get<double>(), 2 * radius["from_spacing"].get<double>());
      EXPECT_EQ(radius["cells_of_the_solid_dropped"].get<uint64_t>(), 0u);
    } else {
      EXPECT_EQ(radius["used"].get<double>(), radius["from_spacing"].get<double>());
    }
  }
}

TEST(Meshenc, RejectsBadOptions) {
  // A command line the tool cannot take exits with 2, an input it cannot
  // use with 1 (docs/CLI.md).
  const CommandRun range = meshenc(test::data_path("torus_288.node") + " --qbits 25");
  EXPECT_TRUE(WIFEXITED(range.status) && WEXITSTATUS(range.status) == 2) << range.output;
  const CommandRun unknown = meshenc(test::data_path("torus_288.node") + " --no-such-option");
  EXPECT_TRUE(WIFEXITED(unknown.status) && WEXITSTATUS(unknown.status) == 2) << unknown.output;
  const CommandRun missing = meshenc("/no/such/file.node -o -");
  EXPECT_TRUE(WIFEXITED(missing.status) && WEXITSTATUS(missing.status) == 1) << missing.output;
  const CommandRun help = meshenc("--help");
  EXPECT_TRUE(WIFEXITED(help.status) && WEXITSTATUS(help.status) == 0) << help.output;
  // Options that contradict each other, or a value of the wrong form,
  // found after parsing: 2 too.
  for (const char* options :
       {" --alpha nonsense", " --scale 2 --box 3", " --field-error pressure", " --bricks --level-step 2",
        " --no-fields --field-error a=1", " --field-error a=1 --field-error a=2"}) {
    const CommandRun run = meshenc(test::data_path("torus_288.node") + options + " -o -");
    EXPECT_TRUE(WIFEXITED(run.status) && WEXITSTATUS(run.status) == 2) << options << ": " << run.output;
  }
  // Numbers as every number option reads them: decimal, finite, the whole
  // argument (--alpha and --field-error took inf, hexadecimal and spaces).
  for (const char* options : {" --alpha inf", " --alpha 0x20", " --alpha ' 20'", " --alpha 0", " --alpha nan",
                              " --field-error boundary_marker=inf", " --field-error boundary_marker=0x1",
                              " --field-error 'boundary_marker= 1'", " --dmax inf", " --dmax 0x20"}) {
    const CommandRun run = meshenc(test::data_path("torus_288.node") + options + " -o -");
    EXPECT_TRUE(WIFEXITED(run.status) && WEXITSTATUS(run.status) == 2) << options << ": " << run.output;
    EXPECT_NE(run.output.find("finite number"), std::string::npos) << options << ": " << run.output;
  }
  EXPECT_EQ(meshenc(test::data_path("torus_288.node") + " --alpha 1e1 -q -o -").status, 0);
  const std::string golden = std::string(DTM_TEST_SOURCE_DIR) + "/golden/torus_288_cells_bricks.dtm";
  for (const char* options : {" --pieces 2 -o x.vtu", " --box 1 1 1 0 0 0 -o x.vtu", " -o - --format node"}) {
    const CommandRun run = run_command(kMeshdec + " " + golden + options);
    EXPECT_TRUE(WIFEXITED(run.status) && WEXITSTATUS(run.status) == 2) << options << ": " << run.output;
  }
  // What bricked streams cannot do yet is refused before any work: no table.
  for (const char* flag : {"--exact", "--keep-order"}) {
    const CommandRun run = meshenc(test::data_path("torus_288.node") + " --bricks " + flag + " -o -");
    EXPECT_TRUE(WIFEXITED(run.status) && WEXITSTATUS(run.status) == 2) << flag << ": " << run.output;
    EXPECT_NE(run.output.find(flag), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("level  vertices"), std::string::npos) << run.output;
  }
}

// --exact's stream for the newest decoders and, asked for, for older ones
// (spec/FORMAT.md §7): the version each says, and the same level 0 (the
// cell hash meshdec checks) from each.
TEST(Meshenc, ExactStreamsForOlderDecoders) {
  const std::string input = test::data_path("torus_288.node") + " --scale 25 --dmax 3 --hash-cells -q";
  for (const auto& [flag, version] :
       {std::pair{"--exact", "23.0"}, std::pair{"--exact-v22", "14.0"}, std::pair{"--exact-v13", "13.0"},
        std::pair{"--exact-v12", "12.0"}, std::pair{"--exact-v11", "11.0"}}) {
    const std::string out = ::testing::TempDir() + "/torus_exact.dtm";
    const CommandRun r = meshenc(input + " " + flag + " -o " + out);
    ASSERT_EQ(r.status, 0) << flag << ": " << r.output;
    const CommandRun info = run_command(kMeshinfo + " " + out + " --json");
    ASSERT_EQ(info.status, 0) << info.output;
    EXPECT_EQ(nlohmann::json::parse(info.output)["version"], version) << flag;
    const CommandRun decoded =
        run_command(kMeshdec + " " + out + " -q -o " + ::testing::TempDir() + "/e.node");
    EXPECT_EQ(decoded.status, 0) << flag << ": " << decoded.output;
  }
}

// The three tools end to end, as the README shows them.
class Tools : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/tools";
    std::filesystem::create_directories(dir_);
    stream_ = dir_ + "/bunny.dtm";
    const CommandRun r =
        meshenc(test::data_path("bunny_10k.node") + " --box 256 --dmax 2 --hash-cells -q -o " + stream_);
    ASSERT_EQ(r.status, 0) << r.output;
    const CommandRun info = run_command(kMeshinfo + " " + stream_ + " --json");
    ASSERT_EQ(info.status, 0) << info.output;
    const auto j = nlohmann::json::parse(info.output);
    levels_ = j["level_count"].get<int>();
    ASSERT_GE(levels_, 4);
    // Half way through the finest layer.
    half_finest_ = j["bytes"].get<size_t>() - j["levels"].back()["layer_bytes"].get<size_t>() / 2;
  }
  static std::string dir_, stream_;
  static int levels_;
  static size_t half_finest_;
};
std::string Tools::dir_, Tools::stream_;
int Tools::levels_ = 0;
size_t Tools::half_finest_ = 0;

TEST_F(Tools, MeshdecWritesEveryFormatAndVerifiesTheLevels) {
  CommandRun r = run_command(kMeshdec + " " + stream_ + " -o " + dir_ + "/fine.node --verify");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("verified " + std::to_string(levels_) + " levels"), std::string::npos) << r.output;
  const NodeFile fine = read_tetgen_node(dir_ + "/fine.node");
  EXPECT_EQ(fine.points.size(), 9844u);
  // Level 0 is the input's solid (bunny_10k.ele beside the .node): its
  // 57047 tetrahedra are 99.1% Delaunay, and the Delaunay cells whose
  // centroid lies in it make 57570.
  EXPECT_EQ(read_tetgen_ele(dir_ + "/fine.ele", fine.points.size()).size(), 57570u);

  r = run_command(kMeshdec + " " + stream_ + " -o " + dir_ + "/l3.vtu --level 3");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("level 3: "), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/l3.vtu"));
}

TEST_F(Tools, MeshdecVerboseTimesEachPhaseAndQuietSaysNothing) {
  const CommandRun r = run_command(kMeshdec + " " + stream_ + " -v -o " + dir_ + "/v.vtu");
  ASSERT_EQ(r.status, 0) << r.output;
  // A line per phase as it ends: its seconds, the memory now and at the peak, its name.
  const std::vector<std::string> phases = {
      "level 0: its ",    "level 0: inserting ",        "level 0: its cells",
      "level 0: carving", "writing " + dir_ + "/v.vtu", "in all"};
  for (const std::string& phase : phases)
    EXPECT_NE(r.output.find(" MiB peak  " + phase), std::string::npos) << phase << "\n" << r.output;
  const CommandRun quiet = run_command(kMeshdec + " " + stream_ + " -v -q -o " + dir_ + "/q.vtu");
  ASSERT_EQ(quiet.status, 0) << quiet.output;
  EXPECT_EQ(quiet.output, "");
}

TEST_F(Tools, ALevelTheStreamDoesNotHaveIsAnError) {
  const CommandRun r =
      run_command(kMeshdec + " " + stream_ + " -o " + dir_ + "/none.vtu --level " + std::to_string(levels_));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("levels 0 to " + std::to_string(levels_ - 1)), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/none.vtu"));
}

TEST_F(Tools, TruncatedInputDecodesWhatItHolds) {
  // Cut half way through the finest layer: every level but the finest.
  const CommandRun r = run_command("head -c " + std::to_string(half_finest_) + " " + stream_ + " | " +
                                   kMeshdec + " - -o " + dir_ + "/cut.vtu");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("truncated"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("writing level 1"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/cut.vtu"));
  // Level 0 asked for by name: an error, not level 1 in its place.
  const CommandRun asked = run_command("head -c " + std::to_string(half_finest_) + " " + stream_ + " | " +
                                       kMeshdec + " - -o " + dir_ + "/cut0.vtu --level 0");
  EXPECT_NE(asked.status, 0) << asked.output;
  EXPECT_NE(asked.output.find("--level 0 asked"), std::string::npos) << asked.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/cut0.vtu"));
}

// A region or the pieces of a truncated stream, without --level: its
// finest whole level, as the whole decode gives, and said so.
TEST_F(Tools, ATruncatedStreamsBoxAndPiecesAreOfItsFinestWholeLevel) {
  const std::string bricked = dir_ + "/bricked.dtm", cut = dir_ + "/bricked_cut.dtm";
  CommandRun r = meshenc(test::data_path("bunny_10k.node") +
                         " --box 256 --dmax 2 --bricks --brick-points 256 -q -o " + bricked);
  ASSERT_EQ(r.status, 0) << r.output;
  const size_t size = std::filesystem::file_size(bricked);
  ASSERT_EQ(run_command("head -c " + std::to_string(size - size / 6) + " " + bricked + " > " + cut).status,
            0);
  r = run_command(kMeshdec + " " + cut + " -o " + dir_ + "/cut_box.vtu --box -10 -10 -10 10 10 10");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("truncated"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("writing level 1"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/cut_box.vtu"));
  r = run_command(kMeshdec + " " + cut + " -o " + dir_ + "/cut_pieces.pvtu --pieces 2");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("level 1: 2 pieces"), std::string::npos) << r.output;
  // Level 0 asked for: an error.
  r = run_command(kMeshdec + " " + cut + " -o " + dir_ +
                  "/cut_box0.vtu --box -10 -10 -10 10 10 10 --level 0");
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/cut_box0.vtu"));
  // A box that meets nothing says where the mesh is (not the grid's cube,
  // far larger than the mesh along its shorter sides).
  r = run_command(kMeshdec + " " + bricked + " -o " + dir_ + "/far.vtu --box 50 50 50 60 60 60");
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meets the box (the coarsest level's vertices span "), std::string::npos)
      << r.output;
  r = run_command(kMeshdec + " " + stream_ + " -o " + dir_ + "/far.vtu --box 50 50 50 60 60 60");
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("meets the box (its vertices span "), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/far.vtu"));
}

// A parallel grid's pieces repeat the points on their borders: meshenc
// reads a .pvtu as one mesh, those copies merged into one point, so that
// --exact keeps its cells (a merge by quantization would refuse it).
TEST_F(Tools, AParallelGridsPiecesEncodeExactlyAsOneMesh) {
  const std::string bricked = dir_ + "/torus_bricked.dtm", exact = dir_ + "/from_pieces.dtm";
  CommandRun r = meshenc(test::data_path("torus_288.node") + " --bricks --brick-points 64 -q -o " + bricked);
  ASSERT_EQ(r.status, 0) << r.output;
  r = run_command(kMeshdec + " " + bricked + " -q -o " + dir_ + "/torus_pieces.pvtu --pieces 3");
  ASSERT_EQ(r.status, 0) << r.output;
  r = run_command(kMeshdec + " " + bricked + " -q -o " + dir_ + "/torus_whole.vtu");
  ASSERT_EQ(r.status, 0) << r.output;
  r = meshenc(dir_ + "/torus_pieces.pvtu --exact -o " + exact);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(" 0 merged by quantization"), std::string::npos) << r.output;
  r = run_command(kMeshdec + " " + exact + " -q -o " + dir_ + "/torus_again.vtu");
  ASSERT_EQ(r.status, 0) << r.output;
  // The same cells as the whole level's, by their corners' coordinates.
  const auto cells = [](const std::string& path) {
    const InputMesh m = read_input(path);
    std::vector<std::array<std::array<double, 3>, 4>> out;
    for (const auto& t : m.tets) {
      std::array<std::array<double, 3>, 4> c;
      for (size_t k = 0; k < 4; ++k) c[k] = {m.points[t[k]].x, m.points[t[k]].y, m.points[t[k]].z};
      std::sort(c.begin(), c.end());
      out.push_back(c);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  const auto whole = cells(dir_ + "/torus_whole.vtu");
  EXPECT_GT(whole.size(), 500u);
  EXPECT_EQ(cells(dir_ + "/torus_again.vtu"), whole);
}

// An output that cannot be written, or that is the input, is refused before
// any work, the input left as it was.
TEST_F(Tools, AnOutputThatCannotBeWrittenOrIsTheInputIsRefusedFirst) {
  const std::string copy = dir_ + "/mine.node";
  std::filesystem::copy_file(test::data_path("bunny_10k.node"), copy,
                             std::filesystem::copy_options::overwrite_existing);
  const std::string before = test::slurp(copy);
  CommandRun r = meshenc(copy + " --no-reference -o " + copy);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("is the input"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(copy), before);
  // Nor the .ele beside a .node, which is read too.
  std::filesystem::copy_file(test::data_path("bunny_10k.ele"), dir_ + "/mine.ele",
                             std::filesystem::copy_options::overwrite_existing);
  const std::string ele = test::slurp(dir_ + "/mine.ele");
  r = meshenc(copy + " -o " + dir_ + "/mine.ele");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("is the input"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(dir_ + "/mine.ele"), ele);
  // Nor a file the input has beside it or names, found as it is read: the
  // .face (an Abaqus *INCLUDE, a NRRD's data file, a .pvtu's piece alike).
  const auto first = read_input(test::data_path("bunny_10k.node")).tets.front();
  std::ofstream(dir_ + "/mine.face") << "1 1\n0 " << first[0] << " " << first[1] << " " << first[2] << " 7\n";
  const std::string face = test::slurp(dir_ + "/mine.face");
  r = meshenc(copy + " -o " + dir_ + "/mine.face");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("is the input"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(dir_ + "/mine.face"), face);
  std::filesystem::remove(dir_ + "/mine.face");
  r = meshenc(copy + " --no-reference -o " + dir_ + "/no/such/folder/x.dtm");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("no folder"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("level"), std::string::npos) << "said after the work: " << r.output;
  r = run_command(kMeshdec + " " + stream_ + " -o " + stream_);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("is the input"), std::string::npos) << r.output;
  EXPECT_GT(std::filesystem::file_size(stream_), 1000u);
  r = run_command(kMeshdec + " " + stream_ + " -o " + dir_ + "/no/such/folder/x.vtu");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("no folder"), std::string::npos) << r.output;
  // A folder where no file can be made whatever its permission bits say
  // (/proc, and /sys to root): found by making the file, before the work.
  r = meshenc(copy + " -o /proc/dtm_cannot_be_here.dtm");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("cannot write in /proc"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("level"), std::string::npos) << "said after the work: " << r.output;
  r = run_command(kMeshdec + " " + stream_ + " -o /proc/dtm_cannot_be_here.vtu");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("cannot write in /proc"), std::string::npos) << r.output;
  // Options that cannot go together, before the input is read.
  r = meshenc(dir_ + "/not_there.node --bricks --preset paper -o " + dir_ + "/x.dtm");
  EXPECT_EQ(WEXITSTATUS(r.status), 2) << r.output;
  EXPECT_NE(r.output.find("--bricks: bricked layers need the codec preset"), std::string::npos) << r.output;
  r = meshenc(dir_ + "/not_there.node --quality-guard 0.1 -o " + dir_ + "/x.dtm");
  EXPECT_EQ(WEXITSTATUS(r.status), 2) << r.output;
  EXPECT_NE(r.output.find("--quality-guard: the per-removal quality rules belong to the paper preset"),
            std::string::npos)
      << r.output;
  r = meshenc(dir_ + "/not_there.node --min-base -1 -o " + dir_ + "/x.dtm");
  EXPECT_EQ(WEXITSTATUS(r.status), 2) << r.output;
  // A --field-error for no array of the file: said before the table.
  r = meshenc(test::data_path("torus_288.node") + " --field-error nope=0.1 -o " + dir_ + "/x.dtm");
  EXPECT_EQ(WEXITSTATUS(r.status), 1) << r.output;
  EXPECT_NE(r.output.find("--field-error names 'nope', which is not a field of the input (it has "
                          "'boundary_marker')"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("merged by quantization"), std::string::npos) << r.output;
}

// What a field's values or bound cannot be is said in the file's terms: a
// lossy cell array's NaN by the file's tetrahedron, a bound as given (not
// %f's zeros); a --field-error for a cell array left out bounds nothing and
// stops nothing; a .node's unnamed attributes name the fields they were.
TEST_F(Tools, ValuesAreSaidInTheFilesTerms) {
  const std::string vtk = dir_ + "/values.vtk", out = dir_ + "/values.dtm";
  std::ofstream(vtk)
      << "# vtk DataFile Version 3.0\nc\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n"
         "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\nCELLS 2 10\n4 0 1 2 3\n4 1 2 3 4\n"
         "CELL_TYPES 2\n10\n10\nCELL_DATA 2\nSCALARS c double 1\nLOOKUP_TABLE default\n1.5\nnan\n"
         "POINT_DATA 5\nSCALARS t double 1\nLOOKUP_TABLE default\n0.1\n0.2\n0.3\n0.4\n0.5\n";
  const CommandRun nan = meshenc(vtk + " -q --field-error c=0.1 -o " + out);
  EXPECT_NE(nan.status, 0);
  EXPECT_NE(nan.output.find("cell data 'c': tetrahedron 1 (from 0, in the file's order) holds NaN"),
            std::string::npos)
      << nan.output;
  const CommandRun left = meshenc(vtk + " -q --no-cell-data --field-error c=0.1 -o " + out);
  EXPECT_EQ(left.status, 0) << left.output;
  ASSERT_EQ(meshenc(vtk + " -q --no-cell-data --field-error t=1e-12 -o " + out).status, 0);
  const CommandRun info = run_command(kMeshinfo + " " + out);
  EXPECT_NE(info.output.find("field 't': float64, within 1e-12,"), std::string::npos) << info.output;
  const CommandRun node = run_command(kMeshdec + " " + out + " -o " + dir_ + "/values.node");
  EXPECT_EQ(node.status, 0) << node.output;
  EXPECT_NE(
      node.output.find("not written (the format has no place for it): the point fields' names, components "
                       "and types (a .node's attributes are numbers only, written in this order) 't'"),
      std::string::npos)
      << node.output;
}

// Extensions in any case: X.NODE reads its X.ELE beside it, -o X.VTU
// writes a .vtu, -o Y.NODE its Y.ELE.
TEST_F(Tools, ExtensionsInAnyCase) {
  std::filesystem::copy_file(test::data_path("torus_288.node"), dir_ + "/T.NODE");
  std::filesystem::copy_file(test::data_path("torus_288.ele"), dir_ + "/T.ELE");
  CommandRun r = meshenc(dir_ + "/T.NODE -o " + dir_ + "/t.dtm");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the input's 1080 tetrahedra"), std::string::npos) << r.output;
  r = run_command(kMeshdec + " " + dir_ + "/t.dtm -o " + dir_ + "/OUT.VTU");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(read_input(dir_ + "/OUT.VTU").tets.size(), 1102u);
  r = run_command(kMeshdec + " " + dir_ + "/t.dtm -o " + dir_ + "/Y.NODE");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/Y.ELE"));
  // X.NODE's X.ELE is an input: not an output.
  r = meshenc(dir_ + "/T.NODE -o " + dir_ + "/T.ELE");
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("is the input"), std::string::npos) << r.output;
}

// A mesh meshdec wrote, encoded again: its point arrays level, boundary
// and vertex_id are meshdec's own, made again by the decoder; they are
// left out (and said so), not coded as fields and written twice.
TEST_F(Tools, MeshdecsOwnArraysAreNotCodedAgain) {
  const std::string vtu = dir_ + "/again_in.vtu", again = dir_ + "/again.dtm", out = dir_ + "/again_out.vtu";
  ASSERT_EQ(run_command(kMeshdec + " " + stream_ + " -q -o " + vtu).status, 0);
  CommandRun r = meshenc(vtu + " --box 256 --dmax 2 -o " + again);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the point arrays 'level', 'boundary' (meshdec's own"), std::string::npos)
      << r.output;
  ASSERT_EQ(run_command(kMeshdec + " " + again + " -q -o " + out).status, 0);
  const std::string text = test::slurp(out);
  for (const std::string name : {"\"level\"", "\"boundary\""}) {
    size_t count = 0;
    for (size_t at = text.find("Name=" + name); at != std::string::npos;
         at = text.find("Name=" + name, at + 1))
      ++count;
    EXPECT_EQ(count, 1u) << name;
  }
  // A box of a bricked level (or a piece of one) has level and vertex_id,
  // no boundary: meshdec's own too.
  const std::string box = dir_ + "/again_box.vtu";
  r = run_command(kMeshdec + " " + std::string(DTM_TEST_SOURCE_DIR) +
                  "/golden/torus_288_bricks.dtm -q --box -100 -100 -100 100 100 100 -o " + box);
  ASSERT_EQ(r.status, 0) << r.output;
  r = meshenc(box + " -o " + dir_ + "/again_box.dtm");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the point arrays 'level', 'vertex_id' (meshdec's own"), std::string::npos)
      << r.output;
  // The input's own vertex_id (global node numbers), without meshdec's
  // level: kept under another name, said, so that a box's file does not
  // hold two arrays of one name.
  std::string own = test::slurp(vtu);
  for (const auto& [from, to] : {std::pair{"Name=\"level\"", "Name=\"stage\""},
                                 std::pair{"Name=\"boundary\"", "Name=\"vertex_id\""}}) {
    const size_t at = own.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    own.replace(at, std::strlen(from), to);
  }
  std::ofstream(dir_ + "/own_ids.vtu") << own;
  r = meshenc(dir_ + "/own_ids.vtu --bricks -o " + dir_ + "/own_ids.dtm");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the array 'vertex_id' is kept as 'vertex_id (input)'"), std::string::npos)
      << r.output;
  r = run_command(kMeshdec + " " + dir_ + "/own_ids.dtm -q --box -100 -100 -100 100 100 100 -o " + dir_ +
                  "/own_ids_box.vtu");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string written = test::slurp(dir_ + "/own_ids_box.vtu");
  EXPECT_NE(written.find("Name=\"vertex_id (input)\""), std::string::npos);
  EXPECT_EQ(written.find("Name=\"vertex_id\""), written.rfind("Name=\"vertex_id\""));
  // A surface meshdec wrote as PLY has its 'level' alone: meshdec's too
  // (by the file's comment); its surface decoded again as PLY reads back.
  const std::string ply = dir_ + "/again.ply", ply_again = dir_ + "/again2.ply";
  ASSERT_EQ(run_command(kMeshdec + " " + stream_ + " -q -o " + ply).status, 0);
  r = meshenc(ply + " -o " + dir_ + "/again_ply.dtm");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the point property 'level' (meshdec's own"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("'level' (float64"), std::string::npos) << r.output;
  ASSERT_EQ(run_command(kMeshdec + " " + dir_ + "/again_ply.dtm -q -o " + ply_again).status, 0);
  EXPECT_EQ(meshenc(ply_again + " -q -o " + dir_ + "/again_ply2.dtm").status, 0);
}

// An error quoting a file's bytes prints its control bytes escaped, never
// as they are (a terminal would take them as commands).
TEST_F(Tools, AnErrorQuotingBinaryBytesEscapesThem) {
  const std::string path = dir_ + "/binary.msh";
  std::ofstream(path, std::ios::binary) << std::string("garbage\x01\x1b[31m\x7f", 14);
  const CommandRun r = meshenc(path + " -o " + dir_ + "/binary.dtm");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("garbage\\x01\\x1b[31m\\x7f"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << r.output;
}

// What an output format has no place for is named, not dropped silently.
TEST_F(Tools, WhatAFormatCannotHoldIsNamed) {
  const CommandRun r = run_command(kMeshdec + " " + std::string(DTM_TEST_SOURCE_DIR) +
                                   "/golden/torus_288_cells.dtm" + " -o " + dir_ + "/cells.mesh");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("not written (the format has no place for it): the cell arrays 'heat', 'zone'"),
            std::string::npos)
      << r.output;
  // The labels' names where the format holds numbers only (VTK's arrays,
  // Medit's refs); gmsh's $PhysicalNames hold them.
  const std::string named = std::string(DTM_TEST_SOURCE_DIR) + "/golden/two_materials_bricks_faces.dtm";
  for (const char* ext : {".vtu", ".vtk", ".mesh"}) {
    const CommandRun n = run_command(kMeshdec + " " + named + " -o " + dir_ + "/named" + ext);
    EXPECT_EQ(n.status, 0) << n.output;
    EXPECT_NE(
        n.output.find("not written (the format has no place for it): the regions' names (1 \"aluminium\", "
                      "2 \"steel\")"),
        std::string::npos)
        << ext << n.output;
    EXPECT_NE(n.output.find("the face tags' names (3 \"base\", 4 \"load\")"), std::string::npos)
        << ext << n.output;
  }
  const CommandRun gmsh = run_command(kMeshdec + " " + named + " -o " + dir_ + "/named.msh");
  EXPECT_EQ(gmsh.output.find("names"), std::string::npos) << gmsh.output;
  // The input's numbering of a second-order mesh's nodes (its edge nodes
  // among the corners): a format of linear cells numbers the corners alone.
  const std::string numbered = std::string(DTM_TEST_SOURCE_DIR) + "/golden/ball_order2_numbered_exact.dtm";
  const CommandRun linear = run_command(kMeshdec + " " + numbered + " -o " + dir_ + "/numbered.node");
  EXPECT_EQ(linear.status, 0) << linear.output;
  EXPECT_NE(linear.output.find("not written: the input's node numbers"), std::string::npos) << linear.output;
  const CommandRun quadratic = run_command(kMeshdec + " " + numbered + " -o " + dir_ + "/numbered.msh");
  EXPECT_EQ(quadratic.output.find("node numbers"), std::string::npos) << quadratic.output;
  // An option the output does not use is said too.
  const CommandRun coloured =
      run_command(kMeshdec + " " + std::string(DTM_TEST_SOURCE_DIR) +
                  "/golden/torus_288.dtm --color boundary --no-draco -o " + dir_ + "/coloured.vtu");
  EXPECT_EQ(coloured.status, 0) << coloured.output;
  EXPECT_NE(coloured.output.find("--color: only glTF and .drc outputs carry vertex colours"),
            std::string::npos)
      << coloured.output;
  EXPECT_NE(coloured.output.find("--no-draco: only a glTF output"), std::string::npos) << coloured.output;
  // And pieces left empty (more pieces than level 0's chunks).
  const CommandRun pieces =
      run_command(kMeshdec + " " + std::string(DTM_TEST_SOURCE_DIR) +
                  "/golden/torus_288_cells_bricks.dtm -o " + dir_ + "/many.pvtu --pieces 20");
  EXPECT_EQ(pieces.status, 0) << pieces.output;
  EXPECT_NE(pieces.output.find("of the 20 pieces hold no cell"), std::string::npos) << pieces.output;
}

TEST_F(Tools, DamagedOrForeignInputFailsAndWritesNothing) {
  const std::string out = dir_ + "/never.vtu";
  std::filesystem::remove(out);
  CommandRun r = run_command("printf 'not a stream' | " + kMeshdec + " - -o " + out);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("not a .dtm stream"), std::string::npos) << r.output;
  // One flipped byte in the middle of the stream: a damaged layer.
  const std::string damaged = dir_ + "/damaged.dtm";
  std::filesystem::copy_file(stream_, damaged, std::filesystem::copy_options::overwrite_existing);
  {
    std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(20000);
    f.put('\x5a');
  }
  r = run_command(kMeshdec + " " + damaged + " -o " + out);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("checksum mismatch"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(Tools, MeshinfoJsonDescribesTheStreamWithoutDecoding) {
  const CommandRun r = run_command(kMeshinfo + " " + stream_ + " --json");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["qbits"], 14);
  EXPECT_EQ(j["origin"].size(), 3u);
  EXPECT_GT(j["step"].get<double>(), 0);
  EXPECT_EQ(j["truncated"], false);
  ASSERT_EQ(j["levels"].size(), static_cast<size_t>(levels_));
  uint64_t total = dtm::kHeaderSize + j["field_table_bytes"].get<uint64_t>();
  for (const auto& l : j["levels"]) {
    for (const char* key : {"level", "vertices", "alpha", "layer_bytes", "carving_bytes", "complete"})
      EXPECT_TRUE(l.contains(key)) << key;
    total += l["layer_bytes"].get<uint64_t>();
  }
  EXPECT_EQ(total, std::filesystem::file_size(stream_));
  EXPECT_EQ(j["levels"][levels_ - 1]["vertices"], 9844);
  EXPECT_EQ(j["carving_corrections"], true);
}

TEST_F(Tools, EncoderAndDecoderPipe) {
  const CommandRun r = run_command(std::string(DTM_MESHENC) + " " + test::data_path("torus_288.node") +
                                   " -o - | " + kMeshdec + " - -o - --format vtu-ascii | head -c 200");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("UnstructuredGrid"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace dtm
