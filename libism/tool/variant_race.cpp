#include "tool/variant_race.hpp"

#include <algorithm>
#include <cmath>

namespace ism::tool {

VariantRace::VariantRace(std::size_t maps, std::size_t decide_at, double margin)
    : decide_at_(decide_at),
      margin_(margin),
      scores_(maps),
      finished_(maps, 0),
      dropped_(maps, 0) {}

bool VariantRace::report(std::size_t i, double score) {
  const std::lock_guard lock(mutex_);
  if (decided_) return !dropped_.at(i);
  scores_.at(i).push_back(score);
  try_decide();
  return !dropped_[i];
}

bool VariantRace::scoring() const {
  const std::lock_guard lock(mutex_);
  return !decided_;
}

void VariantRace::finish(std::size_t i) {
  const std::lock_guard lock(mutex_);
  finished_.at(i) = 1;
  if (!decided_) try_decide();
}

bool VariantRace::dropped(std::size_t i) const {
  const std::lock_guard lock(mutex_);
  return dropped_.at(i);
}

std::optional<VariantRace::Drop> VariantRace::drop(std::size_t i) const {
  const std::lock_guard lock(mutex_);
  if (!dropped_.at(i)) return std::nullopt;
  return Drop{decide_at_, scores_[i][decide_at_], leader_};
}

void VariantRace::try_decide() {
  const std::size_t n = scores_.size();
  auto reached = [&](std::size_t i) { return scores_[i].size() > decide_at_; };
  for (std::size_t i = 0; i < n; ++i)
    if (!reached(i) && !finished_[i]) return;  // (not every map has reported yet)
  decided_ = true;
  if (!(margin_ >= 0)) return;  // (scores taken, nothing dropped)
  leader_ = -HUGE_VAL;
  for (std::size_t i = 0; i < n; ++i)
    if (reached(i)) leader_ = std::max(leader_, scores_[i][decide_at_]);
  for (std::size_t z = 0; z < n; ++z) {
    if (!reached(z)) continue;
    for (std::size_t w = 0; w < n && !dropped_[z]; ++w) {
      if (w == z || !reached(w)) continue;
      bool behind = true;
      for (std::size_t c = 0; c <= decide_at_ && behind; ++c)
        behind = scores_[w][c] > scores_[z][c] + margin_;
      dropped_[z] = behind;
    }
  }
}

}  // namespace ism::tool
