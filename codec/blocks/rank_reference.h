// The reference solid of a bricked encoding as the ranks of a run hold it
// (codec/blocks/bricked_encoder.h): its solid (the input's tetrahedra, or
// level 0's carving, or a scan's voxels) and its boundary triangles by
// place, whole on one process; on ranks, the boundary whole and the solid
// in parts (codec/blocks/reference_share.h), a block's questions about the
// parts answered by the other ranks (codec/blocks/reference_questions.h).
// Either way a block is carved to the same verdicts.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "codec/blocks/block_levels.h"
#include "codec/blocks/block_runs.h"
#include "codec/blocks/reference_questions.h"
#include "common/exchange.h"
#include "common/grid.h"
#include "common/progress.h"
#include "common/status.h"
#include "core/reference_solid.h"
#include "core/region_solid.h"
#include "core/solid.h"

namespace dtm {

class ReferenceShare;

class RankReference {
 public:
  // `voxels`: a scan's solid, or nullptr; `on_phase` is told each phase.
  RankReference(std::span<const GridPoint> points, int qbits, RankExchange& exchange, const Solid* voxels,
                PhaseCallback on_phase);

  // The reference from its tetrahedra, on this process alone. `tets` are
  // read while this runs only. With `regions` (per tetrahedron, 1 + its
  // region's index; core/region_solid.h) a cell's verdict is its region,
  // and the boundary holds the interfaces between regions too.
  void set_whole(std::span<const std::array<uint32_t, 4>> tets, std::span<const uint8_t> regions = {});
  // The same on the ranks of a run, each given at least its share of the
  // tetrahedra (`share`, or one made from the exchange when null), with
  // their `regions` as set_whole() takes them (or none) from a table of
  // `region_count` (the same on every rank): each finds the boundary faces
  // and the tetrahedra near the boundary that are its own, a region at a
  // time, and every rank gets the boundary whole. The verdicts and the
  // boundary are the ones one process makes. `tets_done` is called once
  // `given` is read no more.
  void set_in_parts(std::span<const std::array<uint32_t, 4>> given, std::span<const uint8_t> regions,
                    size_t region_count, const ReferenceShare* share, const std::function<void()>& tets_done);

  // Whether there is a boundary to measure against (none before level 0 is
  // built when level 0, carved by alpha or voxels, is the reference).
  bool has_boundary() const { return faces_.has_value(); }
  // What a block of `region` is carved to (`solid`: the one run_carving()
  // handed its work) and, `measured`, measured against (the boundary near
  // it); none without a solid. Safe to call from several threads.
  std::optional<BlockReference> for_region(const GridBox& region, const Solid* solid,
                                           bool measured = true) const;
  // run_blocks() of work carving to the reference: with the reference in
  // parts, the other ranks answer what a block's part cannot, while they
  // work (else each block's work is run again until they answered all it
  // asked).
  // `at_once`: run_blocks'.
  std::vector<std::vector<uint8_t>> run_carving(
      const BlockPlan& plan, const std::function<StatusOr<std::vector<uint8_t>>(size_t, const Solid*)>& work,
      Status& status, int at_once);
  // A level's questions are of its own cells: the answers of the level
  // before are forgotten.
  void start_level() { book_ = {}; }
  const QuestionCount& questions() const { return questions_; }
  // What it holds freed, once no block carves any more (before the stream
  // is written): called on every rank at once (the thread answering the
  // other ranks stops at a barrier).
  void release_all();

 private:
  std::span<const GridPoint> points_;
  int qbits_;
  RankExchange& x_;
  const Solid* voxels_;
  PhaseCallback on_phase_;
  std::optional<ReferenceSolid> tet_solid_;  // whole
  std::optional<RegionSolid> region_solid_;  // whole, with regions
  const Solid* solid_ = nullptr;             // one of them, or the voxels
  std::optional<ReferenceParts> parts_;      // on ranks: this rank's parts (no solid_ then)
  AnswerBook book_;                          // what the ranks answered of this level's questions
  QuestionCount questions_;
  std::optional<TriangleIndex> faces_;
  // The other ranks' questions answered from this rank's part while it
  // works, and its own asked (null where the exchange cannot: then asked
  // in the exchanges). Made last, so gone before the part it reads.
  std::unique_ptr<RankAnswers> answers_;
  // The boundary whole, made the first time a block's region meets all of
  // it (a level of one block, level after level) and kept for the next.
  mutable std::mutex whole_mutex_;
  mutable std::shared_ptr<const ReferenceBoundary> whole_;
};

}  // namespace dtm
