// switches.cpp — the skills as `play` loads them, and `treelearn eval switches`: every allowed switch (each
// tree edge, both directions) tried at random moments and commands through the real runtime (a Session on
// levels/flat driven by key events), with its success rate and how much the switch disturbs the motion.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>

#include "ai/env/worker_pool.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/onnx/skill_metadata.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/loop/clock.h"
#include "game/session.h"
#include "levels/level.h"

namespace apps {

robot::SkillSet loadSkills(const robot::RobotModel& model) {
  robot::SkillSet set;
  const robot::SkillTree tree = robot::loadSkillTree(robot::defaultSkillTreePath(), model);
  engine::Hasher h;
  const std::string treeText = engine::readFile(tree.path);
  h.bytes(treeText.data(), treeText.size());
  for (const robot::SkillDef& def : tree.skills) {
    const std::string path = tree.directory + "/" + def.model;
    if (!std::filesystem::exists(path)) {
      set.missing.push_back({def.name, def.key, path});
      continue;
    }
    auto policy = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(path));
    if (policy->observationSize() != robot::kObservationSize || policy->actionSize() != robot::kActionSize)
      throw engine::Error(path + ": network sizes do not match the shared observation/action layout");
    ai::checkModelMatchesSkill(*policy, path, model, def, tree.path);
    h.value(ai::onnxFileHash(path));
    set.skills.push_back({def, [policy](const Eigen::MatrixXf& o, Eigen::MatrixXf* a) { policy->act(o, a); }});
  }
  set.hash = set.skills.empty() ? 0 : h.value();
  return set;
}

