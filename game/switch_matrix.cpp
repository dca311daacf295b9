// switch_matrix.cpp — the switch matrix (see switch_matrix.h).
#include "game/switch_matrix.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "engine/core/error.h"
#include "engine/core/worker_pool.h"
#include "engine/loop/clock.h"
#include "game/session.h"

namespace game {
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

}  // namespace

SwitchTrial runSwitchTrial(const levels::Level& level, const robot::RobotModel& model, const robot::SkillSet& skills,
                           const robot::Skill& from, const robot::Skill& to, uint64_t seed) {
  std::mt19937_64 rng(seed);
  const std::vector<char> keysA = movementKeys(from.def.commands), keysB = movementKeys(to.def.commands);
  const char keyA = keysA[size_t(unit(rng) * double(keysA.size()))];
  const char keyB = keysB[size_t(unit(rng) * double(keysB.size()))];
  const TrialPlan plan = planTrial(skills, from, rng);
  const int64_t switchTick = plan.switchTick;
  // no fall for kSwitchAfterSeconds after the switch itself (a stand-up hands over once the robot stands), at most
  // kSwitchMaxWaitSeconds after the key
  const int64_t lastTick = switchTick + engine::secondsToTicks(kSwitchMaxWaitSeconds + kSwitchAfterSeconds);
  int64_t endTick = lastTick;
  const int64_t half = engine::secondsToTicks(kSwitchWindowSeconds / 2);
  const int64_t reference = switchTick - engine::secondsToTicks(1.0);

  Session s(level, model, SessionOptions{seed, &skills});
  SwitchTrial t;
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
      endTick = std::min(lastTick, tick + engine::secondsToTicks(kSwitchAfterSeconds));
    }
  }
  t.switched = t.latencyTicks >= 0 && t.latencyTicks <= double(engine::secondsToTicks(kSwitchMaxWaitSeconds));
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

std::vector<std::pair<const robot::Skill*, const robot::Skill*>> switchPairs(const robot::SkillSet& skills,
                                                                             std::vector<std::string>* untried) {
  std::vector<std::pair<const robot::Skill*, const robot::Skill*>> pairs;
  auto add = [&](const robot::Skill* a, const robot::Skill* b) {
    if (a && b && std::find(pairs.begin(), pairs.end(), std::make_pair(a, b)) == pairs.end()) pairs.push_back({a, b});
  };
  for (const robot::Skill& child : skills.skills)
    if (const robot::Skill* parent = child.def.parent.empty() ? nullptr : skills.byName(child.def.parent)) {
      add(parent, &child);
      const robot::Skill* up = skills.upFrom(child);
      // a ground skill hands a lying robot only to another ground skill or to its stand-up skill
      if (!child.def.up.empty() && !up)
        untried->push_back(child.def.name + " -> " + child.def.up + ": no model for " + child.def.up + " yet");
      else if (up && !robot::mayHandOver(child.def, up->def))
        untried->push_back(child.def.name + " -> " + up->def.name + ": not a direct switch (lying down, it stands up " +
                           (child.def.up.empty() ? "through a stand-up skill, which the tree does not have yet)"
                                                 : "through " + child.def.up + ", which has no model yet)"));
      else
        add(&child, up);
    }
  return pairs;
}

double SwitchRow::successPercent() const {
  int ok = 0;
  for (const SwitchTrial& t : trials) ok += t.switched && t.upright;
  return trials.empty() ? 0.0 : 100.0 * ok / double(trials.size());
}

SwitchMatrix runSwitchMatrix(const levels::Level& level, const robot::RobotModel& model, const robot::SkillSet& skills,
                             const SwitchMatrixOptions& o) {
  SwitchMatrix m;
  const auto pairs = switchPairs(skills, &m.untried);
  m.allowed = pairs.size();
  if (pairs.empty())
    throw engine::Error("eval switches: no two connected skills have models yet (loaded: " +
                        std::to_string(skills.skills.size()) + "); train a branch first");
  auto selected = [&](const auto& pr) {
    auto among = [&](const std::string& name) {
      return o.anyOf.empty() || std::find(o.anyOf.begin(), o.anyOf.end(), name) != o.anyOf.end();
    };
    return (o.only.empty() || pr.first->def.name == o.only || pr.second->def.name == o.only) &&
           (among(pr.first->def.name) || among(pr.second->def.name));
  };
  if (!o.only.empty()) {
    if (!skills.byName(o.only))
      throw engine::Error("eval switches --only " + o.only + ": no such skill with a model (see `treelearn tree`)");
    if (std::count_if(pairs.begin(), pairs.end(), selected) == 0)
      throw engine::Error("eval switches --only " + o.only +
                          ": the skill has no allowed switch with a model at the other end");
  }
  engine::WorkerPool pool(o.threads);
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (!selected(pairs[p])) continue;  // each kept pair's trials keep their seeds (p counts every pair)
    SwitchRow row{pairs[p].first, pairs[p].second, std::vector<SwitchTrial>(size_t(o.trials))};
    pool.parallelFor(o.trials, [&](int i) {
      row.trials[size_t(i)] =
          runSwitchTrial(level, model, skills, *row.from, *row.to, o.seed * 1000003 + p * 1009 + uint64_t(i));
    });
    m.rows.push_back(std::move(row));
  }
  return m;
}

}  // namespace game
