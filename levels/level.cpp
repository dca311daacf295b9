// level.cpp — TOML level loader (toml++), strict: unknown keys, wrong types and bad sizes are errors.
#include "levels/level.h"

#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace levels {
namespace {

using engine::Error;
using engine::located;

struct Reader {
  std::string file;

  int line(const toml::node& n) const { return static_cast<int>(n.source().begin.line); }

  void onlyKeys(const toml::table& t, std::initializer_list<const char*> allowed, const std::string& where) const {
    for (auto&& [k, v] : t) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || k == a;
      if (!ok) throw Error(located(file, line(v), "unknown key '" + std::string(k.str()) + "' in " + where));
    }
  }

  double number(const toml::table& t, const char* key, double fallback, bool required, double lo, double hi) const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (required) throw Error(located(file, line(t), std::string("missing '") + key + "'"));
      return fallback;
    }
    auto v = n->value<double>();
    if (!v || !std::isfinite(*v)) throw Error(located(file, line(*n), std::string("'") + key + "' must be a number"));
    if (*v < lo || *v > hi)
      throw Error(located(file, line(*n),
                          std::string("'") + key + "' = " + std::to_string(*v) + " is out of range [" +
                              std::to_string(lo) + ", " + std::to_string(hi) + "]"));
    return *v;
  }

  template <int N>
  Eigen::Matrix<double, N, 1> vec(const toml::table& t, const char* key, bool required, double lo, double hi,
                                  Eigen::Matrix<double, N, 1> fallback = Eigen::Matrix<double, N, 1>::Zero()) const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (required) throw Error(located(file, line(t), std::string("missing '") + key + "'"));
      return fallback;
    }
    const toml::array* a = n->as_array();
    if (!a || a->size() != N)
      throw Error(
          located(file, line(*n), std::string("'") + key + "' must be an array of " + std::to_string(N) + " numbers"));
    Eigen::Matrix<double, N, 1> out;
    for (int i = 0; i < N; ++i) {
      auto v = (*a)[static_cast<size_t>(i)].value<double>();
      if (!v || !std::isfinite(*v))
        throw Error(located(file, line(*n),
                            std::string("'") + key + "' must be an array of " + std::to_string(N) + " numbers"));
      if (*v < lo || *v > hi)
        throw Error(located(file, line(*n),
                            std::string("'") + key + "' has a value out of range [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "]"));
      out[i] = *v;
    }
    return out;
  }

  std::string text(const toml::table& t, const char* key, const std::string& fallback) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    auto v = n->value<std::string>();
    if (!v) throw Error(located(file, line(*n), std::string("'") + key + "' must be a string"));
    // printed into summaries and the HUD as is: no control characters (a line break, an escape sequence)
    for (const char c : *v)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
        throw Error(located(file, line(*n), std::string("'") + key + "' must not hold control characters"));
    return *v;
  }

  uint32_t colour(const toml::table& t, uint32_t fallback) const {
    const toml::node* n = t.get("colour");
    if (!n) return fallback;
    auto v = n->value<std::string>();
    unsigned value = 0;
    if (!v || v->size() != 7 || (*v)[0] != '#' || std::sscanf(v->c_str() + 1, "%6x", &value) != 1 ||
        v->find_first_not_of("#0123456789abcdefABCDEF") != std::string::npos)
      throw Error(located(file, line(*n), "'colour' must be \"#rrggbb\""));
    return (value << 8) | 0xffu;
  }

  const toml::table& table(const toml::node& n, const std::string& what) const {
    const toml::table* t = n.as_table();
    if (!t) throw Error(located(file, line(n), what + " must be a table"));
    return *t;
  }
};

constexpr double kMaxCoord = 1000.0;  // levels live within +-1 km

}  // namespace

