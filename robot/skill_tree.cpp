// skill_tree.cpp — strict TOML loader for the runtime's part of the skill tree: a parser per table it owns
// (parsePrior, parseGains, parseActionScale, parseCommands, parseTermination), called by parseSkill, then the checks
// that need the whole tree (checkParentsAndKeys, checkAncestry) and the inheritance of controller tables. The tables
// training owns are ai/tree/training_tree.cpp's; this loader only checks that a skill has no other tables.
#include "robot/skill_tree.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "robot/tree_reader.h"

namespace robot {
namespace {

using engine::Error;
using engine::located;

const char* const kGroups[] = {"hip_pitch",     "hip_roll",     "hip_yaw",   "knee",
                               "ankle_pitch",   "ankle_roll",   "waist_yaw", "shoulder_pitch",
                               "shoulder_roll", "shoulder_yaw", "elbow",     "wrist_roll"};

// A per-joint-group table: group = value (or [kp, kd] when b is given)
void groups(const TreeReader& r, const toml::table& t, const std::string& where, const RobotModel& model, JointArray* a,
            JointArray* b, double lo, double hi) {
  for (auto&& [k, v] : t) {
    const std::string group(k.str());
    bool known = false;
    for (const char* g : kGroups)  // "knee" means both knees, "left_knee" only the left one
      known = known || group == g || group == std::string("left_") + g || group == std::string("right_") + g;
    if (!known) throw Error(located(r.file, r.line(v), where + ": unknown joint group '" + group + "'"));
    double x, y = 0;
    if (b) {
      const toml::array* arr = v.as_array();
      if (!arr || arr->size() != 2) throw Error(located(r.file, r.line(v), where + "." + group + " must be [kp, kd]"));
      x = r.number((*arr)[0], where + "." + group, lo, hi);
      y = r.number((*arr)[1], where + "." + group, lo, hi);
    } else {
      x = r.number(v, where + "." + group, lo, hi);
    }
    for (size_t j = 0; j < size_t(kNumJoints); ++j)
      if (jointInGroup(model.joints[j].name, group)) {
        (*a)[j] = x;
        if (b) (*b)[j] = y;
      }
  }
}

// [prior] type: the kind of prior
PriorDef::Kind priorKind(const TreeReader& r, const toml::table& p, const std::string& where) {
  const std::string type =
      p.get("type") && p.get("type")->value<std::string>() ? *p.get("type")->value<std::string>() : "";
  if (type == "phase") return PriorDef::Kind::Phase;
  if (type == "pose") return PriorDef::Kind::Pose;
  if (type == "jump") return PriorDef::Kind::Jump;
  if (type == "kick") return PriorDef::Kind::Kick;
  if (type == "keyframes") return PriorDef::Kind::Keyframes;
  if (type == "none") return PriorDef::Kind::None;
  throw Error(
      located(r.file, r.line(p),
              where + ".prior.type must be \"phase\", \"pose\", \"jump\", \"kick\", \"keyframes\" or \"none\""));
}

// [prior] offset, swing, late, turn (joint-group tables) and crouch: which kinds need or allow them
void parsePriorPoses(const TreeReader& r, const toml::table& p, const std::string& where, const RobotModel& model,
                     PriorDef* prior) {
  const toml::node* offset = p.get("offset");
  const bool needsOffset =
      prior->kind == PriorDef::Kind::Pose || prior->kind == PriorDef::Kind::Jump || prior->kind == PriorDef::Kind::Kick;
  if (needsOffset != (offset != nullptr))
    throw Error(located(
        r.file, r.line(p),
        where + ".prior: \"pose\", \"jump\" and \"kick\" priors need offset = { group = rad, ... }, and only they"));
  const toml::node* swing = p.get("swing");
  if ((prior->kind == PriorDef::Kind::Kick) != (swing != nullptr))
    throw Error(
        located(r.file, r.line(p), where + ".prior: a \"kick\" prior needs swing = { group = rad, ... }, and only it"));
  if (swing) {
    if (!swing->as_table())
      throw Error(located(r.file, r.line(*swing), where + ".prior.swing must be a table of joint groups"));
    groups(r, *swing->as_table(), where + ".prior.swing", model, &prior->swingOffset, nullptr, -3, 3);
  }
  if (const toml::node* late = p.get("late")) {
    if (prior->kind != PriorDef::Kind::Pose)
      throw Error(located(r.file, r.line(*late), where + ".prior.late is for \"pose\" priors only"));
    if (!late->as_table())
      throw Error(located(r.file, r.line(*late), where + ".prior.late must be a table of joint groups"));
    groups(r, *late->as_table(), where + ".prior.late", model, &prior->lateOffset, nullptr, -3, 3);
    prior->hasLate = true;
  }
  if (const toml::node* turn = p.get("turn")) {
    if (!turn->as_table())
      throw Error(
          located(r.file, r.line(*turn), where + ".prior.turn must be a table of joint groups (rad per rad/s of wz)"));
    groups(r, *turn->as_table(), where + ".prior.turn", model, &prior->turn, nullptr, -1, 1);
  }
  prior->crouch = r.number(p, "crouch", 0, 0, 1, where + ".prior");
  if (offset) {
    if (!offset->as_table())
      throw Error(located(r.file, r.line(*offset), where + ".prior.offset must be a table of joint groups"));
    groups(r, *offset->as_table(), where + ".prior.offset", model, &prior->poseOffset, nullptr, -3, 3);
  }
}

// [prior] keys = [{ t, offset }, ...]: the key poses at increasing times; returns the last key's tick
int parseKeyframes(const TreeReader& r, const toml::node& keysNode, const std::string& where, const RobotModel& model,
                   PriorDef* prior) {
  const toml::array* a = keysNode.as_array();
  if (!a || a->empty())
    throw Error(located(r.file, r.line(keysNode), where + ".prior.keys must be a non-empty list of { t, offset }"));
  int lastTick = 0;
  for (const toml::node& kn : *a) {
    const toml::table* kt = kn.as_table();
    const std::string kw = where + ".prior.keys";
    if (!kt) throw Error(located(r.file, r.line(kn), kw + ": each key must be { t = s, offset = { ... } }"));
    r.onlyKeys(*kt, {"t", "offset"}, kw);
    const toml::node* tn = kt->get("t");
    const toml::node* on = kt->get("offset");
    if (!tn || !on || !on->as_table())
      throw Error(located(r.file, r.line(kn), kw + ": each key needs t = s and offset = { group = rad, ... }"));
    PriorDef::Keyframe key;
    key.tick = int(std::lround(r.number(*tn, kw + ".t", 0.01, 60) / 0.01));
    if (key.tick <= lastTick)
      throw Error(located(r.file, r.line(*tn),
                          kw + ": times must increase (each key after the one before, the first after 0)"));
    lastTick = key.tick;
    groups(r, *on->as_table(), kw + ".offset", model, &key.offset, nullptr, -3.2, 3.2);
    prior->keyframes.push_back(key);
  }
  return lastTick;
}

// [prior] repeat = true: the keyframes cycle, wrapping to the default pose at the last key
void parseRepeat(const TreeReader& r, const toml::node& rp, const std::string& where, int lastTick, PriorDef* prior) {
  const auto b = rp.value<bool>();
  if (!b) throw Error(located(r.file, r.line(rp), where + ".prior.repeat must be true or false"));
  if (!*b) return;
  if (lastTick < 2 || lastTick % 2 != 0)
    throw Error(located(r.file, r.line(rp),
                        where + ".prior.repeat: the last key's t must be an even number of "
                                "hundredths of a second, at least 0.02 (the phase observation "
                                "goes once round per cycle)"));
  for (double x : prior->keyframes.back().offset)
    if (std::abs(x) > 0.05)
      throw Error(located(r.file, r.line(rp),
                          where + ".prior.repeat: the last key must be within 0.05 rad of the "
                                  "default pose (the cycle starts over from it)"));
  prior->cycleTicks = lastTick;
  prior->halfPeriodTicks = lastTick / 2;
}

// [prior] repeat_from = t: a lead-in, then a cycle from the key at t to the last
void parseRepeatFrom(const TreeReader& r, const toml::node& rf, const std::string& where, int lastTick,
                     PriorDef* prior) {
  if (prior->cycleTicks > 0)
    throw Error(located(
        r.file, r.line(rf),
        where + ".prior: repeat = true cycles from the default pose, repeat_from from a key: give one of them"));
  const int startTick = int(std::lround(r.number(rf, where + ".prior.repeat_from", 0.01, 60) / 0.01));
  const auto start = std::find_if(prior->keyframes.begin(), prior->keyframes.end(),
                                  [&](const PriorDef::Keyframe& key) { return key.tick == startTick; });
  if (start == prior->keyframes.end() || start + 1 == prior->keyframes.end())
    throw Error(located(
        r.file, r.line(rf),
        where + ".prior.repeat_from must be the t of a key before the last (the cycle runs from it to the last key)"));
  if ((lastTick - startTick) % 2 != 0)
    throw Error(located(r.file, r.line(rf),
                        where + ".prior.repeat_from: the cycle (last key's t - repeat_from) must be an even number "
                                "of hundredths of a second (the phase observation goes once round per cycle)"));
  for (size_t j = 0; j < start->offset.size(); ++j)
    if (std::abs(start->offset[j] - prior->keyframes.back().offset[j]) > 0.05)
      throw Error(located(r.file, r.line(rf),
                          where + ".prior.repeat_from: the last key must be within 0.05 rad of the key at repeat_from "
                                  "(the cycle starts over from it)"));
  prior->cycleTicks = lastTick;
  prior->cycleStartTick = startTick;
  prior->halfPeriodTicks = (lastTick - startTick) / 2;
}

// Every key of a prior is one its type reads: a key of another type would be silently ignored
void checkPriorKeys(const TreeReader& r, const toml::table& p, const std::string& where, PriorDef::Kind kind) {
  std::vector<std::string> allowed = {"type", "turn"};
  auto add = [&](std::initializer_list<const char*> more) { allowed.insert(allowed.end(), more.begin(), more.end()); };
  switch (kind) {
    case PriorDef::Kind::Phase:
      add({"T1", "dh", "d0", "stand_still", "stand_ramp_s", "stride", "arm_swing"});
      break;
    case PriorDef::Kind::Pose:
      add({"offset", "late"});
      break;
    case PriorDef::Kind::Jump:
      add({"T1", "crouch", "offset"});
      break;
    case PriorDef::Kind::Kick:
      add({"T1", "offset", "swing"});
      break;
    case PriorDef::Kind::Keyframes:
      add({"keys", "repeat", "repeat_from"});
      break;
    case PriorDef::Kind::None:
      break;
  }
  for (auto&& [k, v] : p)
    if (std::find(allowed.begin(), allowed.end(), k.str()) == allowed.end())
      throw Error(located(r.file, r.line(v),
                          where + ".prior." + std::string(k.str()) + " is not a key of a \"" +
                              std::string(p.get("type")->value<std::string>().value_or("")) + "\" prior"));
}

// [skill.NAME.prior]
void parsePrior(const TreeReader& r, const toml::table& p, const std::string& where, const RobotModel& model,
                PriorDef* prior) {
  r.onlyKeys(p,
             {"type", "T1", "dh", "d0", "stand_still", "stand_ramp_s", "stride", "arm_swing", "offset", "crouch",
              "swing", "late", "keys", "repeat", "repeat_from", "turn"},
             where + ".prior");
  prior->kind = priorKind(r, p, where);
  parsePriorPoses(r, p, where, model, prior);
  prior->halfPeriodTicks = int(r.integer(p, "T1", 40, 1, 1000, where + ".prior"));
  const toml::node* keysNode = p.get("keys");
  if ((prior->kind == PriorDef::Kind::Keyframes) != (keysNode != nullptr))
    throw Error(located(
        r.file, r.line(p),
        where +
            ".prior: a \"keyframes\" prior needs keys = [{ t = s, offset = { group = rad, ... } }, ...], and only it"));
  if (keysNode) {
    const int lastTick = parseKeyframes(r, *keysNode, where, model, prior);
    prior->halfPeriodTicks = lastTick;
    if (const toml::node* rp = p.get("repeat")) parseRepeat(r, *rp, where, lastTick, prior);
    if (const toml::node* rf = p.get("repeat_from")) parseRepeatFrom(r, *rf, where, lastTick, prior);
  } else if (p.get("repeat") || p.get("repeat_from")) {
    const toml::node* rp = p.get("repeat") ? p.get("repeat") : p.get("repeat_from");
    throw Error(located(r.file, r.line(*rp), where + ".prior.repeat: only a \"keyframes\" prior repeats"));
  }
  prior->dh = r.number(p, "dh", 0, -1.5, 1.5, where + ".prior");
  prior->d0 = r.number(p, "d0", 0, -1.5, 1.5, where + ".prior");
  prior->stride = r.number(p, "stride", 0, 0, 1, where + ".prior");
  prior->armSwing = r.number(p, "arm_swing", 0, 0, 2, where + ".prior");
  prior->standStill = r.flag(p, "stand_still", prior->standStill, where + ".prior");
  checkPriorKeys(r, p, where, prior->kind);  // after the checks with a more specific message
  prior->standRampTicks = int(std::lround(r.number(p, "stand_ramp_s", 0, 0, 10, where + ".prior") / 0.01));
}

// [skill.NAME.gains]: [kp, kd] per joint group, every joint given one
void parseGains(const TreeReader& r, const toml::table& gt, const std::string& where, const RobotModel& model,
                SkillDef* s) {
  groups(r, gt, where + ".gains", model, &s->kp, &s->kd, 0, 5000);
  for (size_t j = 0; j < size_t(kNumJoints); ++j)
    if (s->kp[j] <= 0)
      throw Error(located(r.file, s->line, where + ".gains: no gain for joint " + model.joints[j].name));
}

// [skill.NAME.action_scale]: rad per policy unit per joint group
void parseActionScale(const TreeReader& r, const toml::table& a, const std::string& where, const RobotModel& model,
                      SkillDef* s) {
  groups(r, a, where + ".action_scale", model, &s->actionScale, nullptr, 0, 2);
}

// [skill.NAME.commands]; skillLine locates an error without a line of its own
void parseCommands(const TreeReader& r, const toml::table& c, const std::string& where, int skillLine, CommandDef* d) {
  const std::string w = where + ".commands";
  r.onlyKeys(c,
             {"vx", "vy", "wz", "amplitude", "pelvis_height", "line_hold", "forward_turn", "line_steer", "line_command",
              "step_command", "step_look_back", "ball_command"},
             w);
  d->vx = r.range(c, "vx", {}, -5, 5, w);
  d->vy = r.range(c, "vy", {}, -5, 5, w);
  d->wz = r.range(c, "wz", {}, -5, 5, w);
  d->amplitude = r.range(c, "amplitude", {}, 0, 1, w);
  const std::array<double, 2> height = r.pair(c, "pelvis_height", {0.78, 0.78}, 0.1, 1.5, w);  // at amplitude 0, at 1
  d->pelvisHeight = {height[0], height[1]};
  d->lineHold = r.number(c, "line_hold", 0, 0, 5, w);
  if (c.contains("forward_turn")) {
    const std::array<double, 2> turn = r.pair(c, "forward_turn", {0, 0}, 0.01, 5, w);
    if (turn[0] > d->vx.hi || turn[1] > std::min(d->wz.hi, -d->wz.lo))
      throw Error(located(r.file, r.line(*c.get("forward_turn")),
                          w + ".forward_turn = [vx, wz] must lie within the skill's vx range and its wz range on "
                              "both sides of 0"));
    d->steerVx = turn[0], d->steerWz = turn[1];
  }
  d->lineSteer = r.number(c, "line_steer", 0, 0, 100, w);
  if (d->lineSteer > 0 && !turnsBothWays(*d))
    throw Error(located(r.file, r.line(*c.get("line_steer")),
                        w + ".line_steer steers with wz, and the skill's commands "
                            "need a wz range either side of 0 (wz = [-x, x])"));
  d->lineCommand = r.flag(c, "line_command", d->lineCommand, w);
  d->stepCommand = r.flag(c, "step_command", d->stepCommand, w);
  d->stepLookBack = r.flag(c, "step_look_back", d->stepLookBack, w);
  if (d->stepLookBack && !d->stepCommand)
    throw Error(located(r.file, c.get("step_look_back") ? r.line(*c.get("step_look_back")) : skillLine,
                        w + ": step_look_back needs step_command = true"));
  d->ballCommand = r.flag(c, "ball_command", d->ballCommand, w);
  if (int(d->lineCommand) + int(d->stepCommand) + int(d->ballCommand) > 1)
    throw Error(located(r.file, r.line(c),
                        w + ": line_command, step_command and ball_command all use the aux command "
                            "slots; a skill can have one"));
}

// [skill.NAME.termination], read whole: the keys left out take the defaults
void parseTermination(const TreeReader& r, const toml::table& e, const std::string& where, TerminationDef* d) {
  r.onlyKeys(e, {"max_tilt_deg", "forward_pitch_deg", "min_height", "episode_s", "lifted_foot_touch_s"},
             where + ".termination");
  d->maxForwardPitchDegrees = r.number(e, "forward_pitch_deg", -1, -1, 180, where + ".termination");
  d->maxTiltDegrees = r.number(e, "max_tilt_deg", 30, 1, 180, where + ".termination");
  d->minHeight = r.number(e, "min_height", 0.5, 0, 2, where + ".termination");
  d->episodeSeconds = r.number(e, "episode_s", 10, 0.1, 3600, where + ".termination");
  d->liftedFootTouchSeconds = r.number(e, "lifted_foot_touch_s", 0, 0, 60, where + ".termination");
}

// Which of the tables a branch inherits from its parent a skill wrote itself.
struct Given {
  bool gains = false, actionScale = false, actionFilter = false, termination = false;
};

// Parents exist, the tree has exactly one root, an `up` names another skill, and a skill without a key is
// someone's `up`.
void checkParentsAndKeys(const TreeReader& r, const SkillTree& tree) {
  int roots = 0;
  for (const SkillDef& s : tree.skills) {
    if (s.parent.empty())
      ++roots;
    else if (!tree.find(s.parent))
      throw Error(located(r.file, s.line, "skill." + s.name + ": unknown parent '" + s.parent + "'"));
    if (!s.up.empty() && (!tree.find(s.up) || s.up == s.name))
      throw Error(
          located(r.file, s.line, "skill." + s.name + ": up = '" + s.up + "' is not another skill of the tree"));
    const bool someonesWayUp =
        std::any_of(tree.skills.begin(), tree.skills.end(), [&](const SkillDef& o) { return o.up == s.name; });
    if (s.key < 0 && !someonesWayUp)
      throw Error(located(r.file, s.line,
                          "skill." + s.name +
                              ": missing key (only a skill that is another's `up`, reached "
                              "by routing through it, may go without one)"));
  }
  if (roots != 1)
    throw Error(
        located(r.file, 0, "the tree needs exactly one root skill (parent = \"\"), found " + std::to_string(roots)));
}

// Every chain of parents reaches the root (no cycles), and so does every way up (each skill's `up`, else its
// parent): a request for the root from anywhere routes there.
void checkAncestry(const TreeReader& r, const SkillTree& tree) {
  for (const SkillDef& s : tree.skills) {
    const SkillDef* at = &s;
    for (size_t hops = 0; !at->parent.empty(); ++hops) {
      if (hops > tree.skills.size())
        throw Error(located(r.file, s.line, "skill." + s.name + ": its parents form a cycle and never reach the root"));
      at = tree.find(at->parent);
    }
    at = &s;
    for (size_t hops = 0; !at->parent.empty(); ++hops) {
      if (hops > tree.skills.size())
        throw Error(located(r.file, s.line,
                            "skill." + s.name +
                                ": its way up (`up`, else the parent) goes round in a "
                                "cycle and never reaches the root"));
      at = tree.find(at->up.empty() ? at->parent : at->up);
    }
  }
}

// A branch inherits the controller tables it does not write (gains, action_scale, action_filter, termination) from
// its parent: resolved from the root down. The root must give gains.
void inheritControllerTables(const TreeReader& r, std::map<std::string, Given>& given, SkillTree* tree) {
  std::set<std::string> resolved;
  for (const SkillDef& s : tree->skills)
    if (s.parent.empty()) {
      if (!given[s.name].gains)
        throw Error(located(r.file, s.line, "skill." + s.name + ": the root needs a [gains] table"));
      resolved.insert(s.name);
    }
  while (resolved.size() < tree->skills.size())
    for (SkillDef& s : tree->skills) {
      if (resolved.count(s.name) || !resolved.count(s.parent)) continue;
      const SkillDef& p = *tree->find(s.parent);
      const Given& g = given[s.name];
      if (!g.gains) s.kp = p.kp, s.kd = p.kd;
      if (!g.actionScale) s.actionScale = p.actionScale;
      if (!g.actionFilter) s.actionFilter = p.actionFilter;
      if (!g.termination) s.termination = p.termination;
      resolved.insert(s.name);
    }
}

// A skill's own keys: parent, up, key (unique in the tree: keys holds those taken), model, switch_in_phase,
// settle_first
void parseSkillKeys(const TreeReader& r, const toml::table& t, const std::string& where, std::set<int>* keys,
                    SkillDef* s) {
  if (const toml::node* p = t.get("parent")) {
    auto v2 = p->value<std::string>();
    if (!v2) throw Error(located(r.file, r.line(*p), where + ".parent must be a skill name (\"\" for the root)"));
    s->parent = *v2;
  }
  if (const toml::node* u = t.get("up")) {
    auto v2 = u->value<std::string>();
    if (!v2 || v2->empty()) throw Error(located(r.file, r.line(*u), where + ".up must be a skill name"));
    s->up = *v2;
  }
  // a skill without a key is reached only by routing through it (the stand-up: key 0 while lying); checkParentsAndKeys
  if (const toml::node* key = t.get("key")) {
    s->key = int(r.integer(*key, where + ".key", 0, 9));
    if (!keys->insert(s->key).second)
      throw Error(located(r.file, r.line(*key), where + ": key " + std::to_string(s->key) + " is taken"));
  }
  s->model = s->name + ".onnx";
  if (const toml::node* m = t.get("model")) {  // a file in the tree's folder: a name, never a path out of it
    const std::optional<std::string> name = m->value<std::string>();
    if (!name || name->empty() || name->find_first_of("/\\") != std::string::npos || *name == "." || *name == "..")
      throw Error(located(r.file, r.line(*m), where + ".model must be a file name in the tree's folder (no path)"));
    s->model = *name;
  }
  s->switchInPhase = r.range(t, "switch_in_phase", {0.0, 1.0}, 0.0, 1.0, where);
  s->settleFirst = r.flag(t, "settle_first", s->settleFirst, where);
}

// The controller's tables and keys (gains, action_scale, action_filter), and which of the inheritable ones the skill
// writes itself (*g)
void parseController(const TreeReader& r, const toml::table& t, const std::string& where, const RobotModel& model,
                     SkillDef* s, Given* g) {
  if (const toml::table* gt = r.table(t, "gains", false, where)) {
    g->gains = true;
    parseGains(r, *gt, where, model, s);
  }
  if (const toml::table* a = r.table(t, "action_scale", false, where)) {
    g->actionScale = true;
    parseActionScale(r, *a, where, model, s);
  }
  g->actionFilter = t.get("action_filter") != nullptr;
  s->actionFilter = r.number(t, "action_filter", 0.0, 0.0, 0.99, where);
  g->termination = t.get("termination") != nullptr;
}

// [skill.NAME]: its keys, then its tables in an order where each finds what it checks against already read
SkillDef parseSkill(const TreeReader& r, const std::string& name, const toml::node& v, const RobotModel& model,
                    std::set<int>* keys, Given* g) {
  SkillDef s;
  s.name = name;
  s.line = r.line(v);
  const std::string where = "skill." + s.name;
  const toml::table* t = v.as_table();
  if (!t) throw Error(located(r.file, s.line, where + " must be a table"));
  // the runtime's keys and tables, then the tables training owns (ai::loadTrainingTree reads and checks those)
  r.onlyKeys(
      *t, {"parent",        "up",       "key",          "model",    "switch_in_phase", "settle_first", "action_filter",
           "prior",         "gains",    "action_scale", "commands", "termination",     "draws",        "rewards",
           "randomisation", "training", "card",         "terrain",  "curriculum",      "ball",         "ppo"},
      where);
  parseSkillKeys(r, *t, where, keys, &s);
  if (const toml::table* p = r.table(*t, "prior", false, where)) parsePrior(r, *p, where, model, &s.prior);
  parseController(r, *t, where, model, &s, g);
  if (const toml::table* c = r.table(*t, "commands", false, where)) parseCommands(r, *c, where, s.line, &s.commands);
  if (const toml::table* e = r.table(*t, "termination", false, where)) parseTermination(r, *e, where, &s.termination);
  return s;
}

}  // namespace

toml::table readTreeFile(const TreeReader& r) {
  const std::string text = engine::readFile(r.file);
  toml::table root;
  try {
    root = toml::parse(text, r.file);
  } catch (const toml::parse_error& e) {
    throw Error(located(r.file, int(e.source().begin.line), std::string(e.description())));
  }
  r.onlyKeys(root, {"ppo", "skill"}, "the skill tree");
  return root;
}

bool jointInGroup(const std::string& jointName, const std::string& group) {
  return jointName.find(group + "_joint") != std::string::npos;
}

const SkillDef* SkillTree::find(const std::string& name) const {
  for (const SkillDef& s : skills)
    if (s.name == name) return &s;
  return nullptr;
}

SkillTree loadSkillTree(const std::string& path, const RobotModel& model) {
  const TreeReader r{path};
  const toml::table root = readTreeFile(r);
  SkillTree tree;
  tree.path = path;
  tree.directory = std::filesystem::path(path).parent_path().string();
  if (tree.directory.empty()) tree.directory = ".";  // a bare file name: the models sit beside it, here
  std::map<std::string, Given> given;                // which inheritable tables each skill wrote itself
  std::set<int> keys;
  for (auto&& [k, v] : *r.table(root, "skill", true, "tree")) {
    const std::string name(k.str());
    tree.skills.push_back(parseSkill(r, name, v, model, &keys, &given[name]));
  }
  checkParentsAndKeys(r, tree);
  checkAncestry(r, tree);
  inheritControllerTables(r, given, &tree);
  return tree;
}

void poseStages(const PriorDef& prior, double amplitude, double* first, double* late) {
  if (!prior.hasLate) {
    *first = amplitude;
    *late = 0.0;
    return;
  }
  *first = std::min(1.0, 2.0 * amplitude);
  *late = std::clamp(2.0 * amplitude - 1.0, 0.0, 1.0);
}

namespace {
std::string& treePathOverride() {
  static std::string path;
  return path;
}
}  // namespace

std::string defaultSkillTreePath() {
  return treePathOverride().empty() ? engine::projectFile("assets/skills/tree.toml") : treePathOverride();
}

void setSkillTreePath(const std::string& path) { treePathOverride() = path; }

}  // namespace robot
