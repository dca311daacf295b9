// skill_tree.cpp — strict TOML loader for the skill tree: a parser per table of a skill (parsePrior, parseCommands,
// ..., parseCard), called by parseSkill in an order where each finds what it checks against already read, then the
// checks that need the whole tree (checkParentsAndKeys, checkAncestry) and the inheritance of controller tables.
#include "robot/skill_tree.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "engine/core/error.h"
#include "engine/core/file_io.h"

namespace robot {
namespace {

using engine::Error;
using engine::located;

const char* const kGroups[] = {"hip_pitch", "hip_roll",       "hip_yaw",        "knee",          "ankle_pitch", "ankle_roll",
                               "waist_yaw", "shoulder_pitch", "shoulder_roll",  "shoulder_yaw",  "elbow",       "wrist_roll"};

struct Reader {
  std::string file;
  int line(const toml::node& n) const { return int(n.source().begin.line); }

  void onlyKeys(const toml::table& t, std::initializer_list<const char*> allowed, const std::string& where) const {
    for (auto&& [k, v] : t) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || k == a;
      if (!ok) throw Error(located(file, line(v), "unknown key '" + std::string(k.str()) + "' in " + where));
    }
  }
  const toml::table* table(const toml::table& t, const char* key, bool required, const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (required) throw Error(located(file, line(t), where + ": missing [" + key + "]"));
      return nullptr;
    }
    if (!n->as_table()) throw Error(located(file, line(*n), where + "." + key + " must be a table"));
    return n->as_table();
  }
  double number(const toml::node& n, const std::string& what, double lo, double hi) const {
    auto v = n.value<double>();
    if (!v || !std::isfinite(*v)) throw Error(located(file, line(n), what + " must be a number"));
    if (*v < lo || *v > hi)
      throw Error(located(file, line(n), what + " = " + std::to_string(*v) + " is outside [" + std::to_string(lo) + ", " +
                                             std::to_string(hi) + "]"));
    return *v;
  }
  double number(const toml::table& t, const char* key, double fallback, double lo, double hi, const std::string& where) const {
    const toml::node* n = t.get(key);
    return n ? number(*n, where + "." + key, lo, hi) : fallback;
  }
  // true or false (not 1 or 0)
  bool flag(const toml::table& t, const char* key, bool fallback, const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    const std::optional<bool> b = n->is_boolean() ? n->value<bool>() : std::nullopt;
    if (!b) throw Error(located(file, line(*n), where + "." + key + " must be true or false"));
    return *b;
  }
  // [a, b] with no order between them
  std::array<double, 2> pair(const toml::table& t, const char* key, std::array<double, 2> fallback, double lo, double hi,
                             const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2) throw Error(located(file, line(*n), where + "." + key + " must be [x, y]"));
    return {number((*a)[0], where + "." + key, lo, hi), number((*a)[1], where + "." + key, lo, hi)};
  }
  Range range(const toml::table& t, const char* key, Range fallback, double lo, double hi, const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2) throw Error(located(file, line(*n), where + "." + key + " must be [low, high]"));
    Range r{number((*a)[0], where + "." + key, lo, hi), number((*a)[1], where + "." + key, lo, hi)};
    if (r.lo > r.hi) throw Error(located(file, line(*n), where + "." + key + ": low is above high"));
    return r;
  }
  // a per-joint-group table: group = value (or [kp, kd] when pairs)
  void groups(const toml::table& t, const std::string& where, const RobotModel& model, JointArray* a, JointArray* b,
              double lo, double hi) const {
    for (auto&& [k, v] : t) {
      const std::string group(k.str());
      bool known = false;
      for (const char* g : kGroups)  // "knee" means both knees, "left_knee" only the left one
        known = known || group == g || group == std::string("left_") + g || group == std::string("right_") + g;
      if (!known) throw Error(located(file, line(v), where + ": unknown joint group '" + group + "'"));
      double x, y = 0;
      if (b) {
        const toml::array* arr = v.as_array();
        if (!arr || arr->size() != 2) throw Error(located(file, line(v), where + "." + group + " must be [kp, kd]"));
        x = number((*arr)[0], where + "." + group, lo, hi);
        y = number((*arr)[1], where + "." + group, lo, hi);
      } else {
        x = number(v, where + "." + group, lo, hi);
      }
      for (size_t j = 0; j < size_t(kNumJoints); ++j)
        if (jointInGroup(model.joints[j].name, group)) {
          (*a)[j] = x;
          if (b) (*b)[j] = y;
        }
    }
  }
};

// A steer (line_steer, heading_steer, a card's steer) turns with wz: the range must reach either side of 0.
bool turnsBothWays(const CommandDef& c) { return c.wz.lo < 0 && c.wz.hi > 0; }

// [prior] type: the kind of prior
PriorDef::Kind priorKind(const Reader& r, const toml::table& p, const std::string& where) {
  const std::string type = p.get("type") && p.get("type")->value<std::string>() ? *p.get("type")->value<std::string>() : "";
  if (type == "phase") return PriorDef::Kind::Phase;
  if (type == "pose") return PriorDef::Kind::Pose;
  if (type == "jump") return PriorDef::Kind::Jump;
  if (type == "kick") return PriorDef::Kind::Kick;
  if (type == "keyframes") return PriorDef::Kind::Keyframes;
  if (type == "none") return PriorDef::Kind::None;
  throw Error(located(r.file, r.line(p), where + ".prior.type must be \"phase\", \"pose\", \"jump\", \"kick\", \"keyframes\" or \"none\""));
}

