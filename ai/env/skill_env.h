// skill_env.h — N G1 environments for training one skill (a VecEnv): each its own Bullet world, stepped on
// all cores. Per step: the skill runtime's act (robot/skill_runtime.h: filtered action, clock, prior, a handover's
// fade -> PD targets) -> its physics tick -> reward terms, fall/time-out checks, automatic reset, the command one tick
// on -> the runtime's observe. Commands, pushes and randomisation come from the skill-tree entry.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "ai/dist/comm.h"
#include "ai/env/vec_env.h"
#include "ai/rewards/reward_terms.h"
#include "ai/tree/training_tree.h"
#include "engine/core/worker_pool.h"
#include "levels/level.h"
#include "robot/entry_state.h"
#include "robot/skill_runtime.h"

namespace ai {

/// A skill that drives part of an episode before the skill being trained or measured takes over, with its
/// deterministic policy (observations x batch -> actions x batch; called from worker threads: thread-safe).
struct HandoverStage {
  const SkillSpec* skill = nullptr;
  std::function<void(const Eigen::MatrixXf&, Eigen::MatrixXf*)> policy;
};

/// A handover's skills as the runtime runs them: the stages in route order, then the skill taking over (its policy
/// runs outside: it is being trained or measured), in one robot::SkillSet so that the tree routes between them.
struct HandoverRoute {
  robot::SkillSet set;
  const SkillSpec* driver = nullptr;           ///< stage 0's training tables (how its drive is drawn)
  const SkillSpec* destinationSpec = nullptr;  ///< the destination's (its handover settings)
  const robot::Skill& destination() const { return set.skills.back(); }
};
HandoverRoute makeHandoverRoute(const std::vector<HandoverStage>& stages, const SkillSpec& destination);

/// One handover into the route's destination `skill` as a player makes it in play, through the skill runtime
/// (robot::route, robot::shapeCommand, robot::controlStep): stage 0 takes the robot from the standing controller (a
/// key-pose skill after kMinHopTicks, as play enters it) and drives at `skill.handoverVx` held (or one random draw
/// from its command ranges, the keys ramping there) for a random `skill.handoverSeconds`; then the next stage's key is
/// pressed, the movement keys released when the destination is a still skill (held otherwise), and the runtime makes
/// the switch when its rules allow (brake, posture, cycle, phase); each stage after the first runs
/// `skill.handoverViaSeconds` at no movement key before the next key. `nominal` is the model the observations use,
/// `actual` the (randomised) one the PD targets use. `robot` starts as placed; `sensors` is updated. On success
/// *state holds the runtime as the destination takes over (its clock carried, the filtered action, the prior fading
/// out) and *commandAtSwitch the command at the switch. Returns false if the robot fell on the way, or a switch
/// waited longer than kMaxHandoverWaitTicks.
constexpr int kMaxHandoverWaitTicks = 600;
bool runHandover(const robot::RobotModel& nominal, const robot::RobotModel& actual, engine::PhysicsWorld& world,
                 robot::Robot& robot, robot::Sensors* sensors, const HandoverRoute& route, std::mt19937_64& rng,
                 robot::SkillState* state, robot::SkillCommand* commandAtSwitch);

struct SkillEnvOptions {
  int numEnvs = 20;
  /// Under mpirun, this rank's share of the run's environments (dist::envShare): the run's environments
  /// [firstEnv, firstEnv + numEnvs) of runEnvs (0: numEnvs), each seeded as one process seeds it, and the ranks
  /// (the curriculum measures every rank's episodes). One process: the defaults.
  int firstEnv = 0;
  int runEnvs = 0;
  const dist::Comm* comm = nullptr;
  int threads = 2;
  bool randomise = true;  ///< friction, added mass and pushes as the skill says (off = nominal robot, no pushes)
  /// handover episodes (the skill's training.handover > 0): the parent's tree entry and its deterministic policy
  /// (observations x batch -> actions x batch; called from the worker threads, so it must be thread-safe)
  const SkillSpec* parent = nullptr;
  std::function<void(const Eigen::MatrixXf&, Eigen::MatrixXf*)> parentPolicy;
  /// the skills a handover episode routes through after the parent (handover_from an ancestor further up: the
  /// one-leg stand between walk and kick), in route order
  std::vector<HandoverStage> via;
  /// handover episodes from a child (the skill's training.handover_back > 0): the child's tree entry and policy
  HandoverStage back;
};

/// Statistics of one environment's current episode, for evaluation.
struct EpisodeStats {
  int ticks = 0;
  double speedErrorSum = 0;  ///< sum over ticks of |v_xy - v_cmd_xy| [m/s]
  double yawErrorSum = 0;    ///< sum over ticks of |wz - wz_cmd| [rad/s]
};

/// A play episode ([training] play_share) runs its entry's segment and this much more [s] (a segment that ended in
/// a fall in play ends there: the episode then shows what follows it).
constexpr double kPlayEpisodeMarginSeconds = 2.0;

class SkillEnv final : public VecEnv {
 public:
  SkillEnv(const robot::RobotModel& model, const SkillSpec& skill, const std::string& treePath,
           const SkillEnvOptions& options);
  ~SkillEnv() override;