namespace {

double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

// the movement keys a skill's command ranges give meaning to, plus "no key"
std::vector<char> movementKeys(const robot::CommandDef& c) {
  std::vector<char> keys = {0};
  if (c.vx.hi > 0) keys.push_back('W');
  if (c.vx.lo < 0) keys.push_back('S');
  if (c.vy.lo < 0 || c.vy.hi > 0) keys.insert(keys.end(), {'Q', 'E'});
  if (c.wz.lo < 0 || c.wz.hi > 0) keys.insert(keys.end(), {'A', 'D'});
  return keys;
}

struct Trial {
  bool switched = false, upright = false;
  double accelAround = 0, accelBefore = 0;   // peak |d v_CoM / dt| [m/s^2] around the switch / 1 s earlier
  double targetAround = 0, targetBefore = 0;  // peak per-tick joint-target change [rad]
  double latencyTicks = -1;                   // key tick -> tick the new skill first acts
  char keyBefore = 0, keyAfter = 0;           // the movement keys held before and after the switch (0: none)
  int64_t switchTick = 0, fallTick = -1;      // the switch key's tick; the tick the robot was down (-1: never)
  std::string fallSkill;                      // the skill driving when it fell, and how it lay
  double fallHeight = 0, fallPitchDeg = 0, fallLeanDeg = 0;
};

constexpr double kWindowSeconds = 0.2;  // the window around the switch (and the earlier reference window)
constexpr double kAfterSeconds = 3.0;   // no fall for this long after the switch
constexpr double kMaxWaitSeconds = 6.0;  // a switch may wait this long after its key (a stand-up: until it stands)

// The moments of a trial's key taps. A skill entered lying down (the stand-up: its parent is a ground skill) is
// reached as in play: its parent's key at 0 and its own once the parent has lain down. A ground skill is left once
// it lies (3-5 s: prone lies face down from ~2.2 s); an upright one at a random gait phase 2-4 s in.
struct TrialPlan {
  char firstKey = 0, secondKey = 0;  // tapped at 0 and at secondTick (0: none)
  int64_t secondTick = 0, switchTick = 0;
};

TrialPlan planTrial(const robot::SkillSet& skills, const robot::Skill& from, std::mt19937_64& rng) {
  TrialPlan p;
  const robot::Skill* parent = from.def.parent.empty() ? nullptr : skills.byName(from.def.parent);
  const bool entersLying = parent && robot::isGroundSkill(parent->def);
  p.firstKey = char('0' + skills.requestKey(entersLying ? *parent : from));
  if (entersLying) {
    p.secondKey = char('0' + skills.requestKey(from));
    p.secondTick = engine::secondsToTicks(3.5);
    p.switchTick = p.secondTick + engine::secondsToTicks(1.0 + 3.0 * unit(rng));  // the stand-up waits for the stand
  } else {
    p.switchTick = engine::secondsToTicks((robot::isGroundSkill(from.def) ? 3.0 : 2.0) + 2.0 * unit(rng));
  }
  return p;
}

Trial runTrial(const levels::Level& level, const robot::RobotModel& model, const robot::SkillSet& skills,
               const robot::Skill& from, const robot::Skill& to, uint64_t seed) {
  std::mt19937_64 rng(seed);
  const std::vector<char> keysA = movementKeys(from.def.commands), keysB = movementKeys(to.def.commands);
  const char keyA = keysA[size_t(unit(rng) * double(keysA.size()))];
  const char keyB = keysB[size_t(unit(rng) * double(keysB.size()))];
  const TrialPlan plan = planTrial(skills, from, rng);
  const int64_t switchTick = plan.switchTick;
  // no fall for kAfterSeconds after the switch itself (a stand-up hands over once the robot stands), at most
  // kMaxWaitSeconds after the key
  const int64_t lastTick = switchTick + engine::secondsToTicks(kMaxWaitSeconds + kAfterSeconds);
  int64_t endTick = lastTick;
  const int64_t half = engine::secondsToTicks(kWindowSeconds / 2);
  const int64_t reference = switchTick - engine::secondsToTicks(1.0);

  game::Session s(level, model, game::SessionOptions{seed, &skills});
  Trial t;
  t.keyBefore = keyA, t.keyAfter = keyB, t.switchTick = switchTick;
  Eigen::Vector3d lastCom = s.sensors().centreOfMass, lastVel = Eigen::Vector3d::Zero();
  robot::JointArray lastTarget = s.robot().command().target;
  for (int64_t tick = 0; tick < endTick && !s.fallen(); ++tick) {
    std::vector<engine::KeyEvent> ev;
    if (tick == 0) ev.push_back({tick, engine::KeyAction::kTap, plan.firstKey});
    if (plan.secondKey && tick == plan.secondTick) ev.push_back({tick, engine::KeyAction::kTap, plan.secondKey});
    if (tick == engine::secondsToTicks(0.5) && keyA) ev.push_back({tick, engine::KeyAction::kDown, keyA});
    if (tick == switchTick) {
      if (keyA) ev.push_back({tick, engine::KeyAction::kUp, keyA});
      ev.push_back({tick, engine::KeyAction::kTap, char('0' + skills.requestKey(to))});
      if (keyB) ev.push_back({tick, engine::KeyAction::kDown, keyB});
    }
    s.step(ev);
    const Eigen::Vector3d com = s.sensors().centreOfMass;
    const Eigen::Vector3d vel = (com - lastCom) / engine::kTickSeconds;
    const double accel = tick > 0 ? (vel - lastVel).norm() / engine::kTickSeconds : 0.0;
    double targetStep = 0;
    for (size_t j = 0; j < lastTarget.size(); ++j)
      targetStep = std::max(targetStep, std::abs(s.robot().command().target[j] - lastTarget[j]));
    lastCom = com, lastVel = vel, lastTarget = s.robot().command().target;
    if (std::abs(tick - switchTick) <= half) {
      t.accelAround = std::max(t.accelAround, accel);
      t.targetAround = std::max(t.targetAround, targetStep);
    }
    if (std::abs(tick - reference) <= half) {
      t.accelBefore = std::max(t.accelBefore, accel);
      t.targetBefore = std::max(t.targetBefore, targetStep);
    }
    if (t.latencyTicks < 0 && tick >= switchTick && s.activeSkillName() == to.def.name) {
      t.latencyTicks = double(tick - switchTick);
      endTick = std::min(lastTick, tick + engine::secondsToTicks(kAfterSeconds));
    }
  }
  t.switched = t.latencyTicks >= 0 && t.latencyTicks <= double(engine::secondsToTicks(kMaxWaitSeconds));
  t.upright = !s.fallen();
  if (!t.upright) {
    t.fallTick = s.tick();
    t.fallSkill = s.activeSkillName();
    t.fallHeight = s.sensors().basePosition.z();
    t.fallPitchDeg = robot::forwardPitch(s.sensors()) * 180.0 / M_PI;
    t.fallLeanDeg = robot::sideLean(s.sensors()) * 180.0 / M_PI;
  }
  return t;
}

}  // namespace

