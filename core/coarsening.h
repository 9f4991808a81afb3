// Choosing a whole coarser level at once (spec/HIERARCHY.md §6.1): a
// well-spaced subset of about half the level's vertices, the way optimal
// coarsening of unstructured meshes does it (Miller, Talmor, Teng): a
// maximal set of vertices no two of which lie closer than beta times their
// local spacing, grown greedily in a fixed order, with beta chosen so that
// the set holds the share asked for.
//
// * Local spacing h(v): the mean length of the edges of v's carved cells
//   (of its Delaunay edges when it is in none).
// * Conflict: u and v conflict when |uv| < beta (h(u) + h(v)) / 2; the
//   candidates are v's Delaunay neighbours (beta settles near 0.8: a vertex
//   that near is almost always one. Adding their neighbours gave the same
//   levels on bunny_10k and bunny_100k at five times the cost).
// * Order: the boundary vertices that must stay (a surface neighbourhood
//   that is not a disk, or a chord error above D_max: spec §4) first, always
//   kept; then the other boundary vertices by descending chord error (the
//   surface's features before its flat parts); then the interior vertices
//   (and those in no kept cell, outside the solid: they shape nothing) in
//   ascending grid order (a sweep, which packs a maximal set more evenly
//   than the paper's importance order does).
// * beta: searched from the previous level's by secant steps within a
//   bracket until the kept share is within 1% of the target (three or four
//   trials, each one linear pass).
//
// The choice only has to be good, not right: the level built from it is
// checked against every bound, and repaired where one breaks (level_build.h).
#pragma once

#include <cstdint>
#include <vector>

#include "core/level.h"

namespace dtm {

// Where the first level's search for beta starts; each later one starts
// from the previous level's beta.
inline constexpr double kFirstBetaGuess = 0.85;

struct CoarseningOptions {
  double keep_share = 0.5;              // of the level's vertices
  double dmax = 1.0;                    // grid units: the chord error above which a boundary vertex stays
  double beta_guess = kFirstBetaGuess;  // where the search for beta starts (the previous level's)
};

// When a coarser level is accepted, the same for whole levels
// (core/codec_hierarchy.cpp) and for levels built in blocks
// (codec/blocks/bricked_encoder.cpp):
// * the share of a level's vertices a coarser level removes, unless
//   HierarchyOptions::removal_share asks another;
inline constexpr double kDefaultRemovalShare = 0.5;
// * a level that removes less than this share of what is asked is not
//   built: the finer level is the coarsest (a thin level costs more bits
//   than the detail it adds: on the corpus, levels removing 13-14% cost over
//   1% of the stream; those removing 17% and more paid for themselves);
inline constexpr double kThinLevelShare = 0.3;
// * a level that breaks a bound (or comes out thin) is tried once more
//   removing this share of what was asked: coarse levels, where the
//   boundary dominates, often hold the bounds that way.
inline constexpr double kRetryShare = 0.6;

struct Coarsening {
  std::vector<uint8_t> keep;  // per vertex of the level
  uint64_t kept = 0;
  uint64_t fixed = 0;  // boundary vertices that had to stay
  double beta = 0;     // the spacing factor the bisection settled on
};

// `surface` is level_surface(level).
Coarsening choose_coarser(const LevelGeometry& level, const LevelSurface& surface,
                          const CoarseningOptions& options);

// The local spacing h(v) of every vertex (grid units).
std::vector<double> local_spacing(const LevelGeometry& level);

}  // namespace dtm