// [prior] offset, swing, late, turn (joint-group tables) and crouch: which kinds need or allow them
void parsePriorPoses(const Reader& r, const toml::table& p, const std::string& where, const RobotModel& model, PriorDef* prior) {
  const toml::node* offset = p.get("offset");
  const bool needsOffset = prior->kind == PriorDef::Kind::Pose || prior->kind == PriorDef::Kind::Jump ||
                           prior->kind == PriorDef::Kind::Kick;
  if (needsOffset != (offset != nullptr))
    throw Error(located(r.file, r.line(p), where + ".prior: \"pose\", \"jump\" and \"kick\" priors need offset = { group = rad, ... }, and only they"));
  const toml::node* swing = p.get("swing");
  if ((prior->kind == PriorDef::Kind::Kick) != (swing != nullptr))
    throw Error(located(r.file, r.line(p), where + ".prior: a \"kick\" prior needs swing = { group = rad, ... }, and only it"));
  if (swing) {
    if (!swing->as_table()) throw Error(located(r.file, r.line(*swing), where + ".prior.swing must be a table of joint groups"));
    r.groups(*swing->as_table(), where + ".prior.swing", model, &prior->swingOffset, nullptr, -3, 3);
  }
  if (const toml::node* late = p.get("late")) {
    if (prior->kind != PriorDef::Kind::Pose)
      throw Error(located(r.file, r.line(*late), where + ".prior.late is for \"pose\" priors only"));
    if (!late->as_table()) throw Error(located(r.file, r.line(*late), where + ".prior.late must be a table of joint groups"));
    r.groups(*late->as_table(), where + ".prior.late", model, &prior->lateOffset, nullptr, -3, 3);
    prior->hasLate = true;
  }
  if (const toml::node* turn = p.get("turn")) {
    if (!turn->as_table()) throw Error(located(r.file, r.line(*turn), where + ".prior.turn must be a table of joint groups (rad per rad/s of wz)"));
    r.groups(*turn->as_table(), where + ".prior.turn", model, &prior->turn, nullptr, -1, 1);
  }
  prior->crouch = r.number(p, "crouch", 0, 0, 1, where + ".prior");
  if (offset) {
    if (!offset->as_table()) throw Error(located(r.file, r.line(*offset), where + ".prior.offset must be a table of joint groups"));
    r.groups(*offset->as_table(), where + ".prior.offset", model, &prior->poseOffset, nullptr, -3, 3);
  }
}

// [prior] keys = [{ t, offset }, ...]: the key poses at increasing times; returns the last key's tick
int parseKeyframes(const Reader& r, const toml::node& keysNode, const std::string& where, const RobotModel& model, PriorDef* prior) {
  const toml::array* a = keysNode.as_array();
  if (!a || a->empty()) throw Error(located(r.file, r.line(keysNode), where + ".prior.keys must be a non-empty list of { t, offset }"));
  int lastTick = 0;
  for (const toml::node& kn : *a) {
    const toml::table* kt = kn.as_table();
    const std::string kw = where + ".prior.keys";
    if (!kt) throw Error(located(r.file, r.line(kn), kw + ": each key must be { t = s, offset = { ... } }"));
    r.onlyKeys(*kt, {"t", "offset"}, kw);
    const toml::node* tn = kt->get("t");
    const toml::node* on = kt->get("offset");
    if (!tn || !on || !on->as_table()) throw Error(located(r.file, r.line(kn), kw + ": each key needs t = s and offset = { group = rad, ... }"));
    PriorDef::Keyframe key;
    key.tick = int(std::lround(r.number(*tn, kw + ".t", 0.01, 60) / 0.01));
    if (key.tick <= lastTick)
      throw Error(located(r.file, r.line(*tn), kw + ": times must increase (each key after the one before, the first after 0)"));
    lastTick = key.tick;
    r.groups(*on->as_table(), kw + ".offset", model, &key.offset, nullptr, -3.2, 3.2);
    prior->keyframes.push_back(key);
  }
  return lastTick;
}

// [prior] repeat = true: the keyframes cycle, wrapping to the default pose at the last key
void parseRepeat(const Reader& r, const toml::node& rp, const std::string& where, int lastTick, PriorDef* prior) {
  const auto b = rp.value<bool>();
  if (!b) throw Error(located(r.file, r.line(rp), where + ".prior.repeat must be true or false"));
  if (!*b) return;
  if (lastTick < 2 || lastTick % 2 != 0)
    throw Error(located(r.file, r.line(rp), where + ".prior.repeat: the last key's t must be an even number of "
                                                  "hundredths of a second, at least 0.02 (the phase observation "
                                                  "goes once round per cycle)"));
  for (double x : prior->keyframes.back().offset)
    if (std::abs(x) > 0.05)
      throw Error(located(r.file, r.line(rp), where + ".prior.repeat: the last key must be within 0.05 rad of the "
                                                    "default pose (the cycle starts over from it)"));
  prior->cycleTicks = lastTick;
  prior->halfPeriodTicks = lastTick / 2;
}

// [prior] repeat_from = t: a lead-in, then a cycle from the key at t to the last
void parseRepeatFrom(const Reader& r, const toml::node& rf, const std::string& where, int lastTick, PriorDef* prior) {
  if (prior->cycleTicks > 0)
    throw Error(located(r.file, r.line(rf), where + ".prior: repeat = true cycles from the default pose, repeat_from from a key: give one of them"));
  const int startTick = int(std::lround(r.number(rf, where + ".prior.repeat_from", 0.01, 60) / 0.01));
  const auto start = std::find_if(prior->keyframes.begin(), prior->keyframes.end(),
                                  [&](const PriorDef::Keyframe& key) { return key.tick == startTick; });
  if (start == prior->keyframes.end() || start + 1 == prior->keyframes.end())
    throw Error(located(r.file, r.line(rf), where + ".prior.repeat_from must be the t of a key before the last (the cycle runs from it to the last key)"));
  if ((lastTick - startTick) % 2 != 0)
    throw Error(located(r.file, r.line(rf), where + ".prior.repeat_from: the cycle (last key's t - repeat_from) must be an even number "
                                                  "of hundredths of a second (the phase observation goes once round per cycle)"));
  for (size_t j = 0; j < start->offset.size(); ++j)
    if (std::abs(start->offset[j] - prior->keyframes.back().offset[j]) > 0.05)
      throw Error(located(r.file, r.line(rf), where + ".prior.repeat_from: the last key must be within 0.05 rad of the key at repeat_from (the cycle starts over from it)"));
  prior->cycleTicks = lastTick;
  prior->cycleStartTick = startTick;
  prior->halfPeriodTicks = (lastTick - startTick) / 2;
}

// [skill.NAME.prior]
void parsePrior(const Reader& r, const toml::table& p, const std::string& where, const RobotModel& model, PriorDef* prior) {
  r.onlyKeys(p, {"type", "T1", "dh", "d0", "stand_still", "stand_ramp_s", "stride", "arm_swing", "offset", "crouch", "swing", "late", "keys", "repeat", "repeat_from", "turn"}, where + ".prior");
  prior->kind = priorKind(r, p, where);
  parsePriorPoses(r, p, where, model, prior);
  prior->halfPeriodTicks = int(r.number(p, "T1", 40, 1, 1000, where + ".prior"));
  const toml::node* keysNode = p.get("keys");
  if ((prior->kind == PriorDef::Kind::Keyframes) != (keysNode != nullptr))
    throw Error(located(r.file, r.line(p), where + ".prior: a \"keyframes\" prior needs keys = [{ t = s, offset = { group = rad, ... } }, ...], and only it"));
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
  if (const toml::node* ss = p.get("stand_still")) prior->standStill = ss->value<bool>().value_or(true);
  prior->standRampTicks = int(std::lround(r.number(p, "stand_ramp_s", 0, 0, 10, where + ".prior") / 0.01));
}