int runSwitchEval(const SwitchEvalOptions& o) {
  const robot::RobotModel model = robot::loadRobotModel(engine::projectFile("assets/robots/g1_23dof.toml"));
  const robot::SkillSet skills = loadSkills(model);
  const levels::Level level = levels::loadLevel(engine::projectFile("levels/flat"));
  std::vector<std::pair<const robot::Skill*, const robot::Skill*>> pairs;
  // each edge down the tree (parent -> child) and each way up (child -> its parent, or -> its `up` skill: prone
  // goes up through standup), for the skills with models
  auto add = [&](const robot::Skill* a, const robot::Skill* b) {
    if (a && b && std::find(pairs.begin(), pairs.end(), std::make_pair(a, b)) == pairs.end()) pairs.push_back({a, b});
  };
  std::vector<std::string> untried;
  for (const robot::Skill& child : skills.skills)
    if (const robot::Skill* parent = child.def.parent.empty() ? nullptr : skills.byName(child.def.parent)) {
      add(parent, &child);
      const robot::Skill* up = skills.upFrom(child);
      // a ground skill hands a lying robot only to another ground skill or to its stand-up skill
      if (!child.def.up.empty() && !up)
        untried.push_back(child.def.name + " -> " + child.def.up + ": no model for " + child.def.up + " yet");
      else if (up && !robot::mayHandOver(child.def, up->def))
        untried.push_back(child.def.name + " -> " + up->def.name + ": not a direct switch (lying down, it stands up " +
                          (child.def.up.empty() ? "through a stand-up skill, which the tree does not have yet)"
                                                : "through " + child.def.up + ", which has no model yet)"));
      else add(&child, up);
    }
  if (pairs.empty())
    throw engine::Error("eval switches: no two connected skills have models yet (loaded: " +
                        std::to_string(skills.skills.size()) + "); train a branch first");
  size_t selected = pairs.size();
  if (!o.only.empty()) {
    if (!skills.byName(o.only))
      throw engine::Error("eval switches --only " + o.only + ": no such skill with a model (see `treelearn tree`)");
    selected = size_t(std::count_if(pairs.begin(), pairs.end(), [&](const auto& pr) {
      return pr.first->def.name == o.only || pr.second->def.name == o.only;
    }));
    if (selected == 0) throw engine::Error("eval switches --only " + o.only + ": the skill has no allowed switch with a model at the other end");
  }
  std::printf("switch report: %zu allowed switches%s x %d trials on levels/flat (random moment 2-4 s, from lying 3-5 s, "
              "out of a stand-up 1-4 s into it; random movement keys before and after; success = switched within %.0f s "
              "of the key and no fall for %.0f s after the switch)\n",
              selected, o.only.empty() ? "" : (" (of " + std::to_string(pairs.size()) + ", those of " + o.only + ")").c_str(),
              o.trials, kMaxWaitSeconds, kAfterSeconds);
  std::printf("  %-22s %8s %9s   %-27s %-27s\n", "switch", "success", "latency", "peak CoM accel [m/s^2]",
              "peak target step [rad]");
  std::printf("  %-22s %8s %9s   %-27s %-27s\n", "", "", "[ticks]", "around switch / 1 s before", "around switch / 1 s before");
  ai::WorkerPool pool(o.threads);
  bool pass = true;
  double worstLatency = 0;
  for (size_t p = 0; p < pairs.size(); ++p) {
    // --only: the others are skipped, each kept pair's trials keep their seeds (p counts every pair)
    if (!o.only.empty() && pairs[p].first->def.name != o.only && pairs[p].second->def.name != o.only) continue;
    std::vector<Trial> trials(size_t(o.trials));
    pool.parallelFor(o.trials, [&](int i) {
      trials[size_t(i)] = runTrial(level, model, skills, *pairs[p].first, *pairs[p].second, o.seed * 1000003 + p * 1009 + uint64_t(i));
    });
    int ok = 0;
    double accA = 0, accB = 0, tgtA = 0, tgtB = 0, latency = 0;
    for (const Trial& t : trials) {
      ok += t.switched && t.upright;
      accA = std::max(accA, t.accelAround), accB = std::max(accB, t.accelBefore);
      tgtA = std::max(tgtA, t.targetAround), tgtB = std::max(tgtB, t.targetBefore);
      latency = std::max(latency, t.latencyTicks);
    }
    worstLatency = std::max(worstLatency, latency);
    const double rate = 100.0 * ok / o.trials;
    const bool good = rate >= o.barPercent;
    pass = pass && good;
    const std::string name = pairs[p].first->def.name + " -> " + pairs[p].second->def.name;
    std::printf("  %-22s %7.0f%% %9.0f   %12.1f / %-12.1f %12.3f / %-12.3f %s\n", name.c_str(), rate, latency, accA, accB,
                tgtA, tgtB, good ? "PASS" : "FAIL");
    if (o.verbose)
      for (size_t i = 0; i < trials.size(); ++i) {
        const Trial& t = trials[i];
        if (t.switched && t.upright) continue;
        auto key = [](char k) { return k ? std::string(1, k) : std::string("none"); };
        char fate[160];
        if (t.upright) std::snprintf(fate, sizeof fate, "never switched");
        else if (t.fallTick < t.switchTick)
          std::snprintf(fate, sizeof fate, "fell %.2f s before the key under %s", double(t.switchTick - t.fallTick) * engine::kTickSeconds,
                        t.fallSkill.c_str());
        else
          std::snprintf(fate, sizeof fate, "fell %.2f s after the key under %s (pelvis %.2f m, forward pitch %.0f deg, side lean %.0f deg)",
                        double(t.fallTick - t.switchTick) * engine::kTickSeconds, t.fallSkill.c_str(), t.fallHeight,
                        t.fallPitchDeg, t.fallLeanDeg);
        char trialLatency[32] = "none";
        if (t.switched) std::snprintf(trialLatency, sizeof trialLatency, "%.0f ticks", t.latencyTicks);
        std::printf("      trial %zu: key %s before, %s after, switch key at %.2f s, latency %s, %s\n", i,
                    key(t.keyBefore).c_str(), key(t.keyAfter).c_str(), double(t.switchTick) * engine::kTickSeconds,
                    trialLatency, fate);
      }
  }
  for (const std::string& u : untried) std::printf("  %s\n", u.c_str());
  std::printf("  worst switch latency: %.0f ticks (%.0f ms) from the key to the new skill's first control step\n",
              worstLatency, worstLatency * engine::kTickSeconds * 1000);
  std::printf("  %s (bar: >= %.0f %% success on every switch)\n", pass ? "SWITCHES PASSED" : "SWITCHES FAILED", o.barPercent);
  return pass ? 0 : 1;
}

}  // namespace apps