Level parseLevel(const std::string& source, const std::string& fileName) {
  Reader r{fileName};
  toml::table root;
  try {
    root = toml::parse(source, fileName);
  } catch (const toml::parse_error& e) {
    throw Error(located(fileName, static_cast<int>(e.source().begin.line), std::string(e.description())));
  }
  r.onlyKeys(root,
             {"name", "description", "plane", "time_limit", "ground", "spawn", "box", "stairs", "wall", "tunnel",
              "rules", "ghost", "coin", "question_box", "ball", "goal"},
             "the level (entity types: box, stairs, wall, tunnel, ghost, coin, question_box, ball, goal; tables: "
             "ground, spawn, rules)");

  Level level;
  level.path = fileName;
  level.hash = engine::hashBytes(source);
  level.name = r.text(root, "name", "");
  if (level.name.empty()) throw Error(located(fileName, 1, "missing 'name = \"...\"'"));
  level.description = r.text(root, "description", "");
  const std::string plane = r.text(root, "plane", "side");
  if (plane == "side")
    level.plane = Plane2d::Side;
  else if (plane == "top")
    level.plane = Plane2d::Top;
  else
    throw Error(located(fileName, r.line(*root.get("plane")), "'plane' must be \"side\" or \"top\""));
  // play runs a game level to its time limit + 0.5 s, and at most 86400 s
  level.timeLimit = r.number(root, "time_limit", 0.0, false, 0.0, 86399.0);

  if (const toml::node* g = root.get("ground")) {
    const toml::table& t = r.table(*g, "[ground]");
    r.onlyKeys(t, {"friction"}, "[ground]");
    level.groundFriction = r.number(t, "friction", 1.0, false, 0.0, 10.0);
  }
  if (const toml::node* s = root.get("spawn")) {
    const toml::table& t = r.table(*s, "[spawn]");
    r.onlyKeys(t, {"position", "yaw"}, "[spawn]");
    level.spawn = r.vec<2>(t, "position", false, -kMaxCoord, kMaxCoord);
    level.spawnYaw = r.number(t, "yaw", 0.0, false, -10.0, 10.0);
  }

  std::set<std::string> names;
  auto addBox = [&](BoxDef b) {
    if (!b.name.empty() && !names.insert(b.name).second)
      throw Error(located(fileName, b.line, "duplicate name '" + b.name + "'"));
    level.boxes.push_back(std::move(b));
  };
  auto arrayOfTables = [&](const char* key) -> std::vector<const toml::table*> {
    std::vector<const toml::table*> out;
    const toml::node* n = root.get(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a)
      throw Error(
          located(fileName, r.line(*n), std::string("'") + key + "' must be written as [[" + key + "]] tables"));
    for (const toml::node& e : *a) out.push_back(&r.table(e, std::string("[[") + key + "]]"));
    return out;
  };

  for (const toml::table* t : arrayOfTables("box")) {
    r.onlyKeys(*t, {"name", "centre", "size", "yaw", "colour", "friction"}, "[[box]]");
    BoxDef b;
    b.line = r.line(*t);
    b.name = r.text(*t, "name", "");
    b.centre = r.vec<3>(*t, "centre", true, -kMaxCoord, kMaxCoord);
    b.size = r.vec<3>(*t, "size", true, 0.0, 2 * kMaxCoord);
    if (b.size.minCoeff() <= 0) throw Error(located(fileName, b.line, "box sizes must be positive"));
    b.yaw = r.number(*t, "yaw", 0.0, false, -10.0, 10.0);
    b.rgba = r.colour(*t, b.rgba);
    b.friction = r.number(*t, "friction", 1.0, false, 0.0, 10.0);
    addBox(std::move(b));
  }

  // a staircase: `steps` boxes rising along +X from `start`, then (if down) as many falling again
  for (const toml::table* t : arrayOfTables("stairs")) {
    r.onlyKeys(*t, {"name", "start", "steps", "rise", "run", "width", "top", "down", "colour"}, "[[stairs]]");
    const int line = r.line(*t);
    const std::string name = r.text(*t, "name", "stairs");
    const Eigen::Vector2d start = r.vec<2>(*t, "start", true, -kMaxCoord, kMaxCoord);
    const double stepsD = r.number(*t, "steps", 0, true, 1, 100);
    if (stepsD != std::floor(stepsD)) throw Error(located(fileName, line, "'steps' must be a whole number"));
    const int steps = static_cast<int>(stepsD);
    const double rise = r.number(*t, "rise", 0, true, 0.001, 1.0);
    const double run = r.number(*t, "run", 0, true, 0.05, 5.0);
    const double width = r.number(*t, "width", 1.5, false, 0.1, 100.0);
    const double top = r.number(*t, "top", run, false, 0.05, 100.0);
    bool down = false;
    if (const toml::node* d = t->get("down")) {
      auto v = d->value<bool>();
      if (!v) throw Error(located(fileName, r.line(*d), "'down' must be true or false"));
      down = *v;
    }
    StairsDef def;
    def.name = name;
    def.start = start;
    def.steps = steps;
    def.rise = rise;
    def.run = run;
    def.width = width;
    def.top = top;
    def.down = down;
    def.rgba = r.colour(*t, 0xc8b08aff);
    def.line = line;
    for (BoxDef& b : expandStairs(def)) addBox(std::move(b));
  }
  // transparent side walls: boxes that collide and are drawn see-through
  for (const toml::table* t : arrayOfTables("wall")) {
    r.onlyKeys(*t, {"name", "centre", "size", "colour"}, "[[wall]]");
    BoxDef b;
    b.line = r.line(*t);
    b.name = r.text(*t, "name", "");
    b.centre = r.vec<3>(*t, "centre", true, -kMaxCoord, kMaxCoord);
    b.size = r.vec<3>(*t, "size", true, 0.0, 2 * kMaxCoord);
    if (b.size.minCoeff() <= 0) throw Error(located(fileName, b.line, "wall sizes must be positive"));
    b.rgba = r.colour(*t, 0x9fc5e8ffu);
    b.seeThrough = true;
    addBox(std::move(b));
  }

  // a tunnel: a ceiling slab over the course, `clearance` above the ground, from x = start for `length`
  for (const toml::table* t : arrayOfTables("tunnel")) {
    r.onlyKeys(*t, {"name", "start", "length", "clearance", "width", "thickness", "colour"}, "[[tunnel]]");
    BoxDef b;
    b.line = r.line(*t);
    b.name = r.text(*t, "name", "tunnel");
    const double start = r.number(*t, "start", 0, true, -kMaxCoord, kMaxCoord);
    const double length = r.number(*t, "length", 0, true, 0.1, 100);
    const double clearance = r.number(*t, "clearance", 0, true, 0.1, 5);
    const double width = r.number(*t, "width", 1.5, false, 0.1, 100);
    const double thickness = r.number(*t, "thickness", 0.2, false, 0.01, 10);
    b.centre = Eigen::Vector3d(start + 0.5 * length, 0.0, clearance + 0.5 * thickness);
    b.size = Eigen::Vector3d(length, width, thickness);
    b.rgba = r.colour(*t, 0x6b8e23ffu);
    addBox(std::move(b));
  }

  if (const toml::node* n = root.get("rules")) {
    const toml::table& t = r.table(*n, "[rules]");
    r.onlyKeys(t, {"falls", "fall_penalty", "coin_value", "gift_value", "win_bonus", "checkpoints"}, "[rules]");
    RulesDef& rules = level.rules;
    rules.present = true;
    const std::string falls = r.text(t, "falls", "respawn");
    if (falls == "lose")
      rules.falls = FallRule::Lose;
    else if (falls == "respawn")
      rules.falls = FallRule::Respawn;
    else
      throw Error(located(fileName, r.line(*t.get("falls")), "'falls' must be \"lose\" or \"respawn\""));
    rules.fallPenalty = int(r.number(t, "fall_penalty", 50, false, 0, 1e6));
    rules.coinValue = int(r.number(t, "coin_value", 10, false, 0, 1e6));
    rules.giftValue = int(r.number(t, "gift_value", 50, false, 0, 1e6));
    rules.winBonus = int(r.number(t, "win_bonus", 100, false, 0, 1e6));
    if (const toml::node* c = t.get("checkpoints")) {
      const toml::array* a = c->as_array();
      if (!a) throw Error(located(fileName, r.line(*c), "'checkpoints' must be a list of x positions"));
      for (const toml::node& x : *a) {
        auto v = x.value<double>();
        if (!v || !std::isfinite(*v))
          throw Error(located(fileName, r.line(*c), "'checkpoints' must be a list of x positions"));
        rules.checkpoints.push_back(*v);
      }
    }
  }
  for (const toml::table* t : arrayOfTables("ghost")) {
    r.onlyKeys(
        *t,
        {"appear_x", "behind", "height", "radius", "speed", "acceleration", "max_speed", "catch_distance", "vanish_x"},
        "[[ghost]]");
    GhostDef g;
    g.line = r.line(*t);
    g.appearX = r.number(*t, "appear_x", 0, true, -kMaxCoord, kMaxCoord);
    g.behind = r.number(*t, "behind", 4.0, false, 0.5, 100);
    g.height = r.number(*t, "height", 1.0, false, 0.1, 10);
    g.radius = r.number(*t, "radius", 0.4, false, 0.05, 5);
    g.speed = r.number(*t, "speed", 0.6, false, 0, 20);
    g.acceleration = r.number(*t, "acceleration", 0.05, false, 0, 20);
    g.maxSpeed = r.number(*t, "max_speed", 2.5, false, 0, 20);
    g.catchDistance = r.number(*t, "catch_distance", 0.3, false, 0, 5);
    if (g.maxSpeed < g.speed) throw Error(located(fileName, g.line, "'max_speed' is below 'speed'"));
    g.vanishX = r.number(*t, "vanish_x", 1e9, false, -kMaxCoord, 1e9);
    if (g.vanishX <= g.appearX) throw Error(located(fileName, g.line, "'vanish_x' must be beyond 'appear_x'"));
    level.ghosts.push_back(g);
  }
  for (const toml::table* t : arrayOfTables("coin")) {
    r.onlyKeys(*t, {"centre", "radius"}, "[[coin]]");
    CoinDef c;
    c.line = r.line(*t);
    c.centre = r.vec<3>(*t, "centre", true, -kMaxCoord, kMaxCoord);
    c.radius = r.number(*t, "radius", 0.15, false, 0.01, 2);
    level.coins.push_back(c);
  }
  for (const toml::table* t : arrayOfTables("question_box")) {
    r.onlyKeys(*t, {"centre", "size", "content"}, "[[question_box]]");
    QuestionBoxDef q;
    q.line = r.line(*t);
    q.centre = r.vec<3>(*t, "centre", true, -kMaxCoord, kMaxCoord);
    q.size = r.vec<3>(*t, "size", false, -2 * kMaxCoord, 2 * kMaxCoord, Eigen::Vector3d(0.4, 0.4, 0.4));
    if (q.size.minCoeff() <= 0) throw Error(located(fileName, q.line, "question box sizes must be positive"));
    const std::string content = r.text(*t, "content", "coin");
    if (content != "coin" && content != "gift")
      throw Error(located(fileName, r.line(*t->get("content")), "'content' must be \"coin\" or \"gift\""));
    q.gift = content == "gift";
    level.questionBoxes.push_back(q);
  }
  for (const toml::table* t : arrayOfTables("ball")) {
    r.onlyKeys(*t, {"position", "radius", "mass"}, "[[ball]]");
    BallSpawnDef b;
    b.line = r.line(*t);
    b.position = r.vec<2>(*t, "position", true, -kMaxCoord, kMaxCoord);
    b.radius = r.number(*t, "radius", 0.11, false, 0.02, 2);
    b.mass = r.number(*t, "mass", 0.43, false, 0.01, 100);
    level.balls.push_back(b);
  }
  for (const toml::table* t : arrayOfTables("goal")) {
    r.onlyKeys(*t, {"centre", "size"}, "[[goal]]");
    GoalDef g;
    g.line = r.line(*t);
    g.centre = r.vec<3>(*t, "centre", true, -kMaxCoord, kMaxCoord);
    g.size = r.vec<3>(*t, "size", true, -2 * kMaxCoord, 2 * kMaxCoord);
    if (g.size.minCoeff() <= 0) throw Error(located(fileName, g.line, "goal sizes must be positive"));
    level.goals.push_back(g);
  }
  if (level.isGame() && level.goals.empty())
    throw Error(
        located(fileName, r.line(*root.get("rules")), "a level with [rules] needs a [[goal]] (nothing to win)"));
  // a map (plane = "top") without rules may have coins to collect and balls lying about; everything else of a game
  // (ghosts chasing along +X, question boxes hit from below, goals to win) belongs to the side-view games
  const bool mapExtras =
      level.plane == Plane2d::Top && level.ghosts.empty() && level.questionBoxes.empty() && level.goals.empty();
  if (!level.isGame() && !mapExtras &&
      (!level.ghosts.empty() || !level.coins.empty() || !level.questionBoxes.empty() || !level.balls.empty() ||
       !level.goals.empty()))
    throw Error(located(fileName, 1,
                        "ghosts, question boxes and goals need a [rules] table (and so do coins and balls in a "
                        "plane = \"side\" level)"));

  // nothing may sit inside a solid box: axis-aligned overlap, ignoring box yaw (the course is axis-aligned)
  auto inside = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& half, int line, const std::string& what) {
    for (const BoxDef& b : level.boxes) {
      const Eigen::Vector3d gap = (c - b.centre).cwiseAbs() - half - 0.5 * b.size;
      if (gap.maxCoeff() < -1e-9)
        throw Error(located(fileName, line,
                            what + " overlaps " + (b.name.empty() ? "a box" : "'" + b.name + "'") +
                                " (defined on line " + std::to_string(b.line) + ")"));
    }
  };
  for (const CoinDef& c : level.coins) inside(c.centre, Eigen::Vector3d::Constant(c.radius), c.line, "coin");
  for (const QuestionBoxDef& q : level.questionBoxes) inside(q.centre, 0.5 * q.size, q.line, "question box");
  for (const BallSpawnDef& b : level.balls)
    inside(Eigen::Vector3d(b.position.x(), b.position.y(), b.radius), Eigen::Vector3d::Constant(b.radius), b.line,
           "ball");
  for (const GoalDef& g : level.goals) inside(g.centre, 0.5 * g.size, g.line, "goal");

  // the spawn and every checkpoint need room to stand (kStandHeight, kStandHalfFootprint): the robot is put there
  // upright on both feet, and one put inside a box is thrown out of it (a box at the spawn threw the pelvis 15 m up)
  auto needRoom = [&](const Eigen::Vector2d& at, int line, const std::string& where) {
    const Eigen::Vector3d c(at.x(), at.y(), 0.5 * kStandHeight);
    const Eigen::Vector3d half(kStandHalfFootprint, kStandHalfFootprint, 0.5 * kStandHeight);
    auto blocked = [&](const Eigen::Vector3d& centre, const Eigen::Vector3d& halfSize, double yaw) {
      // a yawed box by its axis-aligned bounds
      const double cy = std::abs(std::cos(yaw)), sy = std::abs(std::sin(yaw));
      const Eigen::Vector3d h(cy * halfSize.x() + sy * halfSize.y(), sy * halfSize.x() + cy * halfSize.y(),
                              halfSize.z());
      return ((c - centre).cwiseAbs() - half - h).maxCoeff() < -1e-9;
    };
    auto refuse = [&](const std::string& what, int whatLine) {
      char room[96];
      std::snprintf(room, sizeof room, "within %.2f m of it and lower than %.2f m", kStandHalfFootprint, kStandHeight);
      throw Error(located(fileName, line,
                          where + " has no room to stand: " + what + " (defined on line " + std::to_string(whatLine) +
                              ") is " + room + ", where the robot is put upright on both feet"));
    };
    for (const BoxDef& b : level.boxes)
      if (blocked(b.centre, 0.5 * b.size, b.yaw)) refuse(b.name.empty() ? "a box" : "'" + b.name + "'", b.line);
    for (const QuestionBoxDef& q : level.questionBoxes)
      if (blocked(q.centre, 0.5 * q.size, 0.0)) refuse("a question box", q.line);
  };
  {
    char xy[64];
    std::snprintf(xy, sizeof xy, "(%g, %g)", level.spawn.x(), level.spawn.y());
    const toml::node* s = root.get("spawn");
    needRoom(level.spawn, s ? r.line(*s) : 0,
             std::string("the spawn at ") + xy + (s ? "" : " (the default: the level has no [spawn])"));
  }
  if (!level.rules.checkpoints.empty()) {
    const int line = r.line(*root.get("rules")->as_table()->get("checkpoints"));
    for (double x : level.rules.checkpoints) {
      char xs[32];
      std::snprintf(xs, sizeof xs, "%g", x);
      needRoom(Eigen::Vector2d(x, 0.0), line, std::string("checkpoint at x = ") + xs);
    }
  }
  return level;
}