  int numEnvs() const override { return int(envs_.size()); }
  int globalEnvs() const override { return options_.runEnvs > 0 ? options_.runEnvs : numEnvs(); }
  int globalColumn(int n) const override { return options_.firstEnv + n; }
  int observationSize() const override { return robot::kObservationSize; }
  int actionSize() const override { return robot::kActionSize; }
  std::vector<std::string> rewardTermNames() const override;
  void reset(uint64_t seed, Eigen::MatrixXf* observations) override;
  void step(const Eigen::MatrixXf& actions, StepResult* result) override;
  void endRollout() override;

  /// Seconds spent inside physics (substeps) during step() calls so far, summed over threads.
  double physicsSeconds() const;

  /// Curriculum (terrain lessons, or a command curriculum: CurriculumDef), measured at the end of each
  /// rollout: every episode of the rollout (fallen, timed out, or cut by the rollout's end) scores its return
  /// per tick it could have played (up to the time limit or the rollout's end, so a fall counts as zero for the
  /// rest), episodes that could have played less than 1 s (or the time limit, if shorter) are skipped, and the
  /// lesson moves on for the next rollout when the lesson's bias-corrected exponential average of the scores
  /// (curriculumScore, weight 0.02 per episode) passes the curriculum's advance_at, after at least two episodes
  /// per environment. (Measured per time-limit step
  /// alone, a time limit longer than the rollout, such as the walk's 20 s against 10.24 s, left only falls to
  /// count, and no lesson ever passed.)
  int curriculumLesson() const override { return lesson_; }
  std::string curriculumNote() const override;
  std::string saveState() const override;
  void loadState(const std::string& bytes) override;
  /// The current lesson's average episode score (see above; 0 before its first episode).
  double curriculumScore() const;
  /// The step height of the current lesson (0 on flat terrain).
  double stepHeight() const;
  /// The skill as the current lesson trains it (a command curriculum's forward top, T1 and stride applied).
  const SkillSpec& lessonSkill() const { return skill_; }

 private:
  struct Env;
  void resetEnv(Env& e, bool allowHandover = true);
  void startFromEntry(Env& e, double friction);  // a play episode (playEntries_)
  void playCommand(Env& e) const;                // a play episode's keys one tick on, shaped as play does
  bool handOver(Env& e, bool back, robot::SkillCommand* commandAtSwitch);
  void sampleCommand(Env& e);
  void steerCommand(Env& e) const;
  void advanceCommand(Env& e) const;
  void observe(const Env& e, float* out) const;
  int lessonCount() const;
  double advanceAt() const;
  void applyLesson();  // a command curriculum's values for lesson_ into skill_

  robot::RobotModel model_;
  SkillSpec skill_;             // the tree entry with the current lesson applied (see applyLesson)
  SkillSpec treeSkill_;         // the tree entry as written
  SkillSpec parent_;            // handover episodes only: the skill that drives first
  std::vector<SkillSpec> via_;  // ... the skills routed through after it
  SkillSpec backChild_;         // handover episodes from a child: the child that drives first
  SkillSpec backSkill_;         // ... and this skill as that route switches into it (handover_back_s as its drive)
  robot::Skill trainee_;        // skill_ as the runtime runs it (its policy runs outside, batched)
  // play episodes: the skill's handover states, their levels by path, and the tree's skills (a fading prior's)
  std::vector<robot::EntryState> playEntries_;
  std::map<std::string, std::unique_ptr<levels::Level>> playLevels_;
  robot::SkillSet playSet_;
  HandoverRoute route_, backRoute_;  // parent_ then via_ into skill_; backChild_ into backSkill_
  void makeRoutes();
  std::vector<WeightedTerm> terms_;
  SkillEnvOptions options_;
  engine::WorkerPool pool_;
  std::vector<std::unique_ptr<Env>> envs_;
  int lesson_ = 0;
  double smoothed_ = 0;     // exponential average (from 0, not bias-corrected) of this lesson's episode scores
  int lessonEpisodes_ = 0;  // episodes finished on the current lesson
  struct Finished {         // an episode of the current rollout, for the curriculum
    double episodeReturn;
    int startStep;  // rollout step it began at
    int endStep;    // rollout step it ended at (the rollout's steps: cut by the rollout's end)
    int env;        // the run's environment
  };
  std::vector<Finished> finished_;  // in environment order per step
  int rolloutSteps_ = 0;            // steps since the last reset()
};

}  // namespace ai