// [skill.NAME.gains]: [kp, kd] per joint group, every joint given one
void parseGains(const Reader& r, const toml::table& gt, const std::string& where, const RobotModel& model, SkillDef* s) {
  r.groups(gt, where + ".gains", model, &s->kp, &s->kd, 0, 5000);
  for (size_t j = 0; j < size_t(kNumJoints); ++j)
    if (s->kp[j] <= 0) throw Error(located(r.file, s->line, where + ".gains: no gain for joint " + model.joints[j].name));
}

// [skill.NAME.action_scale]: rad per policy unit per joint group
void parseActionScale(const Reader& r, const toml::table& a, const std::string& where, const RobotModel& model, SkillDef* s) {
  r.groups(a, where + ".action_scale", model, &s->actionScale, nullptr, 0, 2);
}

// [skill.NAME.commands]; skillLine locates an error without a line of its own
void parseCommands(const Reader& r, const toml::table& c, const std::string& where, int skillLine, CommandDef* d) {
  r.onlyKeys(c, {"vx", "vy", "wz", "amplitude", "amplitude_rate", "amplitude_zero", "pelvis_height", "zero_probability", "resample_s",
                  "resample_jitter", "ramp", "line_hold", "steer", "turn_in_place", "line_command",
                  "step_command", "step_look_back"},
             where + ".commands");
  d->amplitude = r.range(c, "amplitude", {}, 0, 1, where + ".commands");
  d->amplitudeRate = r.number(c, "amplitude_rate", 0, 0, 100, where + ".commands");
  d->amplitudeZero = r.number(c, "amplitude_zero", 0, 0, 1, where + ".commands");
  if (const toml::node* h = c.get("pelvis_height")) {
    const toml::array* a = h->as_array();
    if (!a || a->size() != 2) throw Error(located(r.file, r.line(*h), where + ".commands.pelvis_height must be [at amplitude 0, at 1]"));
    d->pelvisHeight = {r.number((*a)[0], where + ".commands.pelvis_height", 0.1, 1.5),
                       r.number((*a)[1], where + ".commands.pelvis_height", 0.1, 1.5)};
  }
  d->vx = r.range(c, "vx", {}, -5, 5, where + ".commands");
  d->vy = r.range(c, "vy", {}, -5, 5, where + ".commands");
  d->wz = r.range(c, "wz", {}, -5, 5, where + ".commands");
  d->zeroProbability = r.number(c, "zero_probability", 0.2, 0, 1, where + ".commands");
  d->resampleSeconds = r.number(c, "resample_s", 5, 0.1, 1000, where + ".commands");
  d->resampleJitter = r.number(c, "resample_jitter", 0, 0, 0.9, where + ".commands");
  d->lineHold = r.number(c, "line_hold", 0, 0, 5, where + ".commands");
  d->steer = r.number(c, "steer", 0, 0, 2, where + ".commands");
  d->ramp = r.flag(c, "ramp", d->ramp, where + ".commands");
  d->turnInPlace = r.flag(c, "turn_in_place", d->turnInPlace, where + ".commands");
  d->lineCommand = r.flag(c, "line_command", d->lineCommand, where + ".commands");
  d->stepCommand = r.flag(c, "step_command", d->stepCommand, where + ".commands");
  d->stepLookBack = r.flag(c, "step_look_back", d->stepLookBack, where + ".commands");
  if (d->stepLookBack && !d->stepCommand)
    throw Error(located(r.file, c.get("step_look_back") ? r.line(*c.get("step_look_back")) : skillLine,
                        where + ".commands: step_look_back needs step_command = true"));
  if (d->lineCommand && d->stepCommand)
    throw Error(located(r.file, r.line(*c.get("step_command")), where + ".commands: line_command and step_command both "
                                                               "use the aux command slots; a skill can have one"));
}

// [skill.NAME.rewards]: term = weight (the terms are checked where the rewards are built)
void parseRewards(const Reader& r, const toml::table& w, const std::string& where, SkillDef* s) {
  for (auto&& [rk, rv] : w) {
    s->rewardWeights[std::string(rk.str())] = r.number(rv, where + ".rewards." + std::string(rk.str()), -1e6, 1e6);
    s->rewardLines[std::string(rk.str())] = r.line(rv);
  }
}

// [skill.NAME.termination], read whole: the keys left out take the defaults
void parseTermination(const Reader& r, const toml::table& e, const std::string& where, TerminationDef* d) {
  r.onlyKeys(e, {"max_tilt_deg", "forward_pitch_deg", "min_height", "episode_s", "lifted_foot_touch_s"},
             where + ".termination");
  d->maxForwardPitchDegrees = r.number(e, "forward_pitch_deg", -1, -1, 180, where + ".termination");
  d->maxTiltDegrees = r.number(e, "max_tilt_deg", 30, 1, 180, where + ".termination");
  d->minHeight = r.number(e, "min_height", 0.5, 0, 2, where + ".termination");
  d->episodeSeconds = r.number(e, "episode_s", 10, 0.1, 3600, where + ".termination");
  d->liftedFootTouchSeconds = r.number(e, "lifted_foot_touch_s", 0, 0, 60, where + ".termination");
}

// [skill.NAME.randomisation], read whole
void parseRandomisation(const Reader& r, const toml::table& d, const std::string& where, RandomisationDef* out) {
  r.onlyKeys(d, {"friction", "added_mass", "push_every_s", "push_speed"}, where + ".randomisation");
  out->friction = r.range(d, "friction", {1, 1}, 0.05, 5, where + ".randomisation");
  out->addedMass = r.range(d, "added_mass", {0, 0}, -3, 10, where + ".randomisation");
  out->pushEverySeconds = r.number(d, "push_every_s", 0, 0, 1000, where + ".randomisation");
  out->pushSpeed = r.range(d, "push_speed", {0, 0}, 0, 5, where + ".randomisation");
}

