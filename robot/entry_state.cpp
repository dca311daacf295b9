// entry_state.cpp — see entry_state.h.
#include "robot/entry_state.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "engine/core/error.h"
#include "engine/core/file_io.h"

namespace robot {
namespace {

constexpr const char* kHeader = "treelearn-entries 1";

struct Writer {
  std::string out;
  void key(const char* k) { out += "  ", out += k; }
  void num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, " %.17g", v);
    out += buf;
  }
  void whole(int64_t v) { out += " " + std::to_string(v); }
  void end() { out += '\n'; }
  template <typename It>
  void nums(const char* k, It begin, It end_) {
    key(k);
    for (It i = begin; i != end_; ++i) num(double(*i));
    end();
  }
};

void writeCommand(Writer* w, const char* k, const SkillCommand& c) {
  const double v[] = {c.vx, c.vy, c.wz, c.amplitude, c.aux0, c.aux1};
  w->nums(k, std::begin(v), std::end(v));
}

// one line's words after its keyword, with where it was
struct Line {
  int number = 0;
  std::string keyword;
  std::vector<std::string> words;
};

class Reader {
 public:
  Reader(const std::string& file, const Line& line) : file_(file), line_(line) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw engine::Error(engine::located(file_, line_.number, line_.keyword + ": " + what));
  }
  void expectCount(size_t n) const {
    if (line_.words.size() != n)
      fail("expected " + std::to_string(n) + " value" + (n == 1 ? "" : "s") + ", found " +
           std::to_string(line_.words.size()));
  }
  double number(size_t i) const {
    const std::string& w = line_.words[i];
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (w.empty() || end != w.c_str() + w.size()) fail("'" + w + "' is not a number");
    if (!std::isfinite(v)) fail("'" + w + "' is not a finite number");
    return v;
  }
  int64_t whole(size_t i, int64_t lo, int64_t hi) const {
    const double v = number(i);
    if (v != std::floor(v) || v < double(lo) || v > double(hi))
      fail("'" + line_.words[i] + "' is not a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
           "]");
    return int64_t(v);
  }
  std::vector<double> numbers(size_t n) const {
    expectCount(n);
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = number(i);
    return v;
  }
  const Line& line() const { return line_; }

 private:
  const std::string& file_;
  const Line& line_;
};

SkillCommand readCommand(const Reader& r) {
  const std::vector<double> v = r.numbers(6);
  SkillCommand c;
  c.vx = v[0], c.vy = v[1], c.wz = v[2], c.amplitude = v[3], c.aux0 = v[4], c.aux1 = v[5];
  return c;
}

std::vector<Line> splitLines(const std::string& text, const std::string& file) {
  std::vector<Line> lines;
  std::istringstream in(text);
  std::string raw;
  int number = 0;
  while (std::getline(in, raw)) {
    ++number;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    for (const char ch : raw)
      if ((unsigned char)ch < 0x20 && ch != '\t')
        throw engine::Error(engine::located(file, number, "control character in the line"));
    const size_t hash = raw.find('#');
    if (hash != std::string::npos) raw.resize(hash);
    std::istringstream words(raw);
    Line l;
    l.number = number;
    if (!(words >> l.keyword)) continue;
    for (std::string w; words >> w;) l.words.push_back(w);
    lines.push_back(std::move(l));
  }
  return lines;
}

}  // namespace

