// velocity_card.h — the report card of a velocity-commanded skill (walk, run): randomised episodes on flat
// ground with pushes and commands changing every segment, measured in physics with the deterministic policy.
// The card's episodes, command mix and bars come from the skill's [card] table in the tree file.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "ai/env/skill_env.h"
#include "ai/tree/training_tree.h"
#include "robot/skill_layout.h"

namespace ai {

/// A deterministic policy: observations (obsSize x batch) -> actions (actSize x batch).
using PolicyFn = std::function<void(const Eigen::MatrixXf& observations, Eigen::MatrixXf* actions)>;

/// How to run a card: the tree file's card definition plus the run's seed and threads.
struct CardRun {
  CardDef card;
  uint64_t seed = 1;
  int threads = 2;
  /// Under mpirun, the ranks that share the card's episodes (ai/eval/card_ranks.h; every rank gets the same figures,
  /// the bits one process gets); null: one process.
  const dist::Comm* comm = nullptr;
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

/// Runs a velocity or height card (CardKind::Velocity / Height, and the other driven kinds). Commands are one of
/// forward, sideways, turn or zero at a time (the keyboard's interlock), drawn with the card's mix. With `leadIn` (the
/// card's lead_in: the skills that drive first, as in the skill's training handover episodes, see runHandover) each
/// randomised episode starts where that route leaves the robot. Results do not depend on the thread count.
CardResult runVelocityCard(const robot::RobotModel& model, const SkillSpec& skill, const PolicyFn& policy,
                           const CardRun& run, const std::vector<HandoverStage>& leadIn = {});

/// One row of a speed sweep: a fixed command held for the whole episode, no pushes, friction 1.
struct SweepRow {
  robot::SkillCommand command;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  ///< achieved vx, vy (heading frame) and wz after 1 s
  bool fell = false;
  double secondsUp = 0;
};

/// Holds each command for `seconds` and reports what the policy achieved: where a card's tracking error comes from.
std::vector<SweepRow> runSpeedSweep(const robot::RobotModel& model, const SkillSpec& walk, const PolicyFn& policy,
                                    const std::vector<robot::SkillCommand>& commands, double seconds, int threads);

}  // namespace ai