// [skill.NAME.training] line_jitter, line_steer, heading_steer and heading_steer_share: how training steers, which
// needs the skill's commands
void parseTrainingSteers(const Reader& r, const toml::table& tr, const std::string& where, SkillDef* s) {
  if (const toml::node* lj = tr.get("line_jitter")) {
    if (!s->commands.lineCommand)
      throw Error(located(r.file, r.line(*lj), where + ".training.line_jitter moves the line a skill sees, and it sees none "
                                                     "([commands] line_command = true)"));
    const std::array<double, 2> j = r.pair(tr, "line_jitter", {0.0, 0.0}, 0.0, 2.0, where + ".training");
    s->lineJitterHeading = j[0], s->lineJitterOffset = j[1];
  }
  s->lineSteer = r.number(tr, "line_steer", 0, 0, 100, where + ".training");
  if (s->lineSteer > 0 && !turnsBothWays(s->commands))
    throw Error(located(r.file, r.line(*tr.get("line_steer")), where + ".training.line_steer steers with wz, and the skill's "
                                                                      "commands need a wz range either side of 0 (wz = [-x, x])"));
  s->headingSteer = r.number(tr, "heading_steer", 0, 0, 100, where + ".training");
  if (s->headingSteer > 0 && !turnsBothWays(s->commands))
    throw Error(located(r.file, r.line(*tr.get("heading_steer")), where + ".training.heading_steer steers with wz, and the "
                                                                         "skill's commands need a wz range either side of 0 (wz = [-x, x])"));
  s->headingSteerShare = r.number(tr, "heading_steer_share", 1.0, 0.0, 1.0, where + ".training");
  if (tr.contains("heading_steer_share") && s->headingSteer <= 0)
    throw Error(located(r.file, r.line(*tr.get("heading_steer_share")), where + ".training.heading_steer_share is the share of "
                                                                               "episodes heading_steer steers; set heading_steer too"));
  if (s->headingSteer > 0 && s->lineSteer > 0)
    throw Error(located(r.file, r.line(*tr.get("heading_steer")), where + ".training: heading_steer and line_steer both set "
                                                                         "the yaw-rate command; choose one"));
}

// [skill.NAME.training] handover_back, handover_back_s and handover_back_from: episodes that start under a child
// (that it is one is checked with the whole tree, checkAncestry)
void parseHandoverBack(const Reader& r, const toml::table& tr, const std::string& where, SkillDef* s) {
  s->handoverBack = r.number(tr, "handover_back", 0, 0, 1, where + ".training");
  s->handoverBackSeconds = r.range(tr, "handover_back_s", {1.0, 3.0}, 0.01, 60, where + ".training");
  if (const toml::node* hb = tr.get("handover_back_from")) {
    const std::optional<std::string> name = hb->value<std::string>();
    if (!name) throw Error(located(r.file, r.line(*hb), where + ".training.handover_back_from must be a skill name"));
    s->handoverBackFrom = *name;
  }
  if (s->handover + s->handoverBack > 1.0)
    throw Error(located(r.file, r.line(*tr.get("handover_back")), where + ".training.handover + handover_back must be at most 1 "
                                                                         "(they are shares of the training episodes)"));
  if ((s->handoverBack > 0) != !s->handoverBackFrom.empty())
    throw Error(located(r.file, r.line(tr), where + ".training: handover_back and handover_back_from go together (the "
                                                   "share of episodes that start under a child, and which child)"));
}

// [skill.NAME.training]: the budget and the handover episodes; after [commands] (the steers need its wz range)
void parseTraining(const Reader& r, const toml::table& tr, const std::string& where, SkillDef* s) {
  r.onlyKeys(tr, {"steps", "envs", "only_positive_rewards", "handover", "handover_s", "handover_from", "handover_via_s", "handover_vx",
                  "handover_back", "handover_back_from", "handover_back_s", "line_jitter", "line_steer", "heading_steer", "heading_steer_share"}, where + ".training");
  if (const toml::node* op = tr.get("only_positive_rewards")) {
    auto b = op->value<bool>();
    if (!b) throw Error(located(r.file, r.line(*op), where + ".training.only_positive_rewards must be true or false"));
    s->onlyPositiveRewards = *b;
  }
  s->trainingSteps = int64_t(r.number(tr, "steps", 1e7, 1, 1e10, where + ".training"));
  s->trainingEnvs = int(r.number(tr, "envs", 20, 1, 1024, where + ".training"));
  s->handover = r.number(tr, "handover", 0, 0, 1, where + ".training");
  s->handoverSeconds = r.range(tr, "handover_s", {1.0, 3.0}, 0.01, 60, where + ".training");
  s->handoverViaSeconds = r.range(tr, "handover_via_s", {0.0, 0.0}, 0.0, 60, where + ".training");
  s->handoverVx = r.range(tr, "handover_vx", {0.0, 0.0}, -10, 10, where + ".training");
  if (const toml::node* hf = tr.get("handover_from")) {
    const std::optional<std::string> name = hf->value<std::string>();
    if (!name) throw Error(located(r.file, r.line(*hf), where + ".training.handover_from must be a skill name"));
    s->handoverFrom = *name;
  }
  if (const toml::node* hv = tr.get("handover_via_s"); hv && (s->handoverFrom.empty() || s->handoverFrom == s->parent))
    throw Error(located(r.file, r.line(*hv), where + ".training.handover_via_s is the time in the skills between handover_from "
                                                   "and this one, and there are none (handover_from is the parent)"));
  if (s->handover > 0 && s->parent.empty())
    throw Error(located(r.file, r.line(*tr.get("handover")), where + ".training.handover needs a parent skill"));
  parseTrainingSteers(r, tr, where, s);
  parseHandoverBack(r, tr, where, s);
}

// [skill.NAME.ball]; after [commands] (the ball takes the aux command slots)
void parseBall(const Reader& r, const toml::table& bt, const std::string& where, SkillDef* s) {
  const std::string w = where + ".ball";
  r.onlyKeys(bt, {"offset", "jitter", "absent"}, w);
  const std::array<double, 2> off = r.pair(bt, "offset", {0.3, -0.12}, -5, 5, w);
  s->ball.enabled = true;
  s->ball.x = off[0];
  s->ball.y = off[1];
  s->ball.jitter = r.number(bt, "jitter", 0.03, 0, 1, w);
  s->ball.absent = r.number(bt, "absent", 0.0, 0, 1, w);
  if (s->commands.lineCommand || s->commands.stepCommand)
    throw Error(located(r.file, r.line(bt), w + ": a ball skill sees its ball in the aux command slots, so it cannot "
                                               "also have [commands] line_command or step_command = true"));
}

