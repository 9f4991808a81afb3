// Per-vertex values coded level by level: one component's values, as a
// layer's value section carries them (codec/sections/value_fields.h puts a stream's
// fields together). Encoder and decoder side by side, sharing the predictor.
//
// Values are integers that order like the originals (to_ordered below: the
// integers as they are, floats by the fpzip map of their bits), shifted by
// the smallest value and divided by the greatest common divisor of the
// shifts (CT numbers in steps of 10 cost log2(10) bits less each). Points
// arrive layer by layer, coarsest first, in the order the decoder produces
// them; each value is predicted from the values of the kValueNeighbours
// nearest points already coded (every coarser level's, and this layer's
// earlier ones), weighted by inverse squared distance in exact integer
// arithmetic, or pulled toward the mean of every value coded so far (each
// layer says which: noisy data such as a CT's predict better from the mean),
// and the residual is range-coded: zero flag, sign, magnitude class in
// unary, two modelled mantissa bits, the rest raw. Contexts: how
// far apart the neighbours' values are. The models carry over from layer to
// layer, as the values do.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "mesh/geometry.h"

namespace dtm {

// How a field's values are stored: integers of 8 to 64 bits, IEEE floats.
enum class ValueType : uint8_t { kI8, kU8, kI16, kU16, kI32, kU32, kI64, kU64, kF32, kF64 };

// The order-preserving integer of a value given by its bits (the integer's
// two's complement bits, or the float's IEEE bits), and back. Floats: NaNs
// and infinities included, bit for bit.
Int128 to_ordered(uint64_t bits, ValueType type);
uint64_t from_ordered(Int128 ordered, ValueType type);

// What the whole field shares, sent once: its smallest ordered value and the
// gcd of every value's distance from it (1 when all values are equal).
struct ValueScale {
  Int128 offset = 0;
  Int128 step = 1;
};
ValueScale value_scale(std::span<const Int128> ordered);

// Lossy coding of a float field with a guaranteed bound E: each value v
// becomes the integer q = round((v - origin) / (2E)), coded losslessly, and
// decodes to origin + q * 2E, within E of v, in the field's own type (the
// encoder checks it value by value and takes q +- 1 where rounding would
// break the bound). kInvalidInput naming the first vertex for a NaN or an
// infinity, or for a bound too small for the values' magnitude.
struct LossyScale {
  double origin = 0;
  double step = 1;  // 2E
};
StatusOr<std::vector<Int128>> quantize_within(std::span<const double> values, double error, bool float32,
                                              LossyScale& scale);
double dequantize(Int128 q, const LossyScale& scale, bool float32);

inline constexpr int kValueNeighbours = 8;

// How a layer predicts: from the neighbours, halfway between them and the
// mean of the values so far, or the mean alone. The encoder tries each.
enum class ValueMode : uint8_t { kNeighbours = 0, kHalfway = 1, kMean = 2 };
inline constexpr int kValueModes = 3;
inline constexpr int kValueSpreadContexts = 6;
inline constexpr int kValueClassModels = 24;

// The nearest points already known to a point about to be coded: their
// indices (in the order they became known) and squared grid distances,
// nearest first, ties to the earlier known.
struct Neighbours {
  std::array<uint32_t, kValueNeighbours> index{};
  std::array<int64_t, kValueNeighbours> d2{};
  int count = 0;
};

// The points coded so far, searchable by place. The neighbours depend on the
// positions alone, which the decoder has before any value: one search serves
// every component of every field.
class NeighbourSearch {
 public:
  // The neighbours of every point of a layer, each among the points known
  // before it (every coarser layer's and this layer's earlier ones); the
  // layer's points are then known.
  std::vector<Neighbours> layer(std::span<const GridPoint> points);
  // Points known before any layer is coded, without searching theirs (a
  // bricked chunk's: the coarser levels' points in its brick).
  void know(std::span<const GridPoint> points);