Level loadLevel(const std::string& pathOrFolder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::string path = pathOrFolder;
  if (fs::is_directory(pathOrFolder, ec)) path = (fs::path(pathOrFolder) / "level.toml").string();
  Level level = parseLevel(engine::readFile(path), path);
  level.directory = fs::path(path).parent_path().string();

  return level;
}

std::vector<BoxDef> expandStairs(const StairsDef& d) {
  std::vector<BoxDef> boxes;
  // each step is a column from the ground up to its tread height
  double x = d.start.x();
  auto column = [&](const std::string& n, double x0, double length, double h) {
    BoxDef b;
    b.line = d.line;
    b.name = n;
    b.centre = Eigen::Vector3d(x0 + 0.5 * length, d.start.y(), 0.5 * h);
    b.size = Eigen::Vector3d(length, d.width, h);
    b.rgba = d.rgba;
    b.stairs = true;
    boxes.push_back(std::move(b));
  };
  for (int i = 1; i <= d.steps; ++i, x += d.run)
    column(d.name + "_up" + std::to_string(i), x, i == d.steps ? d.top : d.run, i * d.rise);
  x += d.top - d.run;
  if (d.down)
    for (int i = d.steps - 1; i >= 1; --i, x += d.run)
      column(d.name + "_down" + std::to_string(i), x, d.run, i * d.rise);
  return boxes;
}

double stairsEndX(const StairsDef& d) {
  return d.start.x() + (d.steps - 1) * d.run + d.top + (d.down ? (d.steps - 1) * d.run : 0.0);
}

}  // namespace levels
