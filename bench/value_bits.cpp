// value_bits: what a .dtm stream spends on an input's per-vertex fields
// (spec/FORMAT.md §3.3), beside zstd -19 and xz -9 of the same values stored
// raw in the input's order (raster order, x fastest, for a voxel volume), and
// what decoding them adds to decoding the positions. Issue 13's measurement.
//
//   value_bits FILE [--threshold T | --label L] [--voxel-interior-step K]
//              [--box B] [--dmax D] [--field NAME] [--error-shares S1,S2,...]
//              [--csv OUT.csv]
//
// Each field (or only NAME) is encoded as meshenc encodes it, alone with the
// positions: losslessly, or with --error-shares within E = S x its range for
// each S (floats only), against zstd -19 of round(v / 2E) as int32. The
// stream is decoded and every value checked (exact, or within E) before
// anything is printed. --csv appends one row per measurement.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "tools/field_types.h"
#include "tools/formats/input.h"
#include "tools/formats/render_util.h"

namespace {

// Bytes of `command` run on `path` ("zstd -19 -c", "xz -9 -c").
long compressed_size(const std::string& command, const std::string& path) {
  const std::string line = command + " '" + path + "' | wc -c";
  FILE* p = popen(line.c_str(), "r");
  if (!p) return -1;
  long bytes = -1;
  if (std::fscanf(p, "%ld", &bytes) != 1) bytes = -1;
  pclose(p);
  return bytes;
}

// zstd -19 and xz -9 of `raw`, in bytes.
std::pair<long, long> baselines(const std::string& raw) {
  const std::string tmp =
      (std::filesystem::temp_directory_path() / ("value_bits_" + std::to_string(getpid()) + ".raw")).string();
  std::ofstream(tmp, std::ios::binary).write(raw.data(), static_cast<std::streamsize>(raw.size()));
  const long zstd = compressed_size("zstd -19 -q -c", tmp), xz = compressed_size("xz -9 -c", tmp);
  std::filesystem::remove(tmp);
  return {zstd, xz};
}

// Seconds to decode `bytes` to the finest mesh (points, values and the
// carved tetrahedralization).
double decode_once(const std::vector<uint8_t>& bytes) {
  const auto start = std::chrono::steady_clock::now();
  dtm::ProgressiveDecoder d;
  if (!d.feed(bytes).ok() || d.carved_cells().empty()) throw std::runtime_error("the stream does not decode");
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// What decoding `with` costs beyond decoding `without`, as a share of the
// latter: the best of 15 runs each, taken in turns so that the machine's
// slower spells touch both alike.
double extra_decode_share(const std::vector<uint8_t>& with, const std::vector<uint8_t>& without) {
  double best_with = 1e300, best_without = 1e300;
  for (int k = 0; k < 15; ++k) {
    best_without = std::min(best_without, decode_once(without));
    best_with = std::min(best_with, decode_once(with));
  }
  return (best_with - best_without) / best_without;
}

struct Args {
  std::string path, only_field, csv;
  dtm::VolumeOptions volume;
  dtm::EncodeOptions options;
  std::vector<double> error_shares;
};

Args parse(int argc, char** argv) {
  Args a;
  a.path = argv[1];
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string o = argv[i], v = argv[i + 1];
    if (o == "--threshold") {
      a.volume.threshold = std::stod(v);
    } else if (o == "--label") {
      a.volume.label = std::stod(v);
    } else if (o == "--voxel-interior-step") {
      a.volume.interior_step = std::stoi(v);
    } else if (o == "--box") {
      a.options.box = std::stod(v);
    } else if (o == "--dmax") {
      a.options.dmax = std::stod(v);
    } else if (o == "--field") {
      a.only_field = v;
    } else if (o == "--csv") {
      a.csv = v;
    } else if (o == "--error-shares") {
      std::stringstream s(v);
      for (std::string item; std::getline(s, item, ',');) a.error_shares.push_back(std::stod(item));
    } else {
      throw std::invalid_argument("unknown option " + o);
    }
  }
  return a;
}

// The input's points in raster order (z, then y, then x slowest first).
std::vector<size_t> raster_order(const dtm::InputMesh& in) {
  std::vector<size_t> raster(in.points.size());
  for (size_t i = 0; i < raster.size(); ++i) raster[i] = i;
  std::stable_sort(raster.begin(), raster.end(), [&](size_t a, size_t b) {
    const auto& p = in.points[a];
    const auto& q = in.points[b];
    return std::tie(p.z, p.y, p.x) < std::tie(q.z, q.y, q.x);
  });
  return raster;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: value_bits FILE [--threshold T | --label L] [--voxel-interior-step K] [--box B] "
                 "[--dmax D] [--field NAME] [--error-shares S1,S2,...] [--csv OUT.csv]\n");
    return 2;
  }
  try {
    const Args args = parse(argc, argv);
    const dtm::InputMesh in = dtm::read_input(args.path, {}, args.volume);
    dtm::EncodeInput input;
    input.points = in.points;
    input.tetrahedra = in.tets;
    if (in.on_grid) input.lattice = &*in.on_grid;
    const dtm::EncodedMesh plain = dtm::encode(input, args.options).value();
    const size_t n = plain.report.levels.front().stats.vertices;
    std::printf(
        "%s: %zu points (%zu input), %zu levels; the positions alone: %zu bytes, %.2f bits per point\n",
        args.path.c_str(), n, in.points.size(), plain.report.streamed_levels.size(), plain.bytes.size(),
        8.0 * static_cast<double>(plain.bytes.size()) / static_cast<double>(n));
    const std::vector<size_t> raster = raster_order(in);
    const std::string model = std::filesystem::path(args.path).stem().string();

    for (const dtm::VertexField& f : in.fields) {
      if (!args.only_field.empty() && f.name != args.only_field) continue;
      const dtm::ValueType type = dtm::value_type(f.type);
      const dtm::EncodeInput::Field field{f.name, type, f.components, f.values};
      input.fields = std::span(&field, 1);
      double lo = 1e300, hi = -1e300;
      for (double v : f.values) lo = std::min(lo, v), hi = std::max(hi, v);
      std::vector<double> shares = {0};
      if (dtm::is_float(type))
        shares.insert(shares.end(), args.error_shares.begin(), args.error_shares.end());
      for (const double share : shares) {
        const double error = share * (hi - lo);
        dtm::EncodeOptions options = args.options;
        if (error > 0) options.field_errors[f.name] = error;
        const dtm::EncodedMesh encoded = dtm::encode(input, options).value();
        // Every value back, exactly or within E (a merged point keeps its first input's).
        dtm::ProgressiveDecoder dec;
        if (!dtm::decode_stream(encoded.bytes, dec).ok())
          throw std::runtime_error("the stream does not decode");
        std::vector<uint8_t> first(n, 1);
        for (size_t i = 0; i < in.points.size(); ++i) {
          const uint32_t v = encoded.vertex_of_input[i];
          if (!first[v]) continue;
          first[v] = 0;
          for (int c = 0; c < f.components; ++c) {
            const double want = f.values[i * f.components + c], got = dec.fields()[0].value(v, c);
            const bool same = error > 0
                                  ? std::abs(got - want) <= error
                                  : dec.fields()[0].bits[v * f.components + c] == dtm::bits_of(want, type);
            if (!same) throw std::runtime_error(f.name + ": point " + std::to_string(i) + " decodes wrong");
          }
        }
        // The baseline: raw values in raster order, in their type (lossy: round(v / 2E) as int32).
        std::string raw;
        for (const size_t i : raster)
          for (int c = 0; c < f.components; ++c) {
            const double v = f.values[i * f.components + c];
            if (error > 0)
              dtm::append_binary(raw, static_cast<int32_t>(std::lround(v / (2 * error))));
            else
              dtm::append_scalar_binary(raw, dtm::bits_of(v, type), f.type);
          }
        const auto [zstd, xz] = baselines(raw);
        const double values = static_cast<double>(in.points.size()) * f.components;
        const double ours = 8.0 * static_cast<double>(encoded.report.fields[0].bytes) /
                            (static_cast<double>(n) * f.components);
        const double zstd_bits = 8.0 * static_cast<double>(zstd) / values,
                     xz_bits = 8.0 * static_cast<double>(xz) / values;
        const double decode_share = extra_decode_share(encoded.bytes, plain.bytes);
        std::printf(
            "field '%s' (%s%s), %s: ours %.3f bits/value, zstd -19 %.3f, xz -9 %.3f, raw %.1f; "
            "ours / better = %.3f; decoding the values adds %.0f%% to decoding the positions\n",
            f.name.c_str(), dtm::value_type_name(type),
            f.components > 1 ? (" x " + std::to_string(f.components)).c_str() : "",
            error > 0 ? ("within E = " + std::to_string(error) + " (" + std::to_string(share) +
                         " of the range; baselines of round(v / 2E) as int32)")
                            .c_str()
                      : "lossless",
            ours, zstd_bits, xz_bits, 8.0 * static_cast<double>(raw.size()) / values,
            ours / std::min(zstd_bits, xz_bits), 100 * decode_share);
        if (!args.csv.empty()) {
          const bool header = !std::filesystem::exists(args.csv);
          std::ofstream csv(args.csv, std::ios::app);
          if (header)
            csv << "model,field,type,components,mode,error_share,error,vertices,ours_bits,zstd_bits,xz_bits,"
                   "ours_over_better,decode_share\n";
          csv << model << "," << f.name << "," << dtm::value_type_name(type) << "," << f.components << ","
              << (error > 0 ? "lossy" : "lossless") << "," << share << "," << error << "," << n << "," << ours
              << "," << zstd_bits << "," << xz_bits << "," << ours / std::min(zstd_bits, xz_bits) << ","
              << decode_share << "\n";
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "value_bits: %s\n", e.what());
    return 1;
  }
  return 0;
}
