// training_tree.cpp — strict TOML loader for the tables of the skill tree that training and the cards own: [draws],
// [rewards], [randomisation], [training], [ball], [terrain], [curriculum] and [card], a parser per table called by
// parseSpec in an order where each finds what it checks against already read, after robot::loadSkillTree has read
// and checked the runtime's tables of the same file. Then the checks that need the whole tree (checkHandoverSkills)
// and the inheritance of [randomisation].
#include "ai/tree/training_tree.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "ai/ppo/ppo_config.h"
#include "ai/rewards/reward_terms.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "robot/tree_reader.h"

namespace ai {
namespace {

using engine::Error;
using engine::located;
using robot::TreeReader;
using robot::turnsBothWays;

// [skill.NAME.draws]: how training draws the commands
void parseDraws(const TreeReader& r, const toml::table& c, const std::string& where, CommandDraws* d) {
  const std::string w = where + ".draws";
  r.onlyKeys(c,
             {"zero_probability", "resample_s", "resample_jitter", "ramp", "steer", "turn_in_place", "amplitude_zero",
              "amplitude_rate"},
             w);
  d->zeroProbability = r.number(c, "zero_probability", 0.2, 0, 1, w);
  d->resampleSeconds = r.number(c, "resample_s", 5, 0.1, 1000, w);
  d->resampleJitter = r.number(c, "resample_jitter", 0, 0, 0.9, w);
  d->ramp = r.flag(c, "ramp", d->ramp, w);
  d->steer = r.number(c, "steer", 0, 0, 2, w);
  d->turnInPlace = r.flag(c, "turn_in_place", d->turnInPlace, w);
  d->amplitudeZero = r.number(c, "amplitude_zero", 0, 0, 1, w);
  d->amplitudeRate = r.number(c, "amplitude_rate", 0, 0, 100, w);
}

// [skill.NAME.rewards]: term = weight (the terms are checked where the rewards are built)
void parseRewards(const TreeReader& r, const toml::table& w, const std::string& where, SkillSpec* s) {
  for (auto&& [rk, rv] : w) {
    s->rewardWeights[std::string(rk.str())] = r.number(rv, where + ".rewards." + std::string(rk.str()), -1e6, 1e6);
    s->rewardLines[std::string(rk.str())] = r.line(rv);
  }
}

// [skill.NAME.randomisation], read whole
void parseRandomisation(const TreeReader& r, const toml::table& d, const std::string& where, RandomisationDef* out) {
  r.onlyKeys(d, {"friction", "added_mass", "push_every_s", "push_speed"}, where + ".randomisation");
  out->friction = r.range(d, "friction", {1, 1}, 0.05, 5, where + ".randomisation");
  out->addedMass = r.range(d, "added_mass", {0, 0}, -3, 10, where + ".randomisation");
  out->pushEverySeconds = r.number(d, "push_every_s", 0, 0, 1000, where + ".randomisation");
  out->pushSpeed = r.range(d, "push_speed", {0, 0}, 0, 5, where + ".randomisation");
}

// [skill.NAME.training] line_jitter, heading_steer and heading_steer_share: how training steers, which needs the
// skill's commands
void parseTrainingSteers(const TreeReader& r, const toml::table& tr, const std::string& where, SkillSpec* s) {
  if (const toml::node* lj = tr.get("line_jitter")) {
    if (!s->commands.lineCommand)
      throw Error(located(r.file, r.line(*lj),
                          where + ".training.line_jitter moves the line a skill sees, and it sees none "
                                  "([commands] line_command = true)"));
    const std::array<double, 2> j = r.pair(tr, "line_jitter", {0.0, 0.0}, 0.0, 2.0, where + ".training");
    s->lineJitterHeading = j[0], s->lineJitterOffset = j[1];
  }
  s->headingSteer = r.number(tr, "heading_steer", 0, 0, 100, where + ".training");
  if (s->headingSteer > 0 && !turnsBothWays(s->commands))
    throw Error(located(r.file, r.line(*tr.get("heading_steer")),
                        where + ".training.heading_steer steers with wz, and the "
                                "skill's commands need a wz range either side of 0 (wz = [-x, x])"));
  s->headingSteerShare = r.number(tr, "heading_steer_share", 1.0, 0.0, 1.0, where + ".training");
  if (tr.contains("heading_steer_share") && s->headingSteer <= 0)
    throw Error(located(r.file, r.line(*tr.get("heading_steer_share")),
                        where + ".training.heading_steer_share is the share of "
                                "episodes heading_steer steers; set heading_steer too"));
  if (s->headingSteer > 0 && s->commands.lineSteer > 0)
    throw Error(located(r.file, r.line(*tr.get("heading_steer")),
                        where + ".training: heading_steer and [commands] line_steer "
                                "both set the yaw-rate command; choose one"));
}

// [skill.NAME.training] handover_back, handover_back_s and handover_back_from: episodes that start under a child
// (that it is one is checked with the whole tree, checkAncestry)
void parseHandoverBack(const TreeReader& r, const toml::table& tr, const std::string& where, SkillSpec* s) {
  s->handoverBack = r.number(tr, "handover_back", 0, 0, 1, where + ".training");
  s->handoverBackSeconds = r.range(tr, "handover_back_s", {1.0, 3.0}, 0.01, 60, where + ".training");
  if (const toml::node* hb = tr.get("handover_back_from")) {
    const std::optional<std::string> name = hb->value<std::string>();
    if (!name) throw Error(located(r.file, r.line(*hb), where + ".training.handover_back_from must be a skill name"));
    s->handoverBackFrom = *name;
  }
  if (s->handover + s->handoverBack > 1.0)
    throw Error(located(r.file, r.line(*tr.get("handover_back")),
                        where + ".training.handover + handover_back must be at most 1 "
                                "(they are shares of the training episodes)"));
  if ((s->handoverBack > 0) != !s->handoverBackFrom.empty())
    throw Error(located(r.file, r.line(tr),
                        where + ".training: handover_back and handover_back_from go together (the "
                                "share of episodes that start under a child, and which child)"));
}

// [skill.NAME.training]: the budget and the handover episodes; after [commands] (the steers need its wz range)
void parseTraining(const TreeReader& r, const toml::table& tr, const std::string& where, SkillSpec* s) {
  r.onlyKeys(tr,
             {"steps", "envs", "only_positive_rewards", "handover", "handover_s", "handover_from", "handover_via_s",
              "handover_vx", "handover_back", "handover_back_from", "handover_back_s", "line_jitter", "heading_steer",
              "heading_steer_share", "play_entries", "play_share"},
             where + ".training");
  if (const toml::node* op = tr.get("only_positive_rewards")) {
    auto b = op->value<bool>();
    if (!b) throw Error(located(r.file, r.line(*op), where + ".training.only_positive_rewards must be true or false"));
    s->onlyPositiveRewards = *b;
  }
  s->trainingSteps = int64_t(r.integer(tr, "steps", 10000000, 1, 1e10, where + ".training"));
  s->trainingEnvs = int(r.integer(tr, "envs", 20, 1, 1024, where + ".training"));
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
    throw Error(located(r.file, r.line(*hv),
                        where + ".training.handover_via_s is the time in the skills between handover_from "
                                "and this one, and there are none (handover_from is the parent)"));
  if (s->handover > 0 && s->parent.empty())
    throw Error(located(r.file, r.line(*tr.get("handover")), where + ".training.handover needs a parent skill"));
  parseTrainingSteers(r, tr, where, s);
  parseHandoverBack(r, tr, where, s);
  s->playShare = r.number(tr, "play_share", 0, 0, 1, where + ".training");
  if (const toml::node* pe = tr.get("play_entries")) {
    const std::optional<std::string> name = pe->value<std::string>();
    if (!name || name->empty() || name->find_first_of("/\\") != std::string::npos || *name == "." || *name == "..")
      throw Error(located(r.file, r.line(*pe),
                          where + ".training.play_entries must be a file name in the tree's folder (no path)"));
    s->playEntries = *name;
  }
  if ((s->playShare > 0) != !s->playEntries.empty())
    throw Error(located(r.file, r.line(tr),
                        where + ".training: play_share and play_entries go together (the share of episodes that "
                                "start from play's handover states, and the file holding them)"));
}

// [skill.NAME.ball]; after [commands] (the ball takes the aux command slots)
void parseBall(const TreeReader& r, const toml::table& bt, const std::string& where, SkillSpec* s) {
  const std::string w = where + ".ball";
  r.onlyKeys(bt, {"offset", "jitter", "absent"}, w);
  const std::array<double, 2> off = r.pair(bt, "offset", {0.3, -0.12}, -5, 5, w);
  s->ball.enabled = true;
  s->ball.x = off[0];
  s->ball.y = off[1];
  s->ball.jitter = r.number(bt, "jitter", 0.03, 0, 1, w);
  s->ball.absent = r.number(bt, "absent", 0.0, 0, 1, w);
  if (!s->commands.ballCommand)
    throw Error(located(r.file, r.line(bt),
                        w + ": a ball skill sees its ball in the aux command slots: it needs "
                            "[commands] ball_command = true"));
}

// rise, tread and steps as [low, high] (a terrain's or a stairs card's): a staircase drawn for each episode; all
// three or none
void parseStairsDraw(const TreeReader& r, const toml::table& t, const std::string& w, StairsDraw* d) {
  const toml::node* rise = t.get("rise");
  const toml::node* steps = t.get("steps");
  const bool stepsRange = steps && steps->as_array();
  if (!rise && !t.get("tread") && !stepsRange) return;
  if (!rise || !t.get("tread") || !stepsRange)
    throw Error(located(r.file, r.line(t),
                        w + ": stairs drawn for each episode need rise, tread and steps, each as "
                            "[low, high]"));
  d->rise = r.range(t, "rise", {}, 0.01, 0.5, w);
  d->tread = r.range(t, "tread", {}, 0.1, 2, w);
  d->steps = r.range(t, "steps", {}, 1, 100, w);
  for (const toml::node& n : *steps->as_array()) r.integer(n, w + ".steps", 1, 100);
}

// [skill.NAME.terrain]; after [training] (a ceiling needs handover = 1)
void parseTerrain(const TreeReader& r, const toml::table& tt, const std::string& where, SkillSpec* s) {
  const std::string w = where + ".terrain";
  r.onlyKeys(tt,
             {"type", "steps", "step_depth", "start_x", "top_depth", "width", "lessons", "advance_at", "height",
              "spawn_along", "rise", "tread", "entry_heading_deg"},
             w);
  const std::string type =
      tt.get("type") && tt.get("type")->value<std::string>() ? *tt.get("type")->value<std::string>() : "";
  if (type != "stairs" && type != "flat" && type != "ceiling")
    throw Error(located(r.file, r.line(tt), w + ".type must be \"stairs\", \"flat\" or \"ceiling\""));
  TerrainDef& d = s->terrain;
  d.kind = type == "stairs"    ? TerrainDef::Kind::Stairs
           : type == "ceiling" ? TerrainDef::Kind::Ceiling
                               : TerrainDef::Kind::Flat;
  d.ceilingHeight = r.number(tt, "height", 0.6, 0.2, 3, w);
  if (d.kind == TerrainDef::Kind::Ceiling && s->handover < 1.0)
    throw Error(
        located(r.file, r.line(tt),
                w + ": a ceiling goes over a robot that has lain down: the skill's training needs handover = 1.0"));
  parseStairsDraw(r, tt, w, &d.draw);
  if (d.draw.drawn()) {  // the written staircase is the draw's largest (the card's figures and a spawn's range)
    d.steps = int(d.draw.steps.hi), d.stepDepth = d.draw.tread.hi;
    if (tt.get("step_depth"))
      throw Error(located(r.file, r.line(*tt.get("step_depth")), w + ".step_depth: the tread is drawn (tread)"));
  } else {
    d.steps = int(r.integer(tt, "steps", 10, 1, 100, w));
    d.stepDepth = r.number(tt, "step_depth", 0.3, 0.1, 2, w);
  }
  if (tt.get("entry_heading_deg")) d.entryYaw = r.number(tt, "entry_heading_deg", 0, 0, 90, w) * M_PI / 180.0;
  d.startX = r.number(tt, "start_x", 1.0, 0, 20, w);
  d.topDepth = r.number(tt, "top_depth", 1.5, 0.1, 20, w);
  d.width = r.number(tt, "width", 4.0, 0.5, 50, w);
  d.advanceAt = r.number(tt, "advance_at", 1.0, -1e3, 1e3, w);
  if (const toml::node* l = tt.get("lessons")) {
    const toml::array* a = l->as_array();
    if (!a || a->empty())
      throw Error(located(r.file, r.line(*l), w + ".lessons must be a non-empty list of step heights"));
    for (const toml::node& h : *a) d.lessons.push_back(r.number(h, w + ".lessons", 0, 0.5));
  }
  d.spawnAlong = r.number(tt, "spawn_along", 0.0, 0.0, 1.0, w);
  if (d.spawnAlong > 0 && d.kind != TerrainDef::Kind::Stairs)
    throw Error(located(r.file, r.line(*tt.get("spawn_along")),
                        w + ".spawn_along starts episodes on a staircase's treads: it needs type = \"stairs\""));
  if (d.kind == TerrainDef::Kind::Stairs && d.lessons.empty() && !d.draw.drawn())
    throw Error(located(r.file, r.line(tt), w + ": stairs need lessons = [step heights] or rise = [low, high]"));
  if (d.draw.drawn() && (!d.lessons.empty() || d.kind != TerrainDef::Kind::Stairs))
    throw Error(located(r.file, r.line(tt),
                        w + ": rise, tread and steps draw a staircase per episode: type = \"stairs\" without lessons"));
}

// A command curriculum's last lesson is what the skill ships with: it must be the tree entry's own command range and
// prior. t1 are the T1 lessons as written; errors at the table's line.
void checkCurriculumEnds(const TreeReader& r, int line, const std::string& w, const std::vector<double>& t1,
                         const SkillSpec& s) {
  const CurriculumDef& d = s.curriculum;
  const size_t n = d.lessons();
  if ((!t1.empty() && t1.size() != n) || (!d.stride.empty() && d.stride.size() != n))
    throw Error(located(r.file, line, w + ": T1 and stride need one value per lesson (" + std::to_string(n) + ")"));
  if (!s.terrain.lessons.empty())
    throw Error(located(r.file, line, w + ": a skill has terrain lessons or a command curriculum, not both"));
  if ((!t1.empty() || !d.stride.empty()) && s.prior.kind != robot::PriorDef::Kind::Phase)
    throw Error(located(r.file, line, w + ": T1 and stride lessons are for a \"phase\" prior"));
  if (!d.amplitudeMax.empty() && std::abs(d.amplitudeMax.back() - s.commands.amplitude.hi) > 1e-9)
    throw Error(located(r.file, line,
                        w + ".amplitude_max must end at the commands' amplitude top (" +
                            std::to_string(s.commands.amplitude.hi) + ")"));
  if (!d.vxMax.empty() && std::abs(d.vxMax.back() - s.commands.vx.hi) > 1e-9)
    throw Error(located(r.file, line,
                        w + ".vx_max must end at the commands' vx top (" + std::to_string(s.commands.vx.hi) + ")"));
  for (double x : d.amplitudeMax)
    if (x < s.commands.amplitude.lo)
      throw Error(located(r.file, line,
                          w + ".amplitude_max: every lesson's top must be at least the commands' amplitude bottom"));
  for (double x : d.vxMax)
    if (x <= s.commands.vx.lo)
      throw Error(located(r.file, line, w + ".vx_max: every lesson's top must be above the commands' vx bottom"));
  if (!d.halfPeriodTicks.empty() && d.halfPeriodTicks.back() != s.prior.halfPeriodTicks)
    throw Error(
        located(r.file, line, w + ".T1 must end at the prior's T1 (" + std::to_string(s.prior.halfPeriodTicks) + ")"));
  if (!d.stride.empty() && std::abs(d.stride.back() - s.prior.stride) > 1e-9)
    throw Error(
        located(r.file, line, w + ".stride must end at the prior's stride (" + std::to_string(s.prior.stride) + ")"));
}

// [skill.NAME.curriculum]; after [prior], [commands] and [terrain], which its lessons must agree with
void parseCurriculum(const TreeReader& r, const toml::table& ct, const std::string& where, SkillSpec* s) {
  const std::string w = where + ".curriculum";
  r.onlyKeys(ct, {"vx_max", "amplitude_max", "T1", "stride", "advance_at"}, w);
  CurriculumDef& d = s->curriculum;
  d.advanceAt = r.number(ct, "advance_at", 1.0, -1e3, 1e3, w);
  auto list = [&](const char* key, double lo, double hi, std::vector<double>* out) {
    const toml::node* l = ct.get(key);
    if (!l) return;
    const toml::array* a = l->as_array();
    if (!a || a->empty())
      throw Error(located(r.file, r.line(*l), w + "." + key + " must be a non-empty list of numbers"));
    for (const toml::node& x : *a) out->push_back(r.number(x, w + "." + key, lo, hi));
  };
  std::vector<double> t1;
  list("vx_max", 0.01, 10, &d.vxMax);
  list("amplitude_max", 0.0, 1.0, &d.amplitudeMax);
  list("T1", 1, 1000, &t1);
  list("stride", 0, 1, &d.stride);
  for (double x : t1) d.halfPeriodTicks.push_back(int(std::lround(x)));
  if (d.vxMax.empty() == d.amplitudeMax.empty())
    throw Error(located(r.file, r.line(ct),
                        w + " needs one of vx_max = [the forward command's top, per lesson] or "
                            "amplitude_max = [the amplitude command's top, per lesson]"));
  checkCurriculumEnds(r, r.line(ct), w, t1, *s);
}

// [card] type: the kind of card (*type: as written)
// [card] type: a card of that kind with its defaults (*type: as written)
CardDef::Kinds cardOfType(const TreeReader& r, const toml::table& c, const std::string& w, std::string* type) {
  *type = c.get("type") && c.get("type")->value<std::string>() ? *c.get("type")->value<std::string>() : "";
  if (*type == "velocity") return VelocityCard{};
  if (*type == "height") return HeightCard{};
  if (*type == "balance") return BalanceCard{};
  if (*type == "stairs") return StairsCard{};
  if (*type == "jump") return JumpCard{};
  if (*type == "kick") return KickCard{};
  if (*type == "prone") return ProneCard{};
  if (*type == "standup") return StandUpCard{};
  if (*type == "pushup") return PushUpCard{};
  if (*type == "crawl") return CrawlCard{};
  throw Error(located(r.file, r.line(c),
                      w + ".type must be \"velocity\", \"height\", \"balance\", \"stairs\", \"jump\", "
                          "\"kick\", \"prone\", \"standup\", \"pushup\" or \"crawl\""));
}

// The keys a card of each kind reads (assets/skills/README.md lists them)
std::vector<std::string> cardKeys(CardKind kind) {
  using K = CardKind;
  std::vector<std::string> keys = {"type", "episodes"};
  auto add = [&](std::initializer_list<const char*> more) { keys.insert(keys.end(), more.begin(), more.end()); };
  if (kind == K::StandUp || kind == K::PushUp || kind == K::Crawl)
    add({"lie_s", "success_pct"});
  else
    add({"episode_s", "segment_s", "settle_s", "vx", "vy", "wz", "amplitude", "mix", "ramp", "pushes", "push_speed",
         "push_every_s", "stand_episodes", "stand_s", "no_fall_pct", "speed_error", "yaw_error", "stand_drift"});
  switch (kind) {
    case K::Velocity:
      add({"lead_in"});
      break;
    case K::Height:
      add({"height_error", "lead_in"});
      break;
    case K::Balance:
      add({"lift_height", "lift_s", "success_pct", "lead_in"});
      break;
    case K::Stairs:
      add({"step_height", "steer", "success_pct", "rise", "tread", "steps", "heading_deg"});
      break;
    case K::Jump:
      add({"jump_height", "jumps", "success_pct", "lead_in"});
      break;
    case K::Kick:
      add({"kick_speed", "kick_angle_deg", "success_pct", "lead_in"});
      break;
    case K::Prone:
      add({"prone_s", "prone_height", "prone_pitch_deg", "success_pct"});
      break;
    case K::StandUp:
      add({"rise_s", "after_s"});
      break;
    case K::PushUp:
      add({"episode_s", "push_ups", "rise"});
      break;
    case K::Crawl:
      add({"episode_s", "vx", "crawl_distance", "crawl_speed", "steer"});
      break;
    case K::None:
      break;
  }
  return keys;
}

// Every key of a card is one that its kind reads
void checkCardKeys(const TreeReader& r, const toml::table& c, const std::string& w, const std::string& type,
                   CardKind kind) {
  const std::vector<std::string> allowed = cardKeys(kind);
  for (auto&& [k, v] : c)
    if (std::find(allowed.begin(), allowed.end(), k.str()) == allowed.end())
      throw Error(located(r.file, r.line(v),
                          w + "." + std::string(k.str()) + " is not a key of a " + type +
                              " card (assets/skills/README.md lists each type's keys)"));
}

// What a card of its kind needs of the skill: a parent that lies it down, an up skill, a tunnel
void checkCardNeeds(const TreeReader& r, const toml::table& c, const std::string& w, const std::string& type,
                    const SkillSpec& s, CardKind kind) {
  if (kind == CardKind::StandUp && (s.parent.empty() || s.up.empty()))
    throw Error(
        located(r.file, r.line(c),
                w + ": a standup card needs the skill's parent (it lies down first) and its up skill (it takes over)"));
  if ((kind == CardKind::PushUp || kind == CardKind::Crawl) && s.parent.empty())
    throw Error(located(r.file, r.line(c), w + ": a " + type + " card needs the skill's parent (it lies down first)"));
  if (kind == CardKind::Crawl && s.terrain.kind != TerrainDef::Kind::Ceiling)
    throw Error(located(r.file, r.line(c),
                        w + ": a crawl card runs in a tunnel: the skill needs [terrain] type = \"ceiling\""));
}

// steer (a crawl or stairs card's): the skill's commands must turn both ways to steer with
double cardSteer(const TreeReader& r, const toml::table& c, const std::string& w, const robot::CommandDef& commands) {
  const double steer = r.number(c, "steer", 0, 0, 100, w);
  if (steer > 0 && !turnsBothWays(commands))
    throw Error(located(r.file, r.line(*c.get("steer")),
                        w + ".steer: the skill's commands need a wz range either side of "
                            "0 (wz = [-x, x]) to steer with"));
  return steer;
}

// A driven card's episodes, their commands and pushes, the standing episodes, the tracking bars and the lead-in
void parseDriven(const TreeReader& r, const toml::table& c, const std::string& w, const SkillSpec& s, DrivenCard* d) {
  d->episodeSeconds = r.number(c, "episode_s", 20, 0.1, 3600, w);
  d->segmentSeconds = r.number(c, "segment_s", d->episodeSeconds, 0.1, 3600, w);
  d->settleSeconds = r.number(c, "settle_s", 1, 0, 3600, w);
  d->vx = r.range(c, "vx", {}, -5, 5, w);
  d->vy = r.range(c, "vy", {}, -5, 5, w);
  d->wz = r.range(c, "wz", {}, -5, 5, w);
  d->amplitude = r.range(c, "amplitude", {}, 0, 1, w);
  if (const toml::node* m = c.get("mix")) {
    const toml::array* a = m->as_array();
    double sum = 0;
    if (!a || a->size() != 4)
      throw Error(located(r.file, r.line(*m), w + ".mix must be 4 numbers: forward, sideways, turn, zero"));
    for (size_t i = 0; i < 4; ++i) {
      d->mix[i] = r.number((*a)[i], w + ".mix", 0, 1);
      sum += d->mix[i];
    }
    if (std::abs(sum - 1.0) > 1e-6) throw Error(located(r.file, r.line(*m), w + ".mix must add up to 1"));
  }
  d->ramp = r.flag(c, "ramp", d->ramp, w);
  d->pushes = r.flag(c, "pushes", d->pushes, w);
  if (c.get("push_speed")) d->pushSpeed = r.range(c, "push_speed", {}, 0, 5, w);
  d->pushEverySeconds = r.number(c, "push_every_s", -1, 0.1, 1000, w);
  d->standEpisodes = int(r.integer(c, "stand_episodes", 0, 0, 100000, w));
  d->standSeconds = r.number(c, "stand_s", 10, 0.1, 3600, w);
  d->noFallPercent = r.number(c, "no_fall_pct", -1, -1, 100, w);
  d->speedError = r.number(c, "speed_error", -1, -1, 100, w);
  d->yawError = r.number(c, "yaw_error", -1, -1, 100, w);
  d->standDrift = r.number(c, "stand_drift", -1, -1, 100, w);
  d->leadIn = r.flag(c, "lead_in", false, w);
  if (d->leadIn && s.parent.empty())
    throw Error(located(r.file, r.line(*c.get("lead_in")),
                        w + ".lead_in: only a branch's card starts with a lead-in (the "
                            "parent drives first)"));
}

// A kind's own figures (the driven and lying parts are read before)
void parseKind(const TreeReader& r, const toml::table& c, const std::string& w, const SkillSpec& s, CardDef* card) {
  if (auto* k = card->as<HeightCard>()) k->heightError = r.number(c, "height_error", -1, -1, 100, w);
  if (auto* k = card->as<BalanceCard>()) {
    k->liftHeight = r.number(c, "lift_height", 0.08, 0, 1, w);
    k->liftSeconds = r.number(c, "lift_s", 5, 0, 3600, w);
  }
  if (auto* k = card->as<StairsCard>()) {
    k->stepHeight = r.number(c, "step_height", 0.15, 0, 0.5, w);
    k->steer = cardSteer(r, c, w, s.commands);
    parseStairsDraw(r, c, w, &k->draw);
    if (k->draw.drawn() && c.get("step_height"))
      throw Error(located(r.file, r.line(*c.get("step_height")), w + ".step_height: the rise is drawn (rise)"));
    if (c.get("heading_deg")) k->heading = r.number(c, "heading_deg", 0, 0, 90, w) * M_PI / 180.0;
  }
  if (auto* k = card->as<JumpCard>()) {
    k->height = r.number(c, "jump_height", 0.10, 0, 2, w);
    k->jumps = int(r.integer(c, "jumps", 3, 1, 100, w));
  }
  if (auto* k = card->as<KickCard>()) {
    k->speed = r.number(c, "kick_speed", 2.5, 0, 50, w);
    k->angleDegrees = r.number(c, "kick_angle_deg", 15, 0, 180, w);
  }
  if (auto* k = card->as<ProneCard>()) {
    k->seconds = r.number(c, "prone_s", 3, 0.01, 3600, w);
    k->height = r.number(c, "prone_height", 0.35, 0, 2, w);
    k->pitch = r.range(c, "prone_pitch_deg", {70, 110}, -180, 180, w);
  }
  if (auto* k = card->as<StandUpCard>()) {
    k->riseSeconds = r.number(c, "rise_s", 5, 0.01, 60, w);
    k->afterSeconds = r.number(c, "after_s", 3, 0, 600, w);
  }
  if (auto* k = card->as<PushUpCard>()) {
    k->episodeSeconds = r.number(c, "episode_s", 20, 0.1, 3600, w);
    k->pushUps = int(r.integer(c, "push_ups", 3, 1, 1000, w));
    k->rise = r.number(c, "rise", 0.08, 0, 2, w);
  }
  if (auto* k = card->as<CrawlCard>()) {
    k->episodeSeconds = r.number(c, "episode_s", 20, 0.1, 3600, w);
    k->vx = r.range(c, "vx", {}, -5, 5, w);
    k->distance = r.number(c, "crawl_distance", 5, 0.1, 100, w);
    k->speed = r.number(c, "crawl_speed", 0.25, 0.01, 10, w);
    k->steer = cardSteer(r, c, w, s.commands);
  }
}

// [skill.NAME.card]: the report card; after [terrain] (a crawl card's tunnel)
void parseCard(const TreeReader& r, const toml::table& c, const std::string& where, SkillSpec* s) {
  const std::string w = where + ".card";
  std::string type;
  CardDef& d = s->card;
  d.card = cardOfType(r, c, w, &type);
  checkCardKeys(r, c, w, type, d.kind());
  checkCardNeeds(r, c, w, type, *s, d.kind());
  d.episodes = int(r.integer(c, "episodes", 50, 1, 100000, w));
  d.successPercent = r.number(c, "success_pct", -1, -1, 100, w);
  if (DrivenCard* driven = d.driven()) parseDriven(r, c, w, *s, driven);
  if (auto* lying = std::get_if<StandUpCard>(&d.card)) lying->lieSeconds = r.range(c, "lie_s", {3.0, 5.5}, 0.01, 60, w);
  if (auto* lying = std::get_if<PushUpCard>(&d.card)) lying->lieSeconds = r.range(c, "lie_s", {3.0, 5.5}, 0.01, 60, w);
  if (auto* lying = std::get_if<CrawlCard>(&d.card)) lying->lieSeconds = r.range(c, "lie_s", {3.0, 5.5}, 0.01, 60, w);
  parseKind(r, c, w, *s, &d);
}

// handover_from names an ancestor, and handover_back_from a child
void checkHandoverSkills(const TreeReader& r, const TrainingTree& tree) {
  for (const SkillSpec& s : tree.skills) {
    bool fromAncestor = false;
    for (const SkillSpec* at = &s; !at->parent.empty();) {
      at = tree.find(at->parent);
      fromAncestor = fromAncestor || at->name == s.handoverFrom;
    }
    if (!s.handoverBackFrom.empty()) {
      const SkillSpec* child = tree.find(s.handoverBackFrom);
      if (!child || child->parent != s.name)
        throw Error(located(r.file, s.line,
                            "skill." + s.name + ": training.handover_back_from = '" + s.handoverBackFrom +
                                "' is not one of its children"));
    }
    if (!s.handoverFrom.empty() && !fromAncestor)
      throw Error(located(
          r.file, s.line,
          "skill." + s.name + ": training.handover_from = '" + s.handoverFrom + "' is not one of its ancestors"));
  }
}

// A branch without a [randomisation] table takes its parent's: resolved from the root down (robot::loadSkillTree has
// checked that every chain of parents reaches the root)
void inheritRandomisation(const std::set<std::string>& given, TrainingTree* tree) {
  std::set<std::string> resolved;
  while (resolved.size() < tree->skills.size())
    for (SkillSpec& s : tree->skills) {
      if (resolved.count(s.name) || (!s.parent.empty() && !resolved.count(s.parent))) continue;
      if (!s.parent.empty() && !given.count(s.name)) s.randomisation = tree->find(s.parent)->randomisation;
      resolved.insert(s.name);
    }
}

// [skill.NAME]'s training tables, onto the runtime's definition
SkillSpec parseSpec(const TreeReader& r, const robot::SkillDef& def, const toml::table& t, bool* givesRandomisation) {
  SkillSpec s;
  static_cast<robot::SkillDef&>(s) = def;
  const std::string where = "skill." + s.name;
  if (const toml::table* d = r.table(t, "draws", false, where)) parseDraws(r, *d, where, &s.draws);
  parseRewards(r, *r.table(t, "rewards", true, where), where, &s);
  *givesRandomisation = t.get("randomisation") != nullptr;
  if (const toml::table* d = r.table(t, "randomisation", false, where))
    parseRandomisation(r, *d, where, &s.randomisation);
  if (const toml::table* tr = r.table(t, "training", false, where)) parseTraining(r, *tr, where, &s);
  if (const toml::table* bt = r.table(t, "ball", false, where)) parseBall(r, *bt, where, &s);
  if (const toml::table* tt = r.table(t, "terrain", false, where)) parseTerrain(r, *tt, where, &s);
  if (const toml::table* ct = r.table(t, "curriculum", false, where)) parseCurriculum(r, *ct, where, &s);
  if (const toml::table* c = r.table(t, "card", false, where)) parseCard(r, *c, where, &s);
  if (s.commands.ballCommand && !s.ball.enabled)
    throw Error(located(r.file, s.line,
                        where + ": [commands] ball_command shows a ball that training places: it needs a "
                                "[ball] table"));
  return s;
}

}  // namespace

const SkillSpec* TrainingTree::find(const std::string& name) const {
  for (const SkillSpec& s : skills)
    if (s.name == name) return &s;
  return nullptr;
}

TrainingTree loadTrainingTree(const std::string& path, const robot::RobotModel& model) {
  const robot::SkillTree runtime = robot::loadSkillTree(path, model);
  const TreeReader r{path};
  const toml::table root = robot::readTreeFile(r);
  const toml::table& skills = *root.get("skill")->as_table();  // robot::loadSkillTree checked it is there
  TrainingTree tree;
  tree.path = runtime.path;
  tree.directory = runtime.directory;
  std::set<std::string> givesRandomisation;
  for (const robot::SkillDef& def : runtime.skills) {
    bool gives = false;
    tree.skills.push_back(parseSpec(r, def, *skills.get(def.name)->as_table(), &gives));
    if (gives) givesRandomisation.insert(def.name);
  }
  checkHandoverSkills(r, tree);
  inheritRandomisation(givesRandomisation, &tree);
  // what only training reads is checked here too, so that `tree` and `play` refuse a file `train` would: every
  // reward term is a known one, and the [ppo] tables parse
  const std::string text = engine::readFile(path);
  PpoConfig shared = parsePpoConfig(text, path, "ppo");
  for (const SkillSpec& s : tree.skills) {
    resolveRewardTerms(s, path);
    parsePpoConfig(text, path, "skill." + s.name + ".ppo", shared);
  }
  return tree;
}

}  // namespace ai
