// level.cpp — TOML level loader (toml++), strict: unknown keys, wrong types and bad sizes are errors.
#include "levels/level.h"

#include <cmath>
#include <filesystem>
#include <set>
#include <toml++/toml.h>

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
      throw Error(located(file, line(*n), std::string("'") + key + "' = " + std::to_string(*v) + " is out of range [" +
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
      throw Error(located(file, line(*n), std::string("'") + key + "' must be an array of " + std::to_string(N) + " numbers"));
    Eigen::Matrix<double, N, 1> out;
    for (int i = 0; i < N; ++i) {
      auto v = (*a)[static_cast<size_t>(i)].value<double>();
      if (!v || !std::isfinite(*v))
        throw Error(located(file, line(*n), std::string("'") + key + "' must be an array of " + std::to_string(N) + " numbers"));
      if (*v < lo || *v > hi)
        throw Error(located(file, line(*n), std::string("'") + key + "' has a value out of range [" + std::to_string(lo) +
                                                ", " + std::to_string(hi) + "]"));
      out[i] = *v;
    }
    return out;
  }

  std::string text(const toml::table& t, const char* key, const std::string& fallback) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    auto v = n->value<std::string>();
    if (!v) throw Error(located(file, line(*n), std::string("'") + key + "' must be a string"));
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
  r.onlyKeys(root, {"name", "description", "plane", "time_limit", "ground", "spawn", "box", "stairs"}, "the level");

  Level level;
  level.path = fileName;
  level.hash = engine::hashBytes(source);
  level.name = r.text(root, "name", "");
  if (level.name.empty()) throw Error(located(fileName, 1, "missing 'name = \"...\"'"));
  level.description = r.text(root, "description", "");
  const std::string plane = r.text(root, "plane", "side");
  if (plane == "side") level.plane = Plane2d::Side;
  else if (plane == "top") level.plane = Plane2d::Top;
  else throw Error(located(fileName, r.line(*root.get("plane")), "'plane' must be \"side\" or \"top\""));
  level.timeLimit = r.number(root, "time_limit", 0.0, false, 0.0, 86400.0);

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
    if (!a) throw Error(located(fileName, r.line(*n), std::string("'") + key + "' must be written as [[" + key + "]] tables"));
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
    boxes.push_back(std::move(b));
  };
  for (int i = 1; i <= d.steps; ++i, x += d.run) column(d.name + "_up" + std::to_string(i), x, i == d.steps ? d.top : d.run, i * d.rise);
  x += d.top - d.run;
  if (d.down)
    for (int i = d.steps - 1; i >= 1; --i, x += d.run) column(d.name + "_down" + std::to_string(i), x, d.run, i * d.rise);
  return boxes;
}

double stairsEndX(const StairsDef& d) {
  return d.start.x() + (d.steps - 1) * d.run + d.top + (d.down ? (d.steps - 1) * d.run : 0.0);
}

}  // namespace levels