// [skill.NAME.terrain]; after [training] (a ceiling needs handover = 1)
void parseTerrain(const Reader& r, const toml::table& tt, const std::string& where, SkillDef* s) {
  const std::string w = where + ".terrain";
  r.onlyKeys(tt, {"type", "steps", "step_depth", "start_x", "top_depth", "width", "lessons", "advance_at", "height", "spawn_along"}, w);
  const std::string type = tt.get("type") && tt.get("type")->value<std::string>() ? *tt.get("type")->value<std::string>() : "";
  if (type != "stairs" && type != "flat" && type != "ceiling")
    throw Error(located(r.file, r.line(tt), w + ".type must be \"stairs\", \"flat\" or \"ceiling\""));
  TerrainDef& d = s->terrain;
  d.kind = type == "stairs" ? TerrainDef::Kind::Stairs : type == "ceiling" ? TerrainDef::Kind::Ceiling : TerrainDef::Kind::Flat;
  d.ceilingHeight = r.number(tt, "height", 0.6, 0.2, 3, w);
  if (d.kind == TerrainDef::Kind::Ceiling && s->handover < 1.0)
    throw Error(located(r.file, r.line(tt), w + ": a ceiling goes over a robot that has lain down: the skill's training needs handover = 1.0"));
  d.steps = int(r.number(tt, "steps", 10, 1, 100, w));
  d.stepDepth = r.number(tt, "step_depth", 0.3, 0.1, 2, w);
  d.startX = r.number(tt, "start_x", 1.0, 0, 20, w);
  d.topDepth = r.number(tt, "top_depth", 1.5, 0.1, 20, w);
  d.width = r.number(tt, "width", 4.0, 0.5, 50, w);
  d.advanceAt = r.number(tt, "advance_at", 1.0, -1e3, 1e3, w);
  if (const toml::node* l = tt.get("lessons")) {
    const toml::array* a = l->as_array();
    if (!a || a->empty()) throw Error(located(r.file, r.line(*l), w + ".lessons must be a non-empty list of step heights"));
    for (const toml::node& h : *a) d.lessons.push_back(r.number(h, w + ".lessons", 0, 0.5));
  }
  d.spawnAlong = r.number(tt, "spawn_along", 0.0, 0.0, 1.0, w);
  if (d.spawnAlong > 0 && d.kind != TerrainDef::Kind::Stairs)
    throw Error(located(r.file, r.line(*tt.get("spawn_along")), w + ".spawn_along starts episodes on a staircase's treads: it needs type = \"stairs\""));
  if (d.kind == TerrainDef::Kind::Stairs && d.lessons.empty())
    throw Error(located(r.file, r.line(tt), w + ": stairs need lessons = [step heights]"));
}

// A command curriculum's last lesson is what the skill ships with: it must be the tree entry's own command range and
// prior. t1 are the T1 lessons as written; errors at the table's line.
void checkCurriculumEnds(const Reader& r, int line, const std::string& w, const std::vector<double>& t1, const SkillDef& s) {
  const CurriculumDef& d = s.curriculum;
  const size_t n = d.lessons();
  if ((!t1.empty() && t1.size() != n) || (!d.stride.empty() && d.stride.size() != n))
    throw Error(located(r.file, line, w + ": T1 and stride need one value per lesson (" + std::to_string(n) + ")"));
  if (!s.terrain.lessons.empty())
    throw Error(located(r.file, line, w + ": a skill has terrain lessons or a command curriculum, not both"));
  if ((!t1.empty() || !d.stride.empty()) && s.prior.kind != PriorDef::Kind::Phase)
    throw Error(located(r.file, line, w + ": T1 and stride lessons are for a \"phase\" prior"));
  if (!d.amplitudeMax.empty() && std::abs(d.amplitudeMax.back() - s.commands.amplitude.hi) > 1e-9)
    throw Error(located(r.file, line, w + ".amplitude_max must end at the commands' amplitude top (" +
                                          std::to_string(s.commands.amplitude.hi) + ")"));
  if (!d.vxMax.empty() && std::abs(d.vxMax.back() - s.commands.vx.hi) > 1e-9)
    throw Error(located(r.file, line, w + ".vx_max must end at the commands' vx top (" + std::to_string(s.commands.vx.hi) + ")"));
  for (double x : d.amplitudeMax)
    if (x < s.commands.amplitude.lo)
      throw Error(located(r.file, line, w + ".amplitude_max: every lesson's top must be at least the commands' amplitude bottom"));
  for (double x : d.vxMax)
    if (x <= s.commands.vx.lo)
      throw Error(located(r.file, line, w + ".vx_max: every lesson's top must be above the commands' vx bottom"));
  if (!d.halfPeriodTicks.empty() && d.halfPeriodTicks.back() != s.prior.halfPeriodTicks)
    throw Error(located(r.file, line, w + ".T1 must end at the prior's T1 (" + std::to_string(s.prior.halfPeriodTicks) + ")"));
  if (!d.stride.empty() && std::abs(d.stride.back() - s.prior.stride) > 1e-9)
    throw Error(located(r.file, line, w + ".stride must end at the prior's stride (" + std::to_string(s.prior.stride) + ")"));
}

// [skill.NAME.curriculum]; after [prior], [commands] and [terrain], which its lessons must agree with
void parseCurriculum(const Reader& r, const toml::table& ct, const std::string& where, SkillDef* s) {
  const std::string w = where + ".curriculum";
  r.onlyKeys(ct, {"vx_max", "amplitude_max", "T1", "stride", "advance_at"}, w);
  CurriculumDef& d = s->curriculum;
  d.advanceAt = r.number(ct, "advance_at", 1.0, -1e3, 1e3, w);
  auto list = [&](const char* key, double lo, double hi, std::vector<double>* out) {
    const toml::node* l = ct.get(key);
    if (!l) return;
    const toml::array* a = l->as_array();
    if (!a || a->empty()) throw Error(located(r.file, r.line(*l), w + "." + key + " must be a non-empty list of numbers"));
    for (const toml::node& x : *a) out->push_back(r.number(x, w + "." + key, lo, hi));
  };
  std::vector<double> t1;
  list("vx_max", 0.01, 10, &d.vxMax);
  list("amplitude_max", 0.0, 1.0, &d.amplitudeMax);
  list("T1", 1, 1000, &t1);
  list("stride", 0, 1, &d.stride);
  for (double x : t1) d.halfPeriodTicks.push_back(int(std::lround(x)));
  if (d.vxMax.empty() == d.amplitudeMax.empty())
    throw Error(located(r.file, r.line(ct), w + " needs one of vx_max = [the forward command's top, per lesson] or "
                                               "amplitude_max = [the amplitude command's top, per lesson]"));
  checkCurriculumEnds(r, r.line(ct), w, t1, *s);
}

