#include "tool/variant_race.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

using ism::tool::VariantRace;

namespace {

// Each map's scores after its levels, reported one report at a time in
// `order` (a sequence of map indices; a map finishes after its last score).
// Returns which maps the race dropped.
std::vector<char> run_race(const std::vector<std::vector<double>>& scores,
                           const std::vector<std::size_t>& order, std::size_t decide_at,
                           double margin) {
  VariantRace race(scores.size(), decide_at, margin);
  std::vector<std::size_t> next(scores.size(), 0);
  std::vector<char> stopped(scores.size(), 0);
  for (std::size_t i : order) {
    if (stopped[i] || next[i] >= scores[i].size()) continue;
    if (!race.report(i, scores[i][next[i]++])) stopped[i] = 1;
    if (!stopped[i] && next[i] == scores[i].size()) race.finish(i);
  }
  std::vector<char> out(scores.size());
  for (std::size_t i = 0; i < scores.size(); ++i) {
    out[i] = race.dropped(i);
    EXPECT_FALSE(stopped[i] && !out[i]) << "map " << i << " told to stop but not dropped";
  }
  return out;
}

// One interleaving of the maps' reports, at random.
std::vector<std::size_t> shuffled(const std::vector<std::vector<double>>& scores,
                                  std::mt19937& rng) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < scores.size(); ++i) order.insert(order.end(), scores[i].size(), i);
  std::shuffle(order.begin(), order.end(), rng);
  return order;
}

}  // namespace

TEST(VariantRace, DropsAMapBehindAtEveryLevelUpToTheDecision) {
  const std::vector<std::vector<double>> scores{{0.76, 0.763, 0.766, 0.77},
                                                {0.72, 0.729, 0.731, 0.74}};
  std::mt19937 rng(1);
  for (int trial = 0; trial < 50; ++trial) {
    const auto dropped = run_race(scores, shuffled(scores, rng), 1, 0.01);
    EXPECT_EQ(dropped, (std::vector<char>{0, 1}));
  }
  VariantRace race(2, 1, 0.01);
  EXPECT_TRUE(race.scoring());
  EXPECT_TRUE(race.report(1, 0.72));
  EXPECT_TRUE(race.report(1, 0.729));  // (map 0 has not reported: undecided)
  EXPECT_FALSE(race.drop(1));
  EXPECT_TRUE(race.report(0, 0.76));
  EXPECT_TRUE(race.report(0, 0.763));  // decided: map 1 dropped, map 0 goes on
  EXPECT_FALSE(race.scoring());
  EXPECT_FALSE(race.report(1, 0.731));
  EXPECT_TRUE(race.report(0, 0.766));
  const auto drop = race.drop(1);
  ASSERT_TRUE(drop);
  EXPECT_EQ(drop->checkpoint, 1u);
  EXPECT_DOUBLE_EQ(drop->score, 0.729);
  EXPECT_DOUBLE_EQ(drop->leader, 0.763);
  EXPECT_FALSE(race.drop(0));
}

TEST(VariantRace, KeepsMapsCloseOrAheadAtAnyLevel) {
  std::mt19937 rng(2);
  // Behind by more than the margin at level 1 only; within it at level 0;
  // ahead at level 0 (fandisk's volatile scores: results-gim.md).
  for (const auto& scores :
       std::vector<std::vector<std::vector<double>>>{{{0.80, 0.85, 0.9}, {0.795, 0.80, 0.7}},
                                                     {{0.80, 0.85}, {0.81, 0.80}},
                                                     {{0.80, 0.81}, {0.80, 0.81}}}) {
    for (int trial = 0; trial < 20; ++trial)
      EXPECT_EQ(run_race(scores, shuffled(scores, rng), 1, 0.01), (std::vector<char>{0, 0}));
  }
  // A negative margin: scores taken, nothing dropped.
  const std::vector<std::vector<double>> apart{{0.9, 0.9, 0.9}, {0.1, 0.1, 0.1}};
  EXPECT_EQ(run_race(apart, {0, 1, 0, 1, 0, 1}, 1, -1), (std::vector<char>{0, 0}));
  EXPECT_EQ(run_race(apart, {0, 1, 0, 1, 0, 1}, 1, 0.01), (std::vector<char>{0, 1}));
}

TEST(VariantRace, TheDecisionWaitsForEveryMapAndIgnoresTheOrderOfReports) {
  // A map that finishes (or fails) before the decision's level takes no
  // part; the others are judged once it has finished.
  {
    VariantRace race(3, 1, 0.01);
    EXPECT_TRUE(race.report(0, 0.9));
    EXPECT_TRUE(race.report(0, 0.9));
    EXPECT_TRUE(race.report(1, 0.5));
    EXPECT_TRUE(race.report(1, 0.5));
    EXPECT_TRUE(race.report(2, 0.95));  // map 2 stops after one level
    EXPECT_TRUE(race.scoring());
    race.finish(2);
    EXPECT_FALSE(race.scoring());
    EXPECT_FALSE(race.dropped(0));
    EXPECT_TRUE(race.dropped(1));
    EXPECT_FALSE(race.dropped(2));
    EXPECT_FALSE(race.report(1, 0.6));
  }
  // Five maps with random scores, every order of reports: the same maps
  // dropped, never the leader at the decision, never all.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> score(0.6, 0.66);
  for (int set = 0; set < 30; ++set) {
    std::vector<std::vector<double>> scores(5);
    for (auto& s : scores)
      for (int level = 0; level < 4; ++level) s.push_back(score(rng));
    std::size_t leader = 0;
    for (std::size_t i = 1; i < scores.size(); ++i)
      if (scores[i][1] > scores[leader][1]) leader = i;
    const auto first = run_race(scores, shuffled(scores, rng), 1, 0.01);
    EXPECT_FALSE(first[leader]);
    for (int trial = 0; trial < 20; ++trial)
      EXPECT_EQ(run_race(scores, shuffled(scores, rng), 1, 0.01), first);
    for (std::size_t z = 0; z < scores.size(); ++z) {
      bool behind_someone = false;
      for (std::size_t w = 0; w < scores.size(); ++w)
        behind_someone |= scores[w][0] > scores[z][0] + 0.01 && scores[w][1] > scores[z][1] + 0.01;
      EXPECT_EQ(bool(first[z]), behind_someone) << "set " << set << " map " << z;
    }
  }
}
