// meshenc as a user runs it: the table, the JSON report and its field names,
// and clear failures on bad input with no report left behind.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace dtm {
namespace {

struct ToolRun {
  int status;
  std::string output;  // stdout and stderr
};

ToolRun meshenc(const std::string& args) {
  const std::string cmd = std::string(DTM_MESHENC) + " " + args + " 2>&1";
  ToolRun r{0, {}};
  std::FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
  r.status = pclose(p);
  return r;
}

TEST(Meshenc, WritesTheReportWithTheAgreedFieldNames) {
  const std::string report = ::testing::TempDir() + "/torus.json";
  const ToolRun r = meshenc(test::data_path("torus_288.node") + " --scale 25 --dmax 3 --report " + report);
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
    for (const char* key : {"level", "vertices", "boundary_vertices", "removed_interior",
                            "removed_boundary", "alpha", "tetrahedra", "avg_min_solid_angle",
                            "min_solid_angle", "max_boundary_error"})
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
    const ToolRun r = meshenc(path + " --report " + report);
    EXPECT_NE(r.status, 0) << name;
    EXPECT_NE(r.output.find("meshenc: error:"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(report)) << name;
  }
}

TEST(Meshenc, RejectsBadOptions) {
  EXPECT_NE(meshenc(test::data_path("torus_288.node") + " --qbits 25").status, 0);
  EXPECT_NE(meshenc(test::data_path("torus_288.node") + " --alpha nonsense").status, 0);
  EXPECT_NE(meshenc(test::data_path("torus_288.node") + " --scale 2 --box 3").status, 0);
}

}  // namespace
}  // namespace dtm