// [card] type: the kind of card (*type: as written)
CardDef::Kind cardKind(const Reader& r, const toml::table& c, const std::string& w, std::string* type) {
  *type = c.get("type") && c.get("type")->value<std::string>() ? *c.get("type")->value<std::string>() : "";
  if (*type != "velocity" && *type != "height" && *type != "balance" && *type != "stairs" && *type != "jump" && *type != "kick" &&
      *type != "prone" && *type != "standup" && *type != "pushup" && *type != "crawl")
    throw Error(located(r.file, r.line(c), w + ".type must be \"velocity\", \"height\", \"balance\", \"stairs\", \"jump\", \"kick\", \"prone\", \"standup\", \"pushup\" or \"crawl\""));
  return *type == "velocity" ? CardDef::Kind::Velocity
         : *type == "height" ? CardDef::Kind::Height
         : *type == "balance" ? CardDef::Kind::Balance
         : *type == "stairs"  ? CardDef::Kind::Stairs
         : *type == "jump"    ? CardDef::Kind::Jump
         : *type == "kick"    ? CardDef::Kind::Kick
         : *type == "prone"   ? CardDef::Kind::Prone
         : *type == "pushup"  ? CardDef::Kind::PushUp
         : *type == "crawl"   ? CardDef::Kind::Crawl
                              : CardDef::Kind::StandUp;
}

// What a card of its kind needs of the skill (a parent that lies it down, an up skill, a tunnel), and lead_in, which
// only a branch's card of some kinds has
void parseCardNeeds(const Reader& r, const toml::table& c, const std::string& w, const std::string& type, const SkillDef& s,
                    CardDef* d) {
  if (d->kind == CardDef::Kind::StandUp && (s.parent.empty() || s.up.empty()))
    throw Error(located(r.file, r.line(c), w + ": a standup card needs the skill's parent (it lies down first) and its up skill (it takes over)"));
  if ((d->kind == CardDef::Kind::PushUp || d->kind == CardDef::Kind::Crawl) && s.parent.empty())
    throw Error(located(r.file, r.line(c), w + ": a " + type + " card needs the skill's parent (it lies down first)"));
  if (d->kind == CardDef::Kind::Crawl && s.terrain.kind != TerrainDef::Kind::Ceiling)
    throw Error(located(r.file, r.line(c), w + ": a crawl card runs in a tunnel: the skill needs [terrain] type = \"ceiling\""));
  if (const toml::node* li = c.get("lead_in")) {
    const auto b = li->is_boolean() ? li->value<bool>() : std::nullopt;  // (not 1 or 0)
    if (!b) throw Error(located(r.file, r.line(*li), w + ".lead_in must be true or false"));
    if (*b && (s.parent.empty() || (d->kind != CardDef::Kind::Velocity && d->kind != CardDef::Kind::Height &&
                                    d->kind != CardDef::Kind::Balance && d->kind != CardDef::Kind::Jump &&
                                    d->kind != CardDef::Kind::Kick)))
      throw Error(located(r.file, r.line(*li), w + ".lead_in: only a branch's velocity, height, balance, jump or kick card starts with a lead-in"));
    d->leadIn = *b;
  }
}

// A card's success figures: the ground cards' (crawl, push-ups, stand-up), prone, kick, jump, stairs, balance and
// height; a steering card needs the commands' wz range
void parseCardFigures(const Reader& r, const toml::table& c, const std::string& w, const CommandDef& commands, CardDef* d) {
  d->crawlDistance = r.number(c, "crawl_distance", 5, 0.1, 100, w);
  d->crawlSpeed = r.number(c, "crawl_speed", 0.25, 0.01, 10, w);
  d->steer = r.number(c, "steer", 0, 0, 100, w);
  if (d->steer > 0 && ((d->kind != CardDef::Kind::Crawl && d->kind != CardDef::Kind::Stairs) || !turnsBothWays(commands)))
    throw Error(located(r.file, r.line(*c.get("steer")), w + ".steer: only a crawl or stairs card steers, and the skill's commands "
                                                            "need a wz range either side of 0 (wz = [-x, x]) to steer with"));
  d->pushUps = int(r.number(c, "push_ups", 3, 1, 1000, w));
  d->pushUpRise = r.number(c, "rise", 0.08, 0, 2, w);
  d->proneSeconds = r.number(c, "prone_s", 3, 0.01, 3600, w);
  d->proneHeight = r.number(c, "prone_height", 0.35, 0, 2, w);
  d->pronePitch = r.range(c, "prone_pitch_deg", {70, 110}, -180, 180, w);
  d->lieSeconds = r.range(c, "lie_s", {3.0, 5.5}, 0.01, 60, w);
  d->riseSeconds = r.number(c, "rise_s", 5, 0.01, 60, w);
  d->afterSeconds = r.number(c, "after_s", 3, 0, 600, w);
  d->kickSpeed = r.number(c, "kick_speed", 2.5, 0, 50, w);
  d->kickAngleDegrees = r.number(c, "kick_angle_deg", 15, 0, 180, w);
  d->jumpHeight = r.number(c, "jump_height", 0.10, 0, 2, w);
  d->jumps = int(r.number(c, "jumps", 3, 1, 100, w));
  d->stepHeight = r.number(c, "step_height", 0.15, 0, 0.5, w);
  d->liftHeight = r.number(c, "lift_height", 0.08, 0, 1, w);
  d->liftSeconds = r.number(c, "lift_s", 5, 0, 3600, w);
  d->successPercent = r.number(c, "success_pct", -1, -1, 100, w);
  d->amplitude = r.range(c, "amplitude", {}, 0, 1, w);
  d->heightError = r.number(c, "height_error", -1, -1, 100, w);
}