std::string formatEntries(const std::vector<EntryState>& entries) {
  Writer w;
  w.out = std::string(kHeader) + "\n# play's handover states (docs/formats.md); one entry ... end block each\n";
  for (const EntryState& e : entries) {
    w.out += "entry " + e.skill + "\n";
    w.out += "  level " + e.level + "\n";
    w.out += "  source " + e.source + "\n";
    w.key("seed"), w.out += " " + std::to_string(e.seed), w.end();
    w.key("tick"), w.whole(e.tick), w.end();
    w.key("segment"), w.whole(e.segmentTicks), w.out += e.fellInPlay ? " fell" : " held", w.end();
    const engine::ArticulationState& b = e.body;
    const double base[] = {b.basePosition.x(), b.basePosition.y(), b.basePosition.z(), b.baseRotation.w(),
                           b.baseRotation.x(), b.baseRotation.y(), b.baseRotation.z()};
    w.nums("base", std::begin(base), std::end(base));
    const double vel[] = {b.baseLinearVelocity.x(),  b.baseLinearVelocity.y(),  b.baseLinearVelocity.z(),
                          b.baseAngularVelocity.x(), b.baseAngularVelocity.y(), b.baseAngularVelocity.z()};
    w.nums("base_velocity", std::begin(vel), std::end(vel));
    w.nums("q", b.q.begin(), b.q.end());
    w.nums("qd", b.qd.begin(), b.qd.end());
    for (const engine::BallState& ball : e.balls) {
      const double v[] = {ball.position.x(),        ball.position.y(),        ball.position.z(),
                          ball.velocity.x(),        ball.velocity.y(),        ball.velocity.z(),
                          ball.angularVelocity.x(), ball.angularVelocity.y(), ball.angularVelocity.z()};
      w.nums("ball", std::begin(v), std::end(v));
    }
    const SkillState& s = e.runtime;
    w.out += "  fading_from " + (e.fadingFrom.empty() ? std::string("-") : e.fadingFrom) + "\n";
    w.key("phase"), w.whole(s.phase.tp), w.num(s.phase.gait), w.end();
    w.key("fade_phase"), w.whole(s.fadePhase.tp), w.num(s.fadePhase.gait), w.end();
    w.key("fade_ticks"), w.whole(s.fadeTicks), w.end();
    w.key("active_since"), w.whole(s.activeSince), w.end();
    w.key("waits"), w.whole(s.restWaitTicks), w.whole(s.postureWaitTicks), w.end();
    w.nums("action", s.action.begin(), s.action.end());
    writeCommand(&w, "brake", s.brake);
    writeCommand(&w, "brake_target", s.brakeTarget);
    w.nums("drift", s.drift.data(), s.drift.data() + 2);
    const double line[] = {s.lineStart.x(), s.lineStart.y(), s.lineAlong.x(), s.lineAlong.y(), s.lineSteerError};
    w.nums("line", std::begin(line), std::end(line));
    const double heading[] = {s.headingRef, s.headingLineStart.x(), s.headingLineStart.y()};
    w.nums("heading", std::begin(heading), std::end(heading));
    const engine::CommandState& k = e.keys;
    w.key("keys"), w.whole(k.skillRequest), w.num(k.vx), w.num(k.vy), w.num(k.wz), w.num(k.amplitude),
        w.whole(k.keysHeld), w.end();
    const engine::CommandLimits& l = e.limits;
    const double limits[] = {l.vxForward, l.vxBackward, l.vyMax, l.wzMax, l.vRate, l.wzRate, l.amplitudeRate};
    w.nums("limits", std::begin(limits), std::end(limits));
    for (const engine::KeyEvent& ev : e.events) {
      w.key("event"), w.whole(ev.tick), w.out += " " + std::string(engine::keyActionName(ev.action)) + " ",
          w.out += ev.key, w.end();
    }
    w.out += "end\n";
  }
  return w.out;
}

