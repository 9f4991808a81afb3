// value_bits: what the level-by-level value coder (codec/value_coder.h)
// spends on an input's per-vertex fields, beside zstd -19 and xz -9 of the
// same values stored raw in the input's order (raster order, x fastest, for a
// voxel volume). Issue 13's measurement, before the values are in the stream.
//
//   value_bits FILE [--threshold T | --label L] [--voxel-interior-step K]
//              [--box B] [--dmax D] [--raw-type i16|u16|i32|f32|f64]
//              [--error-share S]
//
// Positions are encoded as meshenc would (codec preset), the stream decoded
// for the decoder's point order and layers, and every field's values coded
// layer by layer in that order. --raw-type says how the baselines store a
// value (default: i16 when every value fits, else f64). --error-share S codes
// the fields lossily within E = S x their range (codec/value_coder.h
// quantize_within), against zstd -19 of round(v / 2E) as int32.
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/value_coder.h"
#include "tools/formats/input.h"

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

template <class T>
void append(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: value_bits FILE [--threshold T | --label L] [--voxel-interior-step K] "
                 "[--box B] [--dmax D] [--raw-type i16|u16|i32|f32|f64]\n");
    return 2;
  }
  const std::string path = argv[1];
  dtm::VolumeOptions volume;
  dtm::EncodeOptions options;
  std::string raw_type;
  double error_share = 0;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--threshold")
      volume.threshold = std::stod(v);
    else if (a == "--label")
      volume.label = std::stod(v);
    else if (a == "--voxel-interior-step")
      volume.interior_step = std::stoi(v);
    else if (a == "--box")
      options.box = std::stod(v);
    else if (a == "--dmax")
      options.dmax = std::stod(v);
    else if (a == "--raw-type")
      raw_type = v;
    else if (a == "--error-share")
      error_share = std::stod(v);
    else {
      std::fprintf(stderr, "value_bits: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  try {
    const dtm::InputMesh in = dtm::read_input(path, {}, volume);
    if (in.fields.empty()) {
      std::fprintf(stderr, "value_bits: %s has no per-vertex field\n", path.c_str());
      return 1;
    }
    dtm::EncodeInput input;
    input.points = in.points;
    input.tetrahedra = in.tets;
    if (in.on_grid) input.lattice = &*in.on_grid;
    const dtm::EncodedMesh encoded = dtm::encode(input, options).value();
    // The decoder's order and layers.
    std::vector<dtm::GridPoint> points;
    std::vector<size_t> layer_ends;
    dtm::ProgressiveDecoder decoder;
    if (!decoder
             .feed(encoded.bytes, [&](const dtm::ProgressiveDecoder& d,
                                      const dtm::DecodedLevel&) { layer_ends.push_back(d.points().size()); })
             .ok())
      throw std::runtime_error("the stream does not decode");
    points = decoder.points();
    const size_t n = points.size();
    // Decoding the positions to the finest mesh, the best of three (the
    // yardstick for decoding the values).
    auto seconds = [](auto&& f) {
      double best = 1e300;
      for (int k = 0; k < 3; ++k) {
        const auto start = std::chrono::steady_clock::now();
        f();
        best =
            std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      return best;
    };
    const double position_seconds = seconds([&] {
      dtm::ProgressiveDecoder d;
      if (!d.feed(encoded.bytes).ok() || d.carved_cells().empty()) throw std::runtime_error("decode failed");
    });
    std::printf("%s: %zu points (%zu input), %zu layers, positions %zu bytes (%.2f bits per point)\n",
                path.c_str(), n, in.points.size(), layer_ends.size(), encoded.bytes.size(),
                8.0 * static_cast<double>(encoded.bytes.size()) / static_cast<double>(n));

    // Raster order of the input points (z, then y, then x slowest first).
    std::vector<size_t> raster(in.points.size());
    for (size_t i = 0; i < raster.size(); ++i) raster[i] = i;
    std::stable_sort(raster.begin(), raster.end(), [&](size_t a, size_t b) {
      const auto& p = in.points[a];
      const auto& q = in.points[b];
      return std::tie(p.z, p.y, p.x) < std::tie(q.z, q.y, q.x);
    });

    for (const dtm::VertexField& f : in.fields) {
      for (int c = 0; c < f.components; ++c) {
        const auto value = [&](size_t i) { return f.values[i * f.components + c]; };
        bool integral = true, fits16 = true, fits_u16 = true;
        for (size_t i = 0; i < in.points.size(); ++i) {
          const double v = value(i);
          integral = integral && v == std::floor(v) && std::abs(v) < 9e15;
          fits16 = fits16 && v >= -32768 && v <= 32767;
          fits_u16 = fits_u16 && v >= 0 && v <= 65535;
        }
        std::string type = raw_type;
        if (type.empty())
          type = integral && fits16 ? "i16" : integral && fits_u16 ? "u16" : integral ? "i32" : "f64";
        const dtm::ValueType vt = type == "f32"   ? dtm::ValueType::kF32
                                  : type == "f64" ? dtm::ValueType::kF64
                                                  : dtm::ValueType::kI32;
        auto ordered_of = [&](double v) {
          if (vt == dtm::ValueType::kF32)
            return dtm::to_ordered(std::bit_cast<uint32_t>(static_cast<float>(v)), vt);
          if (vt == dtm::ValueType::kF64) return dtm::to_ordered(std::bit_cast<uint64_t>(v), vt);
          return dtm::Int128{static_cast<int64_t>(v)};
        };
        // Values in the decoder's order (a merged point takes its first input's).
        std::vector<dtm::Int128> by_vertex(n, 0);
        std::vector<double> doubles(n, 0);
        std::vector<uint8_t> seen(n, 0);
        for (size_t i = 0; i < in.points.size(); ++i) {
          const uint32_t v = encoded.vertex_of_input[i];
          if (!seen[v]) by_vertex[v] = ordered_of(value(i)), doubles[v] = value(i), seen[v] = 1;
        }
        double error = 0;
        dtm::LossyScale lossy;
        if (error_share > 0) {
          const auto [lo, hi] = std::minmax_element(doubles.begin(), doubles.end());
          error = error_share * (*hi - *lo);
          by_vertex = dtm::quantize_within(doubles, error, type == "f32", lossy).value();
        }
        const dtm::ValueScale scale = dtm::value_scale(by_vertex);
        dtm::ValueEncoder enc(scale);
        dtm::ValueDecoder dec(scale);
        size_t bytes = 0, begin = 0;
        std::vector<size_t> per_layer;
        std::vector<std::vector<uint8_t>> sections;
        for (const size_t end : layer_ends) {
          const std::span<const dtm::GridPoint> lp(points.data() + begin, end - begin);
          const std::span<const dtm::Int128> lv(by_vertex.data() + begin, end - begin);
          const std::vector<uint8_t> section = enc.encode_layer(lp, lv);
          std::vector<dtm::Int128> back;
          if (!dec.decode_layer(section, lp, back).ok() || !std::equal(back.begin(), back.end(), lv.begin()))
            throw std::runtime_error("the values do not round-trip");
          bytes += section.size();
          per_layer.push_back(section.size());
          sections.push_back(section);
          begin = end;
        }
        const double value_seconds = seconds([&] {
          dtm::ValueDecoder d(scale);
          std::vector<dtm::Int128> back;
          size_t from = 0;
          for (size_t k = 0; k < sections.size(); ++k) {
            if (!d.decode_layer(sections[k], std::span(points.data() + from, layer_ends[k] - from), back)
                     .ok())
              throw std::runtime_error("the values do not decode");
            from = layer_ends[k];
          }
        });
        // The baselines: the raw values in raster order.
        std::string raw;
        for (const size_t i : raster) {
          const double v = value(i);
          if (error > 0)
            append(raw, static_cast<int32_t>(std::lround(v / (2 * error))));
          else if (type == "i16")
            append(raw, static_cast<int16_t>(v));
          else if (type == "u16")
            append(raw, static_cast<uint16_t>(v));
          else if (type == "i32")
            append(raw, static_cast<int32_t>(v));
          else if (type == "f32")
            append(raw, static_cast<float>(v));
          else
            append(raw, v);
        }
        const std::string tmp =
            (std::filesystem::temp_directory_path() / ("value_bits_" + std::to_string(getpid()) + ".raw"))
                .string();
        std::ofstream(tmp, std::ios::binary).write(raw.data(), static_cast<std::streamsize>(raw.size()));
        const long zstd = compressed_size("zstd -19 -q -c", tmp), xz = compressed_size("xz -9 -c", tmp);
        std::filesystem::remove(tmp);
        const double m = static_cast<double>(in.points.size());
        const double ours = 8.0 * static_cast<double>(bytes) / static_cast<double>(n);
        const double best = 8.0 * static_cast<double>(std::min(zstd, xz)) / m;
        if (error > 0)
          std::printf("lossy, E = %g (%g of the range; baseline values round(v / 2E) as int32): ", error,
                      error_share);
        std::printf(
            "field %s[%d] (%s, gcd %lld): ours %.3f bits/value, zstd -19 %.3f, xz -9 %.3f, raw %.1f; "
            "ours / better = %.3f; per layer (coarsest first):",
            f.name.c_str(), c, type.c_str(), static_cast<long long>(scale.step), ours, 8.0 * zstd / m,
            8.0 * xz / m, 8.0 * static_cast<double>(raw.size()) / m, ours / best);
        begin = 0;
        for (size_t k = 0; k < per_layer.size(); ++k) {
          std::printf(" %.2f",
                      8.0 * static_cast<double>(per_layer[k]) / static_cast<double>(layer_ends[k] - begin));
          begin = layer_ends[k];
        }
        std::printf("; decoding them takes %.0f%% of decoding the positions to the finest mesh",
                    100 * value_seconds / position_seconds);
        std::printf("\n");
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "value_bits: %s\n", e.what());
    return 1;
  }
  return 0;
}