// A card's episodes, their commands and pushes, the standing episodes and the tracking bars
void parseCardEpisodes(const Reader& r, const toml::table& c, const std::string& w, CardDef* d) {
  d->episodes = int(r.number(c, "episodes", 50, 1, 100000, w));
  d->episodeSeconds = r.number(c, "episode_s", 20, 0.1, 3600, w);
  d->segmentSeconds = r.number(c, "segment_s", d->episodeSeconds, 0.1, 3600, w);
  d->settleSeconds = r.number(c, "settle_s", 1, 0, 3600, w);
  d->vx = r.range(c, "vx", {}, -5, 5, w);
  d->vy = r.range(c, "vy", {}, -5, 5, w);
  d->wz = r.range(c, "wz", {}, -5, 5, w);
  if (const toml::node* m = c.get("mix")) {
    const toml::array* a = m->as_array();
    double sum = 0;
    if (!a || a->size() != 4) throw Error(located(r.file, r.line(*m), w + ".mix must be 4 numbers: forward, sideways, turn, zero"));
    for (size_t i = 0; i < 4; ++i) {
      d->mix[i] = r.number((*a)[i], w + ".mix", 0, 1);
      sum += d->mix[i];
    }
    if (std::abs(sum - 1.0) > 1e-6) throw Error(located(r.file, r.line(*m), w + ".mix must add up to 1"));
  }
  d->ramp = r.flag(c, "ramp", d->ramp, w);
  if (const toml::node* p2 = c.get("pushes")) {
    auto b = p2->value<bool>();
    if (!b) throw Error(located(r.file, r.line(*p2), w + ".pushes must be true or false"));
    d->pushes = *b;
  }
  if (c.get("push_speed")) d->pushSpeed = r.range(c, "push_speed", {}, 0, 5, w);
  d->pushEverySeconds = r.number(c, "push_every_s", -1, 0.1, 1000, w);
  d->standEpisodes = int(r.number(c, "stand_episodes", 0, 0, 100000, w));
  d->standSeconds = r.number(c, "stand_s", 10, 0.1, 3600, w);
  d->noFallPercent = r.number(c, "no_fall_pct", -1, -1, 100, w);
  d->speedError = r.number(c, "speed_error", -1, -1, 100, w);
  d->yawError = r.number(c, "yaw_error", -1, -1, 100, w);
  d->standDrift = r.number(c, "stand_drift", -1, -1, 100, w);
}

// The keys a card of each kind reads: ai::runVelocityCard runs the velocity, height, balance, stairs, jump, kick and
// prone cards, ai::runGroundCard the standup, pushup and crawl cards (assets/skills/README.md lists them)
std::vector<std::string> cardKeys(CardDef::Kind kind) {
  using K = CardDef::Kind;
  std::vector<std::string> keys = {"type", "episodes"};
  auto add = [&](std::initializer_list<const char*> more) { keys.insert(keys.end(), more.begin(), more.end()); };
  if (kind == K::StandUp || kind == K::PushUp || kind == K::Crawl)
    add({"lie_s", "success_pct"});
  else
    add({"episode_s", "segment_s", "settle_s", "vx", "vy", "wz", "amplitude", "mix", "ramp", "pushes", "push_speed",
         "push_every_s", "stand_episodes", "stand_s", "no_fall_pct", "speed_error", "yaw_error", "stand_drift"});
  switch (kind) {
    case K::Velocity: add({"lead_in"}); break;
    case K::Height: add({"height_error", "lead_in"}); break;
    case K::Balance: add({"lift_height", "lift_s", "success_pct", "lead_in"}); break;
    case K::Stairs: add({"step_height", "steer", "success_pct"}); break;
    case K::Jump: add({"jump_height", "jumps", "success_pct", "lead_in"}); break;
    case K::Kick: add({"kick_speed", "kick_angle_deg", "success_pct", "lead_in"}); break;
    case K::Prone: add({"prone_s", "prone_height", "prone_pitch_deg", "success_pct"}); break;
    case K::StandUp: add({"rise_s", "after_s"}); break;
    case K::PushUp: add({"episode_s", "push_ups", "rise"}); break;
    case K::Crawl: add({"episode_s", "vx", "crawl_distance", "crawl_speed", "steer"}); break;
    case K::None: break;
  }
  return keys;
}

// Every key of a card is one that its kind reads (checked after the card's other checks)
void checkCardKeys(const Reader& r, const toml::table& c, const std::string& w, const std::string& type, CardDef::Kind kind) {
  const std::vector<std::string> allowed = cardKeys(kind);
  for (auto&& [k, v] : c)
    if (std::find(allowed.begin(), allowed.end(), k.str()) == allowed.end())
      throw Error(located(r.file, r.line(v), w + "." + std::string(k.str()) + " is not a key of a " + type +
                                                 " card (assets/skills/README.md lists each type's keys)"));
}

// [skill.NAME.card]: the report card; after [commands] and [terrain]
void parseCard(const Reader& r, const toml::table& c, const std::string& where, SkillDef* s) {
  const std::string w = where + ".card";
  r.onlyKeys(c, {"type", "episodes", "episode_s", "segment_s", "settle_s", "vx", "vy", "wz", "mix", "pushes",
                 "stand_episodes", "stand_s", "no_fall_pct", "speed_error", "yaw_error", "stand_drift", "amplitude",
                 "height_error", "lift_height", "lift_s", "success_pct", "step_height", "jump_height", "jumps",
                 "kick_speed", "kick_angle_deg", "ramp", "push_speed", "prone_s", "prone_height", "prone_pitch_deg", "push_every_s",
                 "lie_s", "rise_s", "after_s", "push_ups", "rise", "crawl_distance", "crawl_speed", "steer", "lead_in"}, w);
  std::string type;
  CardDef& d = s->card;
  d.kind = cardKind(r, c, w, &type);
  parseCardNeeds(r, c, w, type, *s, &d);
  parseCardFigures(r, c, w, s->commands, &d);
  parseCardEpisodes(r, c, w, &d);
  checkCardKeys(r, c, w, type, d.kind);
}

// Which of the tables a branch inherits from its parent a skill wrote itself.
struct Given {
  bool gains = false, actionScale = false, actionFilter = false, termination = false, randomisation = false;
};

// Parents exist, the tree has exactly one root, an `up` names another skill, and a skill without a key is
// someone's `up`.
void checkParentsAndKeys(const Reader& r, const SkillTree& tree) {
  int roots = 0;
  for (const SkillDef& s : tree.skills) {
    if (s.parent.empty()) ++roots;
    else if (!tree.find(s.parent)) throw Error(located(r.file, s.line, "skill." + s.name + ": unknown parent '" + s.parent + "'"));
    if (!s.up.empty() && (!tree.find(s.up) || s.up == s.name))
      throw Error(located(r.file, s.line, "skill." + s.name + ": up = '" + s.up + "' is not another skill of the tree"));
    const bool someonesWayUp = std::any_of(tree.skills.begin(), tree.skills.end(), [&](const SkillDef& o) { return o.up == s.name; });
    if (s.key < 0 && !someonesWayUp)
      throw Error(located(r.file, s.line, "skill." + s.name + ": missing key (only a skill that is another's `up`, reached "
                                          "by routing through it, may go without one)"));
  }
  if (roots != 1) throw Error(located(r.file, 0, "the tree needs exactly one root skill (parent = \"\"), found " + std::to_string(roots)));
}

