#pragma once
// Map variants refined side by side, the ones clearly behind stopped early
// (the map stage's: tool/map_stage.hpp).
#include <cstddef>
#include <mutex>
#include <optional>
#include <vector>

namespace ism::tool {

/// The race between the maps a map stage refines side by side. Each reports
/// its score after every level of its refinement (checkpoints 0, 1, ...).
/// Once every map has reported checkpoint `decide_at` (or finished without
/// it, or failed), the race is decided once: a map whose score was below
/// another's by more than `margin` at every checkpoint 0..decide_at is
/// dropped (a map that finished before the decision too: the caller leaves
/// it out all the same). Which maps are dropped depends on the scores only,
/// never on the order or the times the reports arrive; the map leading at
/// `decide_at` is never dropped. Thread-safe.
class VariantRace {
 public:
  /// `maps` racing (indices 0..maps-1). margin < 0: scores are taken as
  /// usual but nothing is dropped.
  VariantRace(std::size_t maps, std::size_t decide_at, double margin);

  /// Map i's score at its next checkpoint. False: i is dropped (stop it).
  bool report(std::size_t i, double score);
  /// Whether map i still needs scores (the race is undecided): true until
  /// the decision, so scores need not be computed after it.
  bool scoring() const;
  /// Map i reports no more (refined whole, failed, or never started).
  void finish(std::size_t i);
  bool dropped(std::size_t i) const;

  /// For a dropped map: the checkpoint decided at, its score there and the
  /// leader's (the highest score there).
  struct Drop {
    std::size_t checkpoint;
    double score, leader;
  };
  std::optional<Drop> drop(std::size_t i) const;

 private:
  void try_decide();  // (mutex_ held)

  mutable std::mutex mutex_;
  std::size_t decide_at_;
  double margin_;
  bool decided_ = false;
  std::vector<std::vector<double>> scores_;
  std::vector<char> finished_, dropped_;
  double leader_ = 0;
};

}  // namespace ism::tool