std::vector<EntryState> parseEntries(const std::string& text, const std::string& fileName) {
  const std::vector<Line> lines = splitLines(text, fileName);
  if (lines.empty() || lines[0].keyword + (lines[0].words.empty() ? "" : " " + lines[0].words[0]) != kHeader ||
      lines[0].words.size() != 1)
    throw engine::Error(engine::located(fileName, lines.empty() ? 1 : lines[0].number,
                                        std::string("not an entries file: the first line must be '") + kHeader + "'"));
  std::vector<EntryState> entries;
  EntryState* e = nullptr;
  std::map<std::string, int> seen;  // the fields of the entry being read, and where
  const char* required[] = {"level", "source", "seed",  "tick",   "segment", "base",   "base_velocity",
                            "q",     "qd",     "phase", "action", "keys",    "limits", "fading_from"};
  for (size_t i = 1; i < lines.size(); ++i) {
    const Line& line = lines[i];
    const Reader r(fileName, line);
    if (line.keyword == "entry") {
      if (e) r.fail("the entry before (line " + std::to_string(seen["entry"]) + ") has no 'end'");
      r.expectCount(1);
      entries.emplace_back();
      e = &entries.back();
      e->skill = line.words[0];
      e->body.q.assign(kNumJoints, 0.0), e->body.qd.assign(kNumJoints, 0.0);
      seen.clear();
      seen["entry"] = line.number;
      continue;
    }
    if (!e) r.fail("outside an entry ('entry SKILL' ... 'end')");
    if (line.keyword == "end") {
      r.expectCount(0);
      for (const char* k : required)
        if (!seen.count(k))
          r.fail("the entry of line " + std::to_string(seen["entry"]) + " has no '" + std::string(k) + "' line");
      e = nullptr;
      continue;
    }
    const bool repeats = line.keyword == "ball" || line.keyword == "event";
    if (!repeats && seen.count(line.keyword))
      r.fail("given twice in one entry (first on line " + std::to_string(seen[line.keyword]) + ")");
    seen[line.keyword] = line.number;
    SkillState& s = e->runtime;
    const std::string& k = line.keyword;
    if (k == "level" || k == "source") {
      r.expectCount(1);
      (k == "level" ? e->level : e->source) = line.words[0];
    } else if (k == "seed") {
      r.expectCount(1);
      char* end = nullptr;
      errno = 0;  // strtoull saturates at 2^64 - 1 and says so only through errno
      const unsigned long long v = std::strtoull(line.words[0].c_str(), &end, 10);
      if (!std::isdigit(static_cast<unsigned char>(line.words[0][0])) ||
          end != line.words[0].c_str() + line.words[0].size())
        r.fail("'" + line.words[0] + "' is not a seed (a whole number >= 0)");
      if (errno == ERANGE)
        r.fail("'" + line.words[0] + "' is larger than the largest seed, 18446744073709551615 (2^64 - 1)");
      e->seed = v;
    } else if (k == "tick") {
      r.expectCount(1);
      e->tick = r.whole(0, 0, int64_t(8640000));
    } else if (k == "segment") {
      r.expectCount(2);
      e->segmentTicks = r.whole(0, 0, kSegmentCapTicks);
      if (line.words[1] != "fell" && line.words[1] != "held") r.fail("the segment ends 'fell' or 'held'");
      e->fellInPlay = line.words[1] == "fell";
    } else if (k == "base") {
      const std::vector<double> v = r.numbers(7);
      e->body.basePosition = Eigen::Vector3d(v[0], v[1], v[2]);
      const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
      if (std::abs(q.norm() - 1.0) > 1e-6) r.fail("the rotation (w x y z) is not a unit quaternion");
      e->body.baseRotation = q.normalized();
    } else if (k == "base_velocity") {
      const std::vector<double> v = r.numbers(6);
      e->body.baseLinearVelocity = Eigen::Vector3d(v[0], v[1], v[2]);
      e->body.baseAngularVelocity = Eigen::Vector3d(v[3], v[4], v[5]);
    } else if (k == "q" || k == "qd") {
      (k == "q" ? e->body.q : e->body.qd) = r.numbers(kNumJoints);
    } else if (k == "ball") {
      const std::vector<double> v = r.numbers(9);
      engine::BallState b;
      b.position = Eigen::Vector3d(v[0], v[1], v[2]);
      b.velocity = Eigen::Vector3d(v[3], v[4], v[5]);
      b.angularVelocity = Eigen::Vector3d(v[6], v[7], v[8]);
      e->balls.push_back(b);
    } else if (k == "fading_from") {
      r.expectCount(1);
      e->fadingFrom = line.words[0] == "-" ? std::string() : line.words[0];
    } else if (k == "phase" || k == "fade_phase") {
      r.expectCount(2);
      PhaseClock& c = k == "phase" ? s.phase : s.fadePhase;
      c.tp = int(r.whole(0, 0, 100000));
      c.gait = r.number(1);
    } else if (k == "fade_ticks") {
      r.expectCount(1);
      s.fadeTicks = int(r.whole(0, 0, 100000));
    } else if (k == "active_since") {
      r.expectCount(1);
      s.activeSince = r.whole(0, 0, int64_t(8640000));
    } else if (k == "waits") {
      r.expectCount(2);
      s.restWaitTicks = int(r.whole(0, -1, 100000));
      s.postureWaitTicks = int(r.whole(1, 0, 100000));
    } else if (k == "action") {
      const std::vector<double> v = r.numbers(kActionSize);
      for (int j = 0; j < kActionSize; ++j) s.action[size_t(j)] = float(v[size_t(j)]);
    } else if (k == "brake" || k == "brake_target") {
      (k == "brake" ? s.brake : s.brakeTarget) = readCommand(r);
    } else if (k == "drift") {
      const std::vector<double> v = r.numbers(2);
      s.drift = Eigen::Vector2d(v[0], v[1]);
    } else if (k == "line") {
      const std::vector<double> v = r.numbers(5);
      s.lineStart = Eigen::Vector2d(v[0], v[1]), s.lineAlong = Eigen::Vector2d(v[2], v[3]);
      s.lineSteerError = v[4];
    } else if (k == "heading") {
      const std::vector<double> v = r.numbers(3);
      s.headingRef = v[0], s.headingLineStart = Eigen::Vector2d(v[1], v[2]);
    } else if (k == "keys") {
      r.expectCount(6);
      engine::CommandState& c = e->keys;
      c.skillRequest = int(r.whole(0, -1, 9));
      c.vx = r.number(1), c.vy = r.number(2), c.wz = r.number(3), c.amplitude = r.number(4);
      c.keysHeld = uint32_t(r.whole(5, 0, (int64_t(1) << 18) - 1));
    } else if (k == "limits") {
      const std::vector<double> v = r.numbers(7);
      for (size_t j : {4, 5, 6})
        if (v[j] <= 0) r.fail("the ramp rates (the last three values) must be > 0");
      engine::CommandLimits& l = e->limits;
      l.vxForward = v[0], l.vxBackward = v[1], l.vyMax = v[2], l.wzMax = v[3];
      l.vRate = v[4], l.wzRate = v[5], l.amplitudeRate = v[6];
    } else if (k == "event") {
      r.expectCount(3);
      engine::KeyEvent ev;
      ev.tick = r.whole(0, e->tick + 1, e->tick + kSegmentCapTicks);
      const auto action = engine::parseKeyAction(line.words[1]);
      if (!action) r.fail("'" + line.words[1] + "' is not a key action (down, up or tap)");
      const auto key = engine::parseKeyName(line.words[2]);
      if (!key) r.fail("'" + line.words[2] + "' is not a key (0-9, W A S D Q E R F)");
      if (!e->events.empty() && ev.tick < e->events.back().tick) r.fail("events go back in time");
      ev.action = *action, ev.key = *key;
      e->events.push_back(ev);
    } else {
      r.fail("unknown field");
    }
  }
  if (e) throw engine::Error(engine::located(fileName, seen["entry"], "the entry has no 'end' before the file ends"));
  return entries;
}

std::vector<EntryState> loadEntries(const std::string& path) {
  return parseEntries(engine::readFile(path, engine::kMaxDataFileBytes), path);
}

void saveEntries(const std::string& path, const std::vector<EntryState>& entries) {
  engine::writeFileAtomic(path, formatEntries(entries));
}

SkillState entryRuntime(const EntryState& entry, const SkillSet& set) {
  SkillState s = entry.runtime;
  s.active = set.byName(entry.skill);
  if (!s.active)
    throw engine::Error("an entry of " + entry.level + " (seed " + std::to_string(entry.seed) + ", tick " +
                        std::to_string(entry.tick) + ") hands over to '" + entry.skill +
                        "', which is not among the loaded skills");
  s.fadingFrom = entry.fadingFrom.empty() ? nullptr : set.byName(entry.fadingFrom);
  if (!entry.fadingFrom.empty() && !s.fadingFrom) s.fadeTicks = 0;  // the fading skill is not loaded: no fade
  return s;
}

}  // namespace robot