 private:
  // Sizes the grid for the points known and the layer's.
  void prepare(std::span<const GridPoint> incoming);
  // The nearest among the first `known` points (in coding order).
  Neighbours nearest(const GridPoint& p, uint32_t known) const;
  void add(const GridPoint& p);
  std::array<int64_t, 3> cell_of(const GridPoint& p) const;
  size_t bucket(const std::array<int64_t, 3>& c) const {
    return static_cast<size_t>((c[2] * dims_[1] + c[1]) * dims_[0] + c[0]);
  }
  std::vector<GridPoint> points_;
  // A uniform grid of the known points over the box of every point known or
  // about to be: cells of edge cell_ (grid units), about two points each. The
  // points known when the layer began are stored cell by cell, contiguous
  // with their coordinates (cell_start_ indexes settled_); the layer's own,
  // as they come, in recent_.
  struct Entry {
    GridPoint p;
    uint32_t index;
  };
  std::array<int64_t, 3> origin_{}, dims_{1, 1, 1};
  int64_t cell_ = 1;
  std::vector<uint32_t> cell_start_;
  std::vector<Entry> settled_;
  std::vector<std::vector<Entry>> recent_;
};

// One component's (scaled) values coded so far and its adaptive models: the
// state encoder and decoder keep in step.
class ValuePredictor {
 public:
  // The prediction of the next value and its context, from its neighbours' values.
  struct Prediction {
    Int128 neighbours = 0;  // the inverse-distance mean of the nearest values
    Int128 mean = 0;        // the mean of every value known
    int context = 0;
    Int128 value(ValueMode mode) const {
      return mode == ValueMode::kNeighbours ? neighbours
             : mode == ValueMode::kMean     ? mean
                                            : (neighbours + mean) / 2;
    }
  };
  Prediction predict(const Neighbours& n) const;
  void add(Int128 value);

  struct Models;
  Models& models() { return *models_; }
  ValuePredictor();
  ~ValuePredictor();
  ValuePredictor(ValuePredictor&&) noexcept;
  ValuePredictor& operator=(ValuePredictor&&) noexcept;

 private:
  std::vector<Int128> values_;
  Int128 sum_ = 0;
  std::unique_ptr<Models> models_;
};

class ValueEncoder {
 public:
  explicit ValueEncoder(ValueScale scale) : scale_(scale) {}
  // The block of one layer: the values (ordered integers) of its new
  // points, in the decoder's order, given their neighbours.
  std::vector<uint8_t> encode_layer(std::span<const Neighbours> neighbours, std::span<const Int128> ordered);
  // The same for a component coded alone: it searches the neighbours itself.
  std::vector<uint8_t> encode_layer(std::span<const GridPoint> points, std::span<const Int128> ordered) {
    return encode_layer(own_search_.layer(points), ordered);
  }
  // Values known before the first layer (ordered integers, in the order
  // their points became known to the search): the prediction's, uncoded.
  void know(std::span<const Int128> ordered);

 private:
  ValueScale scale_;
  ValuePredictor predictor_;
  NeighbourSearch own_search_;
};

class ValueDecoder {
 public:
  // A scaled value above `max_scaled` is damage (the type's range, known
  // from the field table, bounds it), and so is one at 2^65 or beyond.
  explicit ValueDecoder(ValueScale scale, Int128 max_scaled = Int128{1} << 65)
      : scale_(scale), max_scaled_(max_scaled) {}
  // The ordered values of a layer's new points from its block, given their
  // neighbours; kCorrupt if the block ends early, has bytes left over or
  // decodes out of range.
  Status decode_layer(std::span<const uint8_t> block, std::span<const Neighbours> neighbours,
                      std::vector<Int128>& ordered);
  // The same for a component coded alone.
  Status decode_layer(std::span<const uint8_t> block, std::span<const GridPoint> points,
                      std::vector<Int128>& ordered) {
    return decode_layer(block, own_search_.layer(points), ordered);
  }
  // As ValueEncoder::know.
  void know(std::span<const Int128> ordered);

 private:
  ValueScale scale_;
  Int128 max_scaled_;
  ValuePredictor predictor_;
  NeighbourSearch own_search_;
};

}  // namespace dtm
