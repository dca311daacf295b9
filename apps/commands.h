// commands.h — the subcommands of the treelearn program (apps/ is the only layer that prints and exits).
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ai/ppo/checkpoint.h"
#include "ai/ppo/ppo.h"
#include "ai/train/train_multi.h"
#include "ai/train/train_skill.h"
#include "robot/skill_runtime.h"
#include "robot/skill_tree.h"

namespace apps {

/// `treelearn bench` options.
struct BenchOptions {
  double seconds = 20.0;   ///< simulated seconds per physics measurement
  int frames = 300;        ///< frames per rendering measurement
  std::string csv;         ///< optional CSV output path
  int autopilotSeeds = 0;  ///< also play levels/mario by autopilot at seeds 1..N (wins, times, falls)
  int variants = 0;  ///< also play variants 1..N of levels/mario by autopilot (levels/variant.h), variant N at seed N
  int gardens = 0;   ///< also play levels/garden at seeds 1..N and garden layouts 1..N for 240 s each by autopilot
};

/// Runs the benchmarks and prints a table; returns the exit code.
int runBench(const BenchOptions& options);

/// `treelearn train` options: the training's (ai::TrainSkillOptions), the skill, and --export-only.
struct TrainOptions : ai::TrainSkillOptions {
  std::string skill;
  bool exportOnly = false;
  std::string exportFrom = "best";  ///< --export-only source: best (best.bin) or last (checkpoint.bin)
};

/// `treelearn eval` options.
struct EvalOptions {
  std::string skill;
  std::string model;  ///< ONNX file to evaluate (default: the skill's shipped model)
  int episodes = 0;   ///< 0 = the card's own count
  uint64_t seed = 1;
  int threads = 2;
  bool sweep = false;        ///< print achieved against commanded speeds instead of the card
  bool verbose = false;      ///< switches: list every failed trial
  bool priorOnly = false;    ///< the card with zero network output: what the skill's prior does by itself
  std::string samplePolicy;  ///< policy file: the card with actions drawn from its Gaussian, as training acts
  std::string only;          ///< switches: only the switches into or out of this skill
  double steer = -1;         ///< >= 0: a stairs or crawl card's steer in place of the tree file's (0: unsteered)
  std::string multitask;     ///< a multi-task run folder: the card of its one network, told the skill by its one-hot
  int rewards = 0;  ///< > 0: instead of the card, the rewards in the skill's training episodes, this many rollouts
};

/// `treelearn entries record` options.
struct EntriesRecordOptions {
  std::string level = "levels/mario";     ///< the game level played
  uint64_t firstSeed = 1, lastSeed = 20;  ///< autopilot seeds
  std::vector<std::string> keys;          ///< key scripts also played (a path, or a file name inside the level folder)
  std::string out = "runs/entries";       ///< folder for SKILL.entries
  int threads = 2;
};
/// Plays the runs, records every handover (game/entry_recorder.h) and writes OUT/SKILL.entries per skill.
int runEntriesRecord(const EntriesRecordOptions& options);

/// `treelearn entries card` options.
struct EntriesCardOptions {
  std::string dir;    ///< folder holding SKILL.entries files
  std::string skill;  ///< only this skill ("" = every skill with an entries file)
  std::string model;  ///< ONNX file to use as `skill`'s model instead of the shipped one
  int threads = 2;
  bool verbose = false;  ///< list the entries that fell
};
/// Prints each skill's play-entry card (game/entry_card.h) beside its own card's recorded figure.
int runEntriesCard(const EntriesCardOptions& options);

/// `treelearn ship` options.
struct ShipOptions {
  std::string skill;
  std::string runDir;  ///< the run folder holding SKILL.onnx and SKILL.policy.bin (default runs/SKILL)
  bool force = false;  ///< install even when the card fails
  int threads = 2;
};

/// `treelearn eval switches` options.
struct SwitchEvalOptions {
  int trials = 10;  ///< per ordered pair
  uint64_t seed = 1;
  int threads = 2;
  double barPercent = 95.0;  ///< success needed on every pair
  bool verbose = false;      ///< list every failed trial (keys, moment, latency, when it fell)
  std::string only;          ///< only the switches into or out of this skill (each trial as in the full run)
};

/// Runs every allowed switch (tree edges, both directions) and prints the report; exit 0 when all pass.
int runSwitchEval(const SwitchEvalOptions& options);

/// Every skill of the tree whose ONNX model exists, loaded once (models checked against their tree entries);
/// the set's hash covers the tree file and the models. `models` gives other files for some skills (skill name ->
/// ONNX path), in place of the tree folder's.
robot::SkillSet loadSkills(const robot::RobotModel& model, const std::map<std::string, std::string>& models = {});

int runTrain(const TrainOptions& options);
/// `treelearn experiment compare` options (apps/experiment.cpp).
struct ExperimentOptions {
  std::string out = "runs/compare";
  double stepsScale = 1.0;  ///< 1: the paper's 10^7 steps per skill
  int seeds = 1;
  int threads = 2;
  int rewardEnvs = 20, rewardRollouts = 2;  ///< the rewards measure (ai::measureRewards)
  int cardEpisodes = 0;                     ///< 0: each card's own count
  int switchTrials = 10;                    ///< trials per switch of the tree arm's switch matrix
};
/// Trains the arms that are not done yet (resuming the ones begun) and measures every final policy into
/// OUT/results.csv.
int runExperimentCompare(const ExperimentOptions& options);

/// `treelearn multitask`: one network on several skills at once (ai::trainMultiTask).
int runMultiTask(const ai::TrainMultiOptions& options);
/// `treelearn tree`: the skill tree with parents, keys, model hashes and each shipped model's recorded card.
int runTree();
/// Where `treelearn eval SKILL` keeps the shipped model's card: assets/skills/SKILL.card.txt.
std::string cardRecordPath(const ai::TrainingTree& tree, const robot::SkillDef& skill);
int runExport(const TrainOptions& options);
/// `treelearn ship SKILL --from RUN`: runs the skill's card on RUN's exported model and, when it passes (or with
/// force), installs RUN/SKILL.onnx and RUN/SKILL.policy.bin into the tree's folder and records the card there.
int runShip(const ShipOptions& options);
int runEval(const EvalOptions& options);
/// `treelearn eval all`: every skill's card, then the switches; exit 0 when everything passes.
int runEvalAll(const EvalOptions& options);

}  // namespace apps
