// skill_card.h — a skill's report card as `eval`, `ship` and training's evaluations run it: the skill in its tree,
// the models that drive the card's other stages (a lead-in, the parent that lies down first, the stand-up's way up),
// the card of whichever kind, and its text.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ai/eval/ground_card.h"
#include "ai/eval/velocity_card.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/tree/training_tree.h"
#include "robot/robot_model.h"

namespace ai {

/// A skill of the tree file, with the robot model and the tree it comes from.
struct SkillContext {
  robot::RobotModel model;
  TrainingTree tree;
  const SkillSpec* skill = nullptr;
};

/// The skill `name` of the tree file the apps use (robot::defaultSkillTreePath) on the default robot; an unknown
/// name is an error that lists the tree's skills.
SkillContext loadSkillContext(const std::string& name);

/// The way a handover into `skill` goes in play: handover_from (or the parent) first, then each skill down to the
/// parent (walk, one_leg for the kick).
std::vector<const SkillSpec*> handoverRoute(const TrainingTree& tree, const SkillSpec& skill);

/// The skills that drive a card's other stages: a ground card's parent (it lies down first) and a standup card's up
/// skill (it takes over once the robot stands); a lead_in card's route; none for the other kinds.
struct CardDrivers {
  DrivingSkill before, after;
  std::vector<HandoverStage> leadIn;  ///< handover_from (or the parent), then the skills between
};
/// Loads the drivers' models from `modelsDir`, each checked against its tree entry; a missing one is an error that
/// says which skill to train first.
CardDrivers loadCardDrivers(const SkillContext& l, const std::string& modelsDir);

/// Runs the skill's card, whichever kind.
CardResult runSkillCard(const SkillContext& l, const PolicyFn& act, const CardRun& run, const CardDrivers& drivers);

/// The card's figures as `eval` prints and records them, ending in CARD PASSED or CARD FAILED.
std::string cardText(const CardResult& card);

/// The card's first line: what it runs and on which model (`modelShown`, its `hash`).
std::string cardHead(const SkillContext& l, const CardRun& run, const std::string& modelShown, const std::string& hash);

/// The skill's ONNX model at `path`, checked as play and eval check it (sizes, the tree entry's controller settings).
std::unique_ptr<LoadedPolicy> loadSkillModel(const SkillContext& l, const std::string& path);

}  // namespace ai
