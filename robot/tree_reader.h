// tree_reader.h — the strict TOML reading both owners of the skill tree file share: robot/skill_tree.cpp reads the
// tables the skill runtime needs, ai/tree/training_tree.cpp the ones training and the cards need. Every value is
// checked where it is read, and an error names the file, the line and the key. Include it from .cpp files only (it
// brings in toml++).
#pragma once

#include <toml++/toml.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>

#include "engine/core/error.h"
#include "robot/skill_tree.h"

namespace robot {

/// Typed, range-checked reads from the tree file; each throws engine::Error with file:line.
struct TreeReader {
  std::string file;
  int line(const toml::node& n) const { return int(n.source().begin.line); }

  void onlyKeys(const toml::table& t, std::initializer_list<const char*> allowed, const std::string& where) const {
    for (auto&& [k, v] : t) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || k == a;
      if (!ok)
        throw engine::Error(engine::located(file, line(v), "unknown key '" + std::string(k.str()) + "' in " + where));
    }
  }
  const toml::table* table(const toml::table& t, const char* key, bool required, const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (required) throw engine::Error(engine::located(file, line(t), where + ": missing [" + key + "]"));
      return nullptr;
    }
    if (!n->as_table()) throw engine::Error(engine::located(file, line(*n), where + "." + key + " must be a table"));
    return n->as_table();
  }
  double number(const toml::node& n, const std::string& what, double lo, double hi) const {
    auto v = n.value<double>();
    if (!v || !std::isfinite(*v)) throw engine::Error(engine::located(file, line(n), what + " must be a number"));
    if (*v < lo || *v > hi)
      throw engine::Error(engine::located(
          file, line(n),
          what + " = " + std::to_string(*v) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]"));
    return *v;
  }
  // a whole number (1e7 or 10000000, not 0.5: a fraction is an error, never truncated)
  int64_t integer(const toml::node& n, const std::string& what, double lo, double hi) const {
    const double v = number(n, what, lo, hi);
    if (v != std::floor(v)) throw engine::Error(engine::located(file, line(n), what + " must be a whole number"));
    return int64_t(v);
  }
  int64_t integer(const toml::table& t, const char* key, int64_t fallback, double lo, double hi,
                  const std::string& where) const {
    const toml::node* n = t.get(key);
    return n ? integer(*n, where + "." + key, lo, hi) : fallback;
  }
  double number(const toml::table& t, const char* key, double fallback, double lo, double hi,
                const std::string& where) const {
    const toml::node* n = t.get(key);
    return n ? number(*n, where + "." + key, lo, hi) : fallback;
  }
  // true or false (not 1 or 0)
  bool flag(const toml::table& t, const char* key, bool fallback, const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    const std::optional<bool> b = n->is_boolean() ? n->value<bool>() : std::nullopt;
    if (!b) throw engine::Error(engine::located(file, line(*n), where + "." + key + " must be true or false"));
    return *b;
  }
  // [a, b] with no order between them
  std::array<double, 2> pair(const toml::table& t, const char* key, std::array<double, 2> fallback, double lo,
                             double hi, const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2)
      throw engine::Error(engine::located(file, line(*n), where + "." + key + " must be [x, y]"));
    return {number((*a)[0], where + "." + key, lo, hi), number((*a)[1], where + "." + key, lo, hi)};
  }
  Range range(const toml::table& t, const char* key, Range fallback, double lo, double hi,
              const std::string& where) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2)
      throw engine::Error(engine::located(file, line(*n), where + "." + key + " must be [low, high]"));
    Range r{number((*a)[0], where + "." + key, lo, hi), number((*a)[1], where + "." + key, lo, hi)};
    if (r.lo > r.hi) throw engine::Error(engine::located(file, line(*n), where + "." + key + ": low is above high"));
    return r;
  }
};

/// The tree file parsed as TOML, its top-level keys checked ([ppo] and [skill.NAME] tables only).
toml::table readTreeFile(const TreeReader& r);

/// A steer (line_steer, heading_steer, a card's steer) turns with wz: the range must reach either side of 0.
inline bool turnsBothWays(const CommandDef& c) { return c.wz.lo < 0 && c.wz.hi > 0; }

}  // namespace robot
