// walk_card.h — the walk skill's report card (issue 3): episodes on flat ground with pushes and commands
// changing every 5 s, measured in physics with the deterministic policy. Figures are compared against bars.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "robot/skill_tree.h"

namespace ai {

/// A deterministic policy: observations (obsSize x batch) -> actions (actSize x batch).
using PolicyFn = std::function<void(const Eigen::MatrixXf& observations, Eigen::MatrixXf* actions)>;

struct WalkCardOptions {
  int episodes = 50;             ///< walking episodes
  double episodeSeconds = 20.0;  ///< each with a new command every segmentSeconds
  double segmentSeconds = 5.0;
  double settleSeconds = 1.0;    ///< tracking error is not counted this long after a command change
  int standEpisodes = 10;        ///< zero-command episodes (no pushes)
  double standSeconds = 10.0;
  uint64_t seed = 1;
  int threads = 2;
};

/// One line of a card.
struct CardFigure {
  std::string name;
  double value = 0;
  std::string bar;  ///< e.g. "<= 0.15 m/s"
  bool pass = false;
};

struct CardResult {
  std::vector<CardFigure> figures;
  bool pass = false;
  /// A fitness for model selection during training: higher is better (no-fall rate minus tracking errors).
  double score = 0;
};

/// Runs the card. Commands: forward -0.6..1.2 m/s, sideways +-0.4 m/s, turn +-1 rad/s, or zero, one at a time.
CardResult runWalkCard(const robot::RobotModel& model, const robot::SkillDef& walk, const PolicyFn& policy,
                       const WalkCardOptions& options);

}  // namespace ai