// Every chain of parents reaches the root (no cycles), handover_from names a skill on it, and handover_back_from
// names a child.
void checkAncestry(const Reader& r, const SkillTree& tree) {
  for (const SkillDef& s : tree.skills) {
    const SkillDef* at = &s;
    bool handoverFromAncestor = false;
    for (size_t hops = 0; !at->parent.empty(); ++hops) {
      if (hops > tree.skills.size())
        throw Error(located(r.file, s.line, "skill." + s.name + ": its parents form a cycle and never reach the root"));
      at = tree.find(at->parent);
      handoverFromAncestor = handoverFromAncestor || at->name == s.handoverFrom;
    }
    if (!s.handoverBackFrom.empty()) {
      const SkillDef* child = tree.find(s.handoverBackFrom);
      if (!child || child->parent != s.name)
        throw Error(located(r.file, s.line, "skill." + s.name + ": training.handover_back_from = '" + s.handoverBackFrom +
                                            "' is not one of its children"));
    }
    if (!s.handoverFrom.empty() && !handoverFromAncestor)
      throw Error(located(r.file, s.line, "skill." + s.name + ": training.handover_from = '" + s.handoverFrom +
                                          "' is not one of its ancestors"));
  }
}

// A branch inherits the controller tables it does not write (gains, action_scale, action_filter, termination,
// randomisation) from its parent: resolved from the root down. The root must give gains.
void inheritControllerTables(const Reader& r, std::map<std::string, Given>& given, SkillTree* tree) {
  std::set<std::string> resolved;
  for (const SkillDef& s : tree->skills)
    if (s.parent.empty()) {
      if (!given[s.name].gains) throw Error(located(r.file, s.line, "skill." + s.name + ": the root needs a [gains] table"));
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
      if (!g.randomisation) s.randomisation = p.randomisation;
      resolved.insert(s.name);
    }
}

// A skill's own keys: parent, up, key (unique in the tree: keys holds those taken), model, switch_in_phase, settle_first
void parseSkillKeys(const Reader& r, const toml::table& t, const std::string& where, std::set<int>* keys, SkillDef* s) {
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
    s->key = int(r.number(*key, where + ".key", 0, 9));
    if (!keys->insert(s->key).second) throw Error(located(r.file, r.line(*key), where + ": key " + std::to_string(s->key) + " is taken"));
  }
  s->model = t.get("model") && t.get("model")->value<std::string>() ? *t.get("model")->value<std::string>() : s->name + ".onnx";
  s->switchInPhase = r.range(t, "switch_in_phase", {0.0, 1.0}, 0.0, 1.0, where);
  s->settleFirst = r.flag(t, "settle_first", s->settleFirst, where);
}

// The controller's tables and keys (gains, action_scale, action_filter), and which of the inheritable ones the skill
// writes itself (*g)
void parseController(const Reader& r, const toml::table& t, const std::string& where, const RobotModel& model, SkillDef* s,
                     Given* g) {
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
  g->randomisation = t.get("randomisation") != nullptr;
}

// [skill.NAME]: its keys, then its tables in an order where each finds what it checks against already read
SkillDef parseSkill(const Reader& r, const std::string& name, const toml::node& v, const RobotModel& model, std::set<int>* keys,
                    Given* g) {
  SkillDef s;
  s.name = name;
  s.line = r.line(v);
  const std::string where = "skill." + s.name;
  const toml::table* t = v.as_table();
  if (!t) throw Error(located(r.file, s.line, where + " must be a table"));
  r.onlyKeys(*t, {"parent", "up", "key", "model", "prior", "gains", "action_scale", "action_filter", "commands", "rewards",
                  "termination", "randomisation", "training", "card", "terrain", "curriculum", "ball", "ppo", "switch_in_phase", "settle_first"},
             where);
  parseSkillKeys(r, *t, where, keys, &s);
  if (const toml::table* p = r.table(*t, "prior", false, where)) parsePrior(r, *p, where, model, &s.prior);
  parseController(r, *t, where, model, &s, g);
  if (const toml::table* c = r.table(*t, "commands", false, where)) parseCommands(r, *c, where, s.line, &s.commands);
  parseRewards(r, *r.table(*t, "rewards", true, where), where, &s);
  if (const toml::table* e = r.table(*t, "termination", false, where)) parseTermination(r, *e, where, &s.termination);
  if (const toml::table* d = r.table(*t, "randomisation", false, where)) parseRandomisation(r, *d, where, &s.randomisation);
  if (const toml::table* tr = r.table(*t, "training", false, where)) parseTraining(r, *tr, where, &s);
  if (const toml::table* bt = r.table(*t, "ball", false, where)) parseBall(r, *bt, where, &s);
  if (const toml::table* tt = r.table(*t, "terrain", false, where)) parseTerrain(r, *tt, where, &s);
  if (const toml::table* ct = r.table(*t, "curriculum", false, where)) parseCurriculum(r, *ct, where, &s);
  if (const toml::table* c = r.table(*t, "card", false, where)) parseCard(r, *c, where, &s);
  return s;
}

// The tree file as TOML, its top-level keys checked
toml::table readTreeFile(const Reader& r) {
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

}  // namespace

bool jointInGroup(const std::string& jointName, const std::string& group) {
  return jointName.find(group + "_joint") != std::string::npos;
}

const SkillDef* SkillTree::find(const std::string& name) const {
  for (const SkillDef& s : skills)
    if (s.name == name) return &s;
  return nullptr;
}

SkillTree loadSkillTree(const std::string& path, const RobotModel& model) {
  const Reader r{path};
  const toml::table root = readTreeFile(r);
  SkillTree tree;
  tree.path = path;
  tree.directory = std::filesystem::path(path).parent_path().string();
  if (tree.directory.empty()) tree.directory = ".";  // a bare file name: the models sit beside it, here
  if (const toml::table* ppo = r.table(root, "ppo", false, "tree")) {
    std::ostringstream ss;
    ss << *ppo;
    tree.ppoToml = ss.str();
  }
  std::map<std::string, Given> given;  // which inheritable tables each skill wrote itself
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
