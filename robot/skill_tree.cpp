// skill_tree.cpp — strict TOML loader for the skill tree.
#include "robot/skill_tree.h"

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
      for (const char* g : kGroups) known = known || group == g;
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
  Reader r{path};
  const std::string text = engine::readFile(path);
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw Error(located(path, int(e.source().begin.line), std::string(e.description())));
  }
  r.onlyKeys(root, {"ppo", "skill"}, "the skill tree");
  SkillTree tree;
  tree.path = path;
  tree.directory = std::filesystem::path(path).parent_path().string();
  if (const toml::table* ppo = r.table(root, "ppo", false, "tree")) {
    std::ostringstream ss;
    ss << *ppo;
    tree.ppoToml = ss.str();
  }
  const toml::table* skills = r.table(root, "skill", true, "tree");
  std::set<int> keys;
  for (auto&& [k, v] : *skills) {
    SkillDef s;
    s.name = std::string(k.str());
    s.line = r.line(v);
    const std::string where = "skill." + s.name;
    const toml::table* t = v.as_table();
    if (!t) throw Error(located(path, s.line, where + " must be a table"));
    r.onlyKeys(*t, {"parent", "key", "model", "prior", "gains", "action_scale", "action_filter", "commands", "rewards",
                    "termination", "randomisation", "training"},
               where);
    if (const toml::node* p = t->get("parent")) {
      auto v2 = p->value<std::string>();
      if (!v2) throw Error(located(path, r.line(*p), where + ".parent must be a skill name (\"\" for the root)"));
      s.parent = *v2;
    }
    const toml::node* key = t->get("key");
    if (!key) throw Error(located(path, s.line, where + ": missing key"));
    s.key = int(r.number(*key, where + ".key", 0, 9));
    if (!keys.insert(s.key).second) throw Error(located(path, r.line(*key), where + ": key " + std::to_string(s.key) + " is taken"));
    s.model = t->get("model") && t->get("model")->value<std::string>() ? *t->get("model")->value<std::string>() : s.name + ".onnx";

    if (const toml::table* p = r.table(*t, "prior", false, where)) {
      r.onlyKeys(*p, {"type", "T1", "dh", "d0", "stand_still"}, where + ".prior");
      const std::string type = p->get("type") && p->get("type")->value<std::string>() ? *p->get("type")->value<std::string>() : "";
      if (type == "phase") s.prior.kind = PriorDef::Kind::Phase;
      else if (type == "none") s.prior.kind = PriorDef::Kind::None;
      else throw Error(located(path, r.line(*p), where + ".prior.type must be \"phase\" or \"none\""));
      s.prior.halfPeriodTicks = int(r.number(*p, "T1", 40, 1, 1000, where + ".prior"));
      s.prior.dh = r.number(*p, "dh", 0, -1.5, 1.5, where + ".prior");
      s.prior.d0 = r.number(*p, "d0", 0, -1.5, 1.5, where + ".prior");
      if (const toml::node* ss = p->get("stand_still")) s.prior.standStill = ss->value<bool>().value_or(true);
    }
    r.groups(*r.table(*t, "gains", true, where), where + ".gains", model, &s.kp, &s.kd, 0, 5000);
    for (size_t j = 0; j < size_t(kNumJoints); ++j)
      if (s.kp[j] <= 0) throw Error(located(path, s.line, where + ".gains: no gain for joint " + model.joints[j].name));
    if (const toml::table* a = r.table(*t, "action_scale", false, where))
      r.groups(*a, where + ".action_scale", model, &s.actionScale, nullptr, 0, 2);
    s.actionFilter = r.number(*t, "action_filter", 0.0, 0.0, 0.99, where);
    if (const toml::table* c = r.table(*t, "commands", false, where)) {
      r.onlyKeys(*c, {"vx", "vy", "wz", "zero_probability", "resample_s"}, where + ".commands");
      s.commands.vx = r.range(*c, "vx", {}, -5, 5, where + ".commands");
      s.commands.vy = r.range(*c, "vy", {}, -5, 5, where + ".commands");
      s.commands.wz = r.range(*c, "wz", {}, -5, 5, where + ".commands");
      s.commands.zeroProbability = r.number(*c, "zero_probability", 0.2, 0, 1, where + ".commands");
      s.commands.resampleSeconds = r.number(*c, "resample_s", 5, 0.1, 1000, where + ".commands");
    }
    if (const toml::table* w = r.table(*t, "rewards", true, where))
      for (auto&& [rk, rv] : *w) {
        s.rewardWeights[std::string(rk.str())] = r.number(rv, where + ".rewards." + std::string(rk.str()), -1e6, 1e6);
        s.rewardLines[std::string(rk.str())] = r.line(rv);
      }
    if (const toml::table* e = r.table(*t, "termination", false, where)) {
      r.onlyKeys(*e, {"max_tilt_deg", "min_height", "episode_s"}, where + ".termination");
      s.termination.maxTiltDegrees = r.number(*e, "max_tilt_deg", 30, 1, 180, where + ".termination");
      s.termination.minHeight = r.number(*e, "min_height", 0.5, 0, 2, where + ".termination");
      s.termination.episodeSeconds = r.number(*e, "episode_s", 10, 0.1, 3600, where + ".termination");
    }
    if (const toml::table* d = r.table(*t, "randomisation", false, where)) {
      r.onlyKeys(*d, {"friction", "added_mass", "push_every_s", "push_speed"}, where + ".randomisation");
      s.randomisation.friction = r.range(*d, "friction", {1, 1}, 0.05, 5, where + ".randomisation");
      s.randomisation.addedMass = r.range(*d, "added_mass", {0, 0}, -3, 10, where + ".randomisation");
      s.randomisation.pushEverySeconds = r.number(*d, "push_every_s", 0, 0, 1000, where + ".randomisation");
      s.randomisation.pushSpeed = r.range(*d, "push_speed", {0, 0}, 0, 5, where + ".randomisation");
    }
    if (const toml::table* tr = r.table(*t, "training", false, where)) {
      r.onlyKeys(*tr, {"steps", "envs", "only_positive_rewards"}, where + ".training");
      if (const toml::node* op = tr->get("only_positive_rewards")) {
        auto b = op->value<bool>();
        if (!b) throw Error(located(path, r.line(*op), where + ".training.only_positive_rewards must be true or false"));
        s.onlyPositiveRewards = *b;
      }
      s.trainingSteps = int64_t(r.number(*tr, "steps", 1e7, 1, 1e10, where + ".training"));
      s.trainingEnvs = int(r.number(*tr, "envs", 20, 1, 1024, where + ".training"));
    }
    tree.skills.push_back(std::move(s));
  }
  // parents exist and the tree has exactly one root
  int roots = 0;
  for (const SkillDef& s : tree.skills) {
    if (s.parent.empty()) ++roots;
    else if (!tree.find(s.parent)) throw Error(located(path, s.line, "skill." + s.name + ": unknown parent '" + s.parent + "'"));
  }
  if (roots != 1) throw Error(located(path, 0, "the tree needs exactly one root skill (parent = \"\"), found " + std::to_string(roots)));
  // every chain of parents must reach the root (no cycles)
  for (const SkillDef& s : tree.skills) {
    const SkillDef* at = &s;
    for (size_t hops = 0; !at->parent.empty(); ++hops) {
      if (hops > tree.skills.size())
        throw Error(located(path, s.line, "skill." + s.name + ": its parents form a cycle and never reach the root"));
      at = tree.find(at->parent);
    }
  }
  return tree;
}

std::string defaultSkillTreePath() { return engine::projectFile("assets/skills/tree.toml"); }

}  // namespace robot
