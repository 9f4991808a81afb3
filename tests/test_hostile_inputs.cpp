// Hostile and degenerate input, on both sides (issue 6): streams crafted to
// exhaust the decoder, damaged or reordered golden streams, and point sets
// in degenerate position given to meshenc. Each gives a clear error or a
// correct result: never a crash, a hang, or memory beyond a small multiple
// of what the vertices need.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "codec/decode.h"
#include "codec/region_decode.h"
#include "codec/stream/format.h"
#include "codec/stream/format_encoder.h"
#include "codec/stream/layer_coder.h"
#include "test_support.h"

namespace dtm {
namespace {

std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Every golden stream (tests/golden and its older formats' folders), by its
// name there without ".dtm": each format version and section the decoder
// reads, whole and bricked.
std::vector<std::string> all_golden() {
  const std::filesystem::path root = std::string(DTM_TEST_SOURCE_DIR) + "/golden";
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root))
    if (entry.path().extension() == ".dtm") {
      std::string name = std::filesystem::relative(entry.path(), root).replace_extension().string();
      names.push_back(std::move(name));
    }
  std::sort(names.begin(), names.end());
  return names;
}
const std::vector<std::string> kGolden = all_golden();

std::string golden(const std::string& name) {
  return std::string(DTM_TEST_SOURCE_DIR) + "/golden/" + name + ".dtm";
}

// A one-level stream whose points are `points` (q = 14), as an encoder
// would write it: valid checksums, valid payload.
std::vector<uint8_t> single_layer_stream(const std::vector<GridPoint>& points) {
  StreamHeader h;
  h.grid.qbits = 14;
  h.level_count = 1;
  h.vertex_count = static_cast<uint32_t>(points.size());
  LayerHeader l;
  l.level = 0;
  l.new_vertices = h.vertex_count;
  l.level_vertices = h.vertex_count;
  l.alpha = 1e9;
  SetCoderModels models;  // as the stream's format (3) has them
  models.enable_coordinate_reuse(14);
  auto bytes = write_header(h);
  const auto layer = write_layer(l, encode_point_set({}, points, 14, models));
  bytes.insert(bytes.end(), layer.begin(), layer.end());
  return bytes;
}

// n points on each of two skew lines: their Delaunay tetrahedralization has
// about n^2 cells, quadratic in what the stream holds.
std::vector<GridPoint> two_skew_lines(int n) {
  std::vector<GridPoint> points;
  for (int i = 0; i < n; ++i) {
    points.push_back({1000 + 7 * i, 5000, 1000});
    points.push_back({9000, 1000 + 7 * i, 9000});
  }
  return points;
}

TEST(HostileStream, TwoSkewLinesAreRefusedBeforeTheirQuadraticMesh) {
  const auto bytes = single_layer_stream(two_skew_lines(3000));  // 9M cells unchecked
  ProgressiveDecoder decoder;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(decode_stream(bytes, decoder).ok());  // the points themselves are valid
  EXPECT_TRUE(decoder.carved_cells().empty());
  EXPECT_EQ(decoder.mesh_status().code(), StatusCode::kLimitExceeded);
  EXPECT_NE(decoder.mesh_status().message().find("cells per vertex"), std::string::npos)
      << decoder.mesh_status().message();
  // Stopped near 64 cells per vertex, not after building 9M cells.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20.0);
}

TEST(HostileStream, MeshdecAndMeshinfoRefuseTwoSkewLines) {
  const std::string dir = ::testing::TempDir() + "/hostile";
  std::filesystem::create_directories(dir);
  const auto bytes = single_layer_stream(two_skew_lines(1500));
  std::ofstream(dir + "/skew.dtm", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  std::filesystem::remove(dir + "/skew.vtu");
  const test::CommandRun dec =
      test::run_command(std::string(DTM_MESHDEC) + " " + dir + "/skew.dtm -o " + dir + "/skew.vtu");
  EXPECT_NE(dec.status, 0);
  EXPECT_NE(dec.output.find("cells per vertex"), std::string::npos) << dec.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/skew.vtu"));
  // meshinfo --stats decodes every level too.
  const test::CommandRun info =
      test::run_command(std::string(DTM_MESHINFO) + " " + dir + "/skew.dtm --stats");
  EXPECT_NE(info.status, 0);
  EXPECT_NE(info.output.find("meshinfo: error: " + dir + "/skew.dtm: level 0 at byte "), std::string::npos)
      << info.output;
}

TEST(HostileStream, EveryTruncationOfEveryGoldenStreamGivesItsWholeLayers) {
  ASSERT_GE(kGolden.size(), 48u) << "tests/golden's streams, every format";
  for (const std::string& name : kGolden) {
    const auto bytes = read_bytes(golden(name));
    const StreamSummary summary = scan_stream(bytes);
    ASSERT_TRUE(summary.status.ok()) << name;
    for (size_t cut = 0; cut < bytes.size(); ++cut) {
      ProgressiveDecoder decoder;
      const Status s = decode_stream(std::span(bytes).first(cut), decoder);
      EXPECT_EQ(s.code(), StatusCode::kTruncated) << name << " cut " << cut << ": " << s.message();
      size_t whole = 0;  // layers that end at or before the cut
      for (const auto& l : summary.layers)
        if (l.offset + l.size() <= cut) ++whole;
      EXPECT_EQ(decoder.levels().size(), whole) << name << " cut " << cut;
    }
  }
}

// Every single bit flipped in a layer's header is an error, never a stream
// cut inside that layer: a length made larger runs past the stream's end,
// where the layer's checksum holds for the length smaller by the overshoot
// (the last layer) or by the bit (any layer: LayerWalk::overshoot_is_damage);
// it read as a truncation, and the decoders gave the coarser levels with no
// error.
TEST(HostileStream, AFlippedBitInALayersHeaderIsDamageNotACut) {
  for (const std::string& name : kGolden) {
    const auto bytes = read_bytes(golden(name));
    const StreamSummary summary = scan_stream(bytes);
    ASSERT_TRUE(summary.status.ok()) << name;
    for (const LayerSummary& layer : summary.layers) {
      const size_t header = layer_header_size(layer.header);
      const bool bricked = layer.header.bricked;
      for (size_t at = layer.offset; at < layer.offset + header; ++at)
        for (int bit = 0; bit < 8; ++bit) {
          std::vector<uint8_t> flipped = bytes;
          flipped[at] ^= static_cast<uint8_t>(1u << bit);
          ProgressiveDecoder decoder;
          const Status s = decode_stream(flipped, decoder);
          EXPECT_FALSE(s.ok() || s.code() == StatusCode::kTruncated)
              << name << " byte " << at << " bit " << bit << ": " << s.message();
          const StreamSummary scanned = scan_stream(flipped);
          EXPECT_FALSE(scanned.status.ok() || scanned.status.code() == StatusCode::kTruncated)
              << name << " byte " << at << " bit " << bit << ": meshinfo: " << scanned.status.message();
          if (bricked) {
            MemorySource source(flipped);
            const auto piece = decode_piece(source, 0, 0, 2);
            EXPECT_FALSE(piece.ok() || piece.status().code() == StatusCode::kTruncated)
                << name << " byte " << at << " bit " << bit << ": piece: " << piece.status().message();
          }
        }
    }
  }
}

TEST(HostileStream, LayersOutOfOrderAreRejected) {
  for (const std::string& name : kGolden) {
    const auto bytes = read_bytes(golden(name));
    const StreamSummary summary = scan_stream(bytes);
    if (summary.layers.size() < 2) continue;
    // Swap the first two layers.
    const auto& a = summary.layers[0];
    const auto& b = summary.layers[1];
    const size_t a_end = b.offset, b_end = b.offset + b.size();
    std::vector<uint8_t> swapped(bytes.begin(), bytes.begin() + a.offset);
    swapped.insert(swapped.end(), bytes.begin() + b.offset, bytes.begin() + b_end);
    swapped.insert(swapped.end(), bytes.begin() + a.offset, bytes.begin() + a_end);
    swapped.insert(swapped.end(), bytes.begin() + b_end, bytes.end());
    ProgressiveDecoder decoder;
    const Status s = decode_stream(swapped, decoder);
    EXPECT_EQ(s.code(), StatusCode::kCorrupt) << name << ": " << s.message();
    EXPECT_TRUE(decoder.levels().empty()) << name;
  }
}

TEST(HostileStream, DamagedHeaderFieldsAreRejected) {
  const auto bytes = read_bytes(golden("torus_288"));
  for (size_t i = 0; i < kHeaderSize; ++i) {
    auto damaged = bytes;
    damaged[i] ^= 0x40;
    ProgressiveDecoder decoder;
    const Status s = decode_stream(damaged, decoder);
    EXPECT_FALSE(s.ok()) << "byte " << i;
    EXPECT_NE(s.code(), StatusCode::kTruncated) << "byte " << i;
    EXPECT_TRUE(decoder.levels().empty()) << "byte " << i;
  }
}

// ---- meshenc on point sets in degenerate position ----

std::string write_node(const std::string& name, const std::vector<std::array<double, 3>>& points) {
  const std::string path = ::testing::TempDir() + "/" + name + ".node";
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fprintf(f, "%zu 3 0 0\n", points.size());
  for (size_t i = 0; i < points.size(); ++i)
    std::fprintf(f, "%zu %.17g %.17g %.17g\n", i, points[i][0], points[i][1], points[i][2]);
  std::fclose(f);
  return path;
}

// Runs meshenc, then decodes what it wrote: a clear error naming the file
// and containing `error_part`, and no output; or (error_part empty) a stream
// that decodes to `expect_vertices` vertices and a non-empty mesh; or
// (error_part "either") one of the two.
void expect_error_or_stream(const std::string& path, const std::string& error_part,
                            uint32_t expect_vertices) {
  const std::string out = path + ".dtm";
  std::filesystem::remove(out);
  const test::CommandRun enc = test::run_command(std::string(DTM_MESHENC) + " " + path + " -q -o " + out);
  if (error_part == "either" && enc.status != 0) {
    EXPECT_NE(enc.output.find("meshenc: error: " + path), std::string::npos) << enc.output;
    EXPECT_FALSE(std::filesystem::exists(out));
    return;
  }
  if (!error_part.empty() && error_part != "either") {
    EXPECT_NE(enc.status, 0) << path;
    EXPECT_NE(enc.output.find("meshenc: error: " + path), std::string::npos) << enc.output;
    EXPECT_NE(enc.output.find(error_part), std::string::npos) << enc.output;
    EXPECT_FALSE(std::filesystem::exists(out));
    return;
  }
  ASSERT_EQ(enc.status, 0) << enc.output;
  const auto bytes = read_bytes(out);
  ProgressiveDecoder decoder;
  ASSERT_TRUE(decode_stream(bytes, decoder).ok());
  // A near-degenerate input may carve to no cell at all (every cell a sliver
  // wider than alpha): the stream is still the right one.
  if (error_part.empty()) {
    EXPECT_EQ(decoder.points().size(), expect_vertices);
    EXPECT_FALSE(decoder.carved_cells().empty());
  }
  EXPECT_TRUE(decoder.mesh_status().ok());
}

TEST(DegenerateInput, CollinearPoints) {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 1000; ++i) p.push_back({i * 0.5, 3.0, -2.0});
  expect_error_or_stream(write_node("collinear", p), "collinear", 0);
  // On a sloped line, rounding to the grid may move points off the line: then
  // they span three dimensions and make a (thin) mesh, which is a correct result.
  p.clear();
  for (int i = 0; i < 1000; ++i) p.push_back({i * 0.5, i * 0.25, -i * 1.0});
  expect_error_or_stream(write_node("collinear_sloped", p), "either", 0);
}

TEST(DegenerateInput, AMillionCopiesOfFivePoints) {
  const std::array<double, 3> five[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.3, 0.3, 0.3}};
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 1'000'000; ++i) p.push_back(five[i % 5]);
  expect_error_or_stream(write_node("copies", p), "", 5);
}

TEST(DegenerateInput, CoordinatesFarApart) {
  // Two tetrahedra 1e300 apart: at q = 14 each collapses to one grid point.
  std::vector<std::array<double, 3>> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 4; ++i) p.push_back({1e300 + p[i][0], p[i][1], p[i][2]});
  expect_error_or_stream(write_node("far_apart", p), "dimension", 0);
  // An extent that overflows a double.
  p = {{-1e308, 0, 0}, {1e308, 0, 0}, {0, 1e308, 0}, {0, 0, 1e308}, {0, -1e308, 5}};
  expect_error_or_stream(write_node("overflow", p), "wider than a double", 0);
}

TEST(DegenerateInput, TwoSkewLinesAreRefusedWithAClearMessage) {
  std::vector<std::array<double, 3>> p;
  for (int i = 0; i < 3000; ++i) {
    p.push_back({double(i), 0, 0});
    p.push_back({1500, double(i), 1000});
  }
  expect_error_or_stream(write_node("skew", p), "cells per vertex", 0);
}

}  // namespace
}  // namespace dtm
