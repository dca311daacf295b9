// garden_pilot.cpp — see garden_pilot.h.
#include "game/garden_pilot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "engine/core/error.h"
#include "engine/loop/clock.h"
#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"
#include "game/session.h"

namespace game {
namespace {

constexpr double kStairsEntryBefore = 0.4;  // the stairs leg starts this far before the path's first stair cell [m]
constexpr double kStairsEntryReach = 0.5;   // a robot this close to the entry (or past it) takes the stairs leg [m] ...
constexpr double kStairsEntryAcross = 0.2;  // ... within this of the staircase's middle line [m]
constexpr double kStairsExitAfter = 0.3;    // the stairs leg ends this far past the last stair cell [m] ...
constexpr double kStairsExitDone = 0.2;     // ... once the robot is within this of that end (the walk brakes the rest)
constexpr double kStairsLost = 1.5;         // a robot this far across from the staircase's middle line has left it [m]
constexpr double kSkipWaypoint = 0.3;       // a waypoint closer than this along the path is passed [m]
constexpr double kCornerReach = 0.5;        // steering: a corner is turned (or steered round) this close to it [m]
constexpr double kMovableLook = 0.8;        // a movable body this close ahead of the pelvis stops Go [m]
constexpr double kMovableHalfWidth = 0.25;  // ... across the body's core (the follower's obstacleHalfWidth) [m]

// a double in [0, 1) from 53 random bits (portable, unlike std::uniform_real_distribution)
double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

// The way across from a path's line over a staircase to the staircase's middle line [m, world]: at the middle of the
// span, the centre of the run of stair cells across it (the taut path keeps to one edge of them, at the map's
// clearance from a railing or a house, where a gait's sway brushes it).
Eigen::Vector2d stairsMiddle(const nav::OccupancyGrid& grid, const nav::Path& path, const nav::StairsSpan& span) {
  const Eigen::Vector2d mid = path.pointAt(0.5 * (span.from + span.to));
  const Eigen::Vector2d across(-std::sin(span.heading), std::cos(span.heading));
  auto onStairs = [&](double k) {
    const Eigen::Vector2i c = grid.cellAt(mid + k * across);
    return grid.kind(c.x(), c.y()) == nav::CellKind::Stairs;
  };
  const double step = 0.5 * grid.cellSize(), most = 3.0;
  double lo = 0, hi = 0;
  while (hi < most && onStairs(hi + step)) hi += step;
  while (lo > -most && onStairs(lo - step)) lo -= step;
  return 0.5 * (lo + hi) * across;
}

// Every cell within `radius` of cell (ix, iy) is free (no wall, no stairs): room to stand and turn.
bool roomAround(const nav::OccupancyGrid& grid, int ix, int iy, double radius) {
  const int r = int(std::ceil(radius / grid.cellSize()));
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (double(dx * dx + dy * dy) * grid.cellSize() * grid.cellSize() <= radius * radius &&
          grid.kind(ix + dx, iy + dy) != nav::CellKind::Free)
        return false;
  return true;
}

}  // namespace

std::vector<Eigen::Vector2d> parseTargets(const std::string& text, const std::string& fileName) {
  std::vector<Eigen::Vector2d> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    for (char& c : line)
      if (c == ',' || c == '\t' || c == '\r') c = ' ';
    std::istringstream fields(line);
    std::vector<std::string> words;
    for (std::string w; fields >> w;) words.push_back(w);
    if (words.empty()) continue;
    if (words.size() != 2)
      throw engine::Error(engine::located(
          fileName, number,
          "a target is two numbers, \"x y\" in metres (got " + std::to_string(words.size()) + " fields)"));
    Eigen::Vector2d t;
    for (int i = 0; i < 2; ++i) {
      const std::string& w = words[size_t(i)];
      char* end = nullptr;
      const double v = std::strtod(w.c_str(), &end);
      if (end == w.c_str() || *end != '\0' || !std::isfinite(v) || std::abs(v) > 1000.0)
        throw engine::Error(
            engine::located(fileName, number, "'" + w + "' is not a coordinate in metres (a number within +-1000)"));
      t[i] = v;
    }
    out.push_back(t);
  }
  if (out.empty()) throw engine::Error(engine::located(fileName, std::max(number, 1), "no targets in the file"));
  return out;
}

double turnRelease(double wz, const GardenKeyParams& p) {
  const double w = std::abs(wz);
  return w * w / (2.0 * p.turnRamp) + w * p.turnLag;
}

double brakeDistance(double vx, const GardenKeyParams& p) {
  const double v = std::max(0.0, vx);
  return v * v / (2.0 * p.keyRamp) + v * p.brakeLag;
}

const char* GardenKeys::modeName(Mode m) {
  switch (m) {
    case Mode::Stop:
      return "stop";
    case Mode::Turn:
      return "turn";
    case Mode::Go:
      return "go";
    case Mode::Back:
      return "back";
  }
  return "?";
}

void GardenKeys::hold(int64_t tick, char key, bool down, std::vector<engine::KeyEvent>* out) {
  held_.hold(tick, key, down, out);
}

void GardenKeys::releaseMoves(int64_t tick, std::vector<engine::KeyEvent>* out) { held_.releaseAll(tick, out); }

void GardenKeys::skill(int64_t tick, char key, std::vector<engine::KeyEvent>* out) {
  if (!key || key == skill_) return;
  out->push_back({tick, engine::KeyAction::kTap, key});
  skill_ = key;
}

void GardenKeys::enter(Mode m) {
  // Stop -> Turn keeps the rest already waited for; every other change waits afresh
  if (!(mode_ == Mode::Stop && m == Mode::Turn)) restSince_ = -1;
  mode_ = m;
}

std::vector<engine::KeyEvent> GardenKeys::decide(int64_t tick, const LegCues& c) {
  std::vector<engine::KeyEvent> out;
  const bool still = c.commandVx == 0.0 && c.commandWz == 0.0 && c.speed < p_.restSpeed;
  auto settled = [&] {
    if (!still) {
      restSince_ = -1;
      return false;
    }
    if (restSince_ < 0) restSince_ = tick;
    return tick - restSince_ >= p_.settleTicks;
  };
  // the walk first: the standing controller does not turn
  if (!skill_) skill(tick, keys_.walk, &out);

  if (c.backOff && mode_ != Mode::Back) {
    releaseMoves(tick, &out);
    if (skill_ != keys_.walk) skill(tick, keys_.walk, &out);
    enter(Mode::Back);
  }
  switch (mode_) {
    case Mode::Back:
      if (c.backOff) {
        if (c.commandWz == 0.0) hold(tick, 'S', true, &out);
      } else {
        releaseMoves(tick, &out);
        enter(Mode::Stop);
      }
      break;
    case Mode::Stop:
      releaseMoves(tick, &out);
      if (settled() && c.haveLeg) {
        if (goStairs_ || skill_ == keys_.run) skill(tick, keys_.walk, &out);  // off the stairs or out of the run
        goStairs_ = false;
        enter(Mode::Turn);
        tries_ = 0;
      }
      break;
    case Mode::Turn: {
      if (!c.haveLeg) {
        releaseMoves(tick, &out);
        enter(Mode::Stop);
        break;
      }
      const double error = std::remainder(c.legHeading - c.yaw, 2.0 * M_PI);
      const double tolerance = c.stairsLeg ? p_.stairsTolerance : p_.walkTolerance;
      const bool turning = held_.holds('A') || held_.holds('D');
      if (turning) {
        // let go early: the ramp down and the skill's lag turn it the rest of the way
        const bool wrongWay = held_.holds('A') != (error > 0);
        if (wrongWay || std::abs(error) <= turnRelease(c.commandWz, p_) + 0.5 * tolerance) {
          releaseMoves(tick, &out);
          restSince_ = -1;
        }
        break;
      }
      if (!settled()) break;
      const double meanError = std::remainder(c.legHeading - c.yawMean, 2.0 * M_PI);
      const double goTolerance = p_.steer && !c.stairsLeg ? std::max(tolerance, p_.steerStartTolerance) : tolerance;
      if (std::abs(meanError) <= goTolerance || tries_ >= p_.maxTurnTries) {
        goStairs_ = c.stairsLeg;
        goHeading_ = c.legHeading;
        skill(tick, c.stairsLeg ? keys_.stairs : keys_.walk, &out);
        hold(tick, 'W', true, &out);
        enter(Mode::Go);
        break;
      }
      hold(tick, meanError > 0 ? 'A' : 'D', true, &out);
      ++tries_;
      break;
    }
    case Mode::Go: {
      if (!goStairs_ && p_.steer) {
        goSteering(tick, c, &out);
        break;
      }
      if (goStairs_ && !c.stairsLeg) {  // the staircase is passed, or the path changed: off the stairs skill
        releaseMoves(tick, &out);
        skill(tick, keys_.walk, &out);
        goStairs_ = false;
        enter(Mode::Stop);
        break;
      }
      if (goStairs_ && p_.steerStairs && c.haveLeg && c.legRemaining > brakeDistance(c.commandVx, p_)) {
        steerUnderW(tick, c, 0.0, &out);  // toward the staircase's middle line
        break;
      }
      bool stop = !c.haveLeg || c.legRemaining <= brakeDistance(c.commandVx, p_);
      if (!goStairs_) {
        stop = stop || c.pathChanged || c.movableAhead || c.stairsLeg;  // a stairs leg begins from a stop, squared up
        stop = stop || c.obstacleFactor < p_.wallStopFactor;            // a wall right ahead: the leg went wrong
        // the bearing to the leg's end has turned away from the heading the leg started on: the walk drifted sideways
        const double drift = std::remainder(c.legHeading - goHeading_, 2.0 * M_PI);
        stop = stop || (std::abs(drift) > p_.returnHeading && c.legRemaining > p_.returnDistance);
        if (!stop && keys_.run && p_.useRun) {
          // the run takes over from a walk at speed (from a standstill it fell within 2 s)
          if (c.runAllowed && c.legRemaining >= p_.runMinLeg && c.speed >= p_.runFromSpeed)
            skill(tick, keys_.run, &out);
          else if (skill_ == keys_.run && (c.legRemaining < p_.runLeaveLeg || !c.runAllowed))
            skill(tick, keys_.walk, &out);
        }
      }
      if (stop) {
        releaseMoves(tick, &out);
        if (goStairs_ || skill_ == keys_.run) skill(tick, keys_.walk, &out);
        goStairs_ = false;
        enter(Mode::Stop);
      }
      break;
    }
  }
  return out;
}

void GardenKeys::goSteering(int64_t tick, const LegCues& c, std::vector<engine::KeyEvent>* out) {
  const double error = std::remainder(c.legHeading - c.yaw, 2.0 * M_PI);
  const bool atEnd = c.haveLeg && c.legRemaining <= brakeDistance(c.commandVx, p_);
  const bool wall = c.centreAhead < p_.steerWallStop;  // a wall right ahead: the leg went wrong
  // out of a run, W stays down (no steering) until the walk is in control at its own speeds: the walk brakes a run.
  // With W let go the run's command fell below its range, and a walk handed 1.6 m/s with W up spun round and fell
  const bool running = skill_ == keys_.run;  // asked for (the runtime hands over when the robot is ready)
  auto brake = [&] {
    if (running) skill(tick, keys_.walk, out);
    hold(tick, 'A', false, out), hold(tick, 'D', false, out);
    hold(tick, 'W', true, out);
  };
  if (c.running != wasRunning_) handover_ = c.running ? -1 : tick, wasRunning_ = c.running;
  // the walk took over from the run: it settles, and brakes to its own speeds, straight on
  const bool afterRun = handover_ >= 0 && (tick - handover_ < p_.walkSettleTicks || c.speed > p_.walkTopSpeed);
  if (handover_ >= 0 && !afterRun) handover_ = -1;
  if (!running && (c.running || afterRun)) {
    brake();
    return;
  }
  auto stop = [&] {
    if (running) return brake();  // stopped once braked
    releaseMoves(tick, out);
    enter(Mode::Stop);
  };
  if (!c.haveLeg || c.stairsLeg || c.movableAhead || wall || (atEnd && c.endStops)) {
    stop();  // a stairs leg begins from a stop, squared up; a ball or a wall is gone round after one
    return;
  }
  if (std::abs(error) > p_.steerCorner) {
    // a corner too sharp to walk through (the next leg's, from kCornerReach before it), or a leg that went wrong:
    // stop and turn in place (turning before the walk is at rest carried it on by up to 0.7 m: into the river)
    stop();
    return;
  }
  if (p_.useRun && keys_.run) {
    // the run on a long straight, taken over from a walk at speed and squared up to the path; the walk again (W held:
    // it brakes to its own speeds) before the leg's end
    const bool steering = held_.holds('A') || held_.holds('D');
    if (!running && c.runAllowed && c.legRemaining >= p_.runMinLeg && c.speed >= p_.runFromSpeed && !steering &&
        std::abs(error) <= p_.runHeading)
      skill(tick, keys_.run, out);
    else if (running && (c.legRemaining < p_.runLeaveLeg || !c.runAllowed))
      return brake();
  }
  // the last stretch to a stop (the path's end, a staircase's entry) slowly, W pulsed: it stops where it should;
  // it steers only while W is down (A or D alone would turn it in place)
  const bool approach = c.endStops && c.legRemaining < p_.approachDistance;
  if (approach) {
    const bool w = c.commandVx < p_.approachSpeed;
    hold(tick, 'W', w, out);
    if (!w) {
      hold(tick, 'A', false, out), hold(tick, 'D', false, out);
      return;
    }
  }
  const double steerUntil = approach ? p_.approachSteerUntil : p_.returnDistance;
  // a corner or a body close ahead on one side only: steer away from it first
  const bool nearLeft = c.leftAhead < p_.steerAvoid, nearRight = c.rightAhead < p_.steerAvoid;
  if (nearLeft != nearRight) {
    hold(tick, nearLeft ? 'A' : 'D', false, out);
    hold(tick, nearLeft ? 'D' : 'A', true, out);
    return;
  }
  // steer under W toward the path ahead (the walk crabs off its yaw; a replanned path bends)
  if (running && c.legRemaining < p_.runLeaveLeg + p_.runStraightBefore) {  // the run goes straight before the walk
    hold(tick, 'A', false, out), hold(tick, 'D', false, out);
    return;
  }
  steerUnderW(tick, c, steerUntil, out);
}

void GardenKeys::steerUnderW(int64_t tick, const LegCues& c, double until, std::vector<engine::KeyEvent>* out) {
  const double error = std::remainder(c.legHeading - c.yaw, 2.0 * M_PI);
  const bool left = held_.holds('A'), right = held_.holds('D');
  if (left || right) {
    const double wz = std::abs(c.commandWz);
    const double coast = wz * wz / (2.0 * p_.steerRamp) + wz * p_.steerLag;  // turned after the key is let go
    if (left != (error > 0) || std::abs(error) <= coast || c.legRemaining <= until)
      hold(tick, left ? 'A' : 'D', false, out);
  } else if (std::abs(error) > p_.steerOn && c.legRemaining > until) {
    hold(tick, error > 0 ? 'A' : 'D', true, out);
  }
}

// ---------------------------------------------------------------------------------------------------------------

nav::NavigatorParams GardenPilot::gardenNavigatorParams() {
  nav::NavigatorParams p;
  p.reachRadius = 0.5;  // the paper's operator gave the next target within 0.5 m
  // legs drift 0.1-0.3 m sideways (the walk crabs up to 0.1 rad off its yaw, the stairs 0.3-0.5 m over the bridge):
  // 0.15 m more clearance than the navigation's default radius. At 0.45 m walks past the bridge's foot stepped onto
  // its first riser or met a railing's end (seeds 1-10: 4 falls, 63 targets; at 0.5 m: 2 falls, 75 targets). The
  // 1.1 m alley keeps one column of cells through its middle
  p.grid.robotRadius = 0.5;
  return p;
}

GardenPilot::GardenPilot(const engine::PlaneWorld& plane, const SkillKeys& keys, uint64_t seed,
                         std::vector<Eigen::Vector2d> targets, const nav::NavigatorParams& navParams,
                         GardenKeyParams keyParams)
    : keys_(keys, keyParams), rng_(seed ^ 0x67617264656eULL), fixed_(std::move(targets)) {
  nav::NavigatorParams params = navParams;
  Eigen::Vector2d lo, hi;
  if (!plane.staticBounds(&lo, &hi)) throw engine::Error("the garden pilot needs a map: the level's 2D layer is empty");
  params.grid.origin = lo;
  params.grid.size = hi - lo;
  nav_ = std::make_unique<nav::Navigator>(plane, params);
  random_ = fixed_.empty();
}

Eigen::Vector2d GardenPilot::drawTarget(const nav::OccupancyGrid& grid, const Eigen::Vector2d& from, bool across,
                                        const TargetDraw& draw, std::mt19937_64* rng) {
  // fallbacks, best first: a crossing at any length (for an across target), one within the ordinary lengths, any
  std::optional<Eigen::Vector2d> crossing, ordinary, any;
  for (int i = 0; i < draw.tries; ++i) {
    const int ix = std::min(grid.width() - 1, int(unit(*rng) * grid.width()));
    const int iy = std::min(grid.height() - 1, int(unit(*rng) * grid.height()));
    if (grid.kind(ix, iy) != nav::CellKind::Free) continue;
    const Eigen::Vector2d c = grid.centre(ix, iy);
    if (!roomAround(grid, ix, iy, draw.clearance)) continue;
    const nav::Path path = nav::planPath(grid, from, c);
    if (!path.found || path.length() < draw.minPath) continue;
    const bool crosses = !path.stairs.empty(), near = path.length() <= draw.maxPath;
    if (across ? crosses && path.length() <= draw.acrossMaxPath : near) return c;
    if (crosses && !crossing) crossing = c;
    if (near && !ordinary) ordinary = c;
    if (!any) any = c;
  }
  // (from the garden's north end no path crosses a staircase: an across target there is an ordinary one)
  return crossing && across ? *crossing : ordinary ? *ordinary : any ? *any : from;
}

void GardenPilot::nextTarget(const Eigen::Vector2d& from) {
  ++targetIndex_;
  Eigen::Vector2d t;
  if (random_) {
    const bool across = draw_.acrossEvery > 0 && targetIndex_ % draw_.acrossEvery == 1;
    t = drawTarget(nav_->grid(), from, across, draw_, &rng_);
  } else {
    if (targetIndex_ >= int(fixed_.size())) {
      nav_->clearTarget();
      return;
    }
    t = fixed_[size_t(targetIndex_)];
  }
  nav_->setTarget(t);
  ++tally_.given;
  tally_.targets.push_back(t);
}

LegCues GardenPilot::legCues(const Session& session, const nav::NavOutput& out) {
  LegCues c;
  const robot::Sensors& s = session.sensors();
  const Eigen::Vector2d p = s.basePosition.head<2>();
  c.yaw = s.yaw;
  double sx = 0, sy = 0;
  for (const double y : yaws_) sx += std::cos(y), sy += std::sin(y);
  c.yawMean = yaws_.empty() ? s.yaw : std::atan2(sy, sx);
  c.speed = (s.baseRotation * s.linearVelocity).head<2>().norm();
  c.commandVx = session.command().vx;
  c.commandWz = session.command().wz;
  c.running = session.activeSkillName() == "run";
  c.backOff = out.state == nav::NavState::BackingOff;
  c.pathChanged = out.events.replanned;
  c.runAllowed = out.command.skill == nav::NavSkill::Run;
  c.obstacleFactor = out.follow.obstacleFactor;
  // a movable body (a ball) right ahead of the body's core
  const Eigen::Vector2d ahead(std::cos(s.yaw), std::sin(s.yaw)), left(-ahead.y(), ahead.x());
  const engine::PlaneWorld& plane = session.plane();
  for (const double k : {-1.0, 0.0, 1.0}) {
    const Eigen::Vector2d from = p + k * kMovableHalfWidth * left;
    const engine::RayHit hit = plane.rayCast(from, from + kMovableLook * ahead);
    if (hit.hit && engine::isMovableTag(hit.tag)) c.movableAhead = true;
  }
  // walls and bodies ahead of the pelvis and of either side of the body's core (the follower's rays)
  const nav::FollowerParams& ray = nav_->params().follower;
  c.rightAhead = nav::clearAhead(plane, p - ray.obstacleHalfWidth * left, s.yaw, ray.obstacleClear);
  c.centreAhead = nav::clearAhead(plane, p, s.yaw, ray.obstacleClear);
  c.leftAhead = nav::clearAhead(plane, p + ray.obstacleHalfWidth * left, s.yaw, ray.obstacleClear);
  const nav::Path& path = nav_->path();
  if (out.events.replanned) stairsPassed_ = -1;
  if (out.state != nav::NavState::Following || !path.found || path.points.size() < 2) return c;
  c.haveLeg = true;
  const double s0 = out.follow.progress.arc;
  // a staircase being crossed (latched at its entry): its leg, by the robot's place along it, whatever the path does
  // (a path replanned on the stairs starts on them, and the walk took over on a deck)
  if (latch_.on) {
    if (latchedLeg(p, &c)) return c;
    latch_.on = false;  // passed (or lost): off the stairs skill, and not onto them again (nor back to them)
    for (const nav::StairsSpan& st : path.stairs)
      if (st.to + kStairsExitAfter > s0) {
        stairsPassed_ = st.from;
        break;
      }
  }
  // the next staircase on the path, and where its leg begins
  const nav::StairsSpan* span = nullptr;
  for (const nav::StairsSpan& st : path.stairs)
    if (st.to + kStairsExitAfter > s0 && st.from != stairsPassed_) {
      span = &st;
      break;
    }
  double entry = 0;
  Eigen::Vector2d entryPoint = Eigen::Vector2d::Zero();  // where the stairs leg starts: on the stairs' middle line
  if (span) {
    const int j = path.segmentAt(span->from + 1e-3);  // the straight that crosses the stairs starts at point j
    entry = std::max(path.arc[size_t(j)], span->from - kStairsEntryBefore);
    // the staircase's middle line: through the middle of its stair cells across the span's middle, along its axis (a
    // path may cross the stairs up to 5 deg off their axis, so each point is projected onto this line)
    const Eigen::Vector2d axis(std::cos(span->heading), std::sin(span->heading));
    const Eigen::Vector2d centre =
        path.pointAt(0.5 * (span->from + span->to)) + stairsMiddle(nav_->grid(), path, *span);
    auto onMiddle = [&](const Eigen::Vector2d& q) -> Eigen::Vector2d { return centre + (q - centre).dot(axis) * axis; };
    // kStairsEntryBefore before the first stair cell on the middle line (a robot radius and that much before the
    // first riser) when it can be walked to from the path's corner; else where the path's straight begins. (A path
    // that comes in from the side turns at the stair cells' edge: the stairs started 0.2 m from the riser, and fell.)
    entryPoint = onMiddle(path.pointAt(entry));
    const Eigen::Vector2d square = onMiddle(path.pointAt(span->from)) - kStairsEntryBefore * axis;
    const Eigen::Vector2i cell = nav_->grid().cellAt(square);
    if ((square - entryPoint).dot(axis) < 0 && nav_->grid().traversable(cell.x(), cell.y()) &&
        nav::lineOfSight(nav_->grid(), path.pointAt(entry), square, nav_->params().planner.stairLineTolerance))
      entryPoint = square;
    // the stairs leg starts on the staircase's middle line in front of it: within kStairsEntryAcross of that line (or
    // right at the entry) and within kStairsEntryReach of the entry along it; or on the stairs already
    const Eigen::Vector2d toRobot = p - entryPoint;
    const double across = std::abs(axis.x() * toRobot.y() - axis.y() * toRobot.x());
    const bool atEntry = std::abs(toRobot.dot(axis)) < kStairsEntryReach &&
                         (across < kStairsEntryAcross || toRobot.norm() < kStairsEntryAcross);
    const Eigen::Vector2i here = nav_->grid().cellAt(p);
    const bool onStairs = nav_->grid().kind(here.x(), here.y()) == nav::CellKind::Stairs && s0 >= span->from;
    // the leg's end: kStairsExitAfter past the last stair cell on the middle line, measured along the axis
    const double exitAlong = (onMiddle(path.pointAt(span->to)) + kStairsExitAfter * axis - centre).dot(axis);
    const bool exitAhead = exitAlong - (p - centre).dot(axis) > kStairsExitDone;
    if (exitAhead && (atEntry || onStairs || s0 >= span->from + kStairsEntryReach)) {
      latch_ = {true, centre, axis, span->heading, exitAlong};
      if (latchedLeg(p, &c)) return c;  // (its end is ahead; kStairsLost is more than the entry's reach)
      latch_.on = false;
    }
  }
  // the leg ends at the next waypoint ahead; with steering, a corner is taken from kCornerReach before it
  const double reach = keys_.params().steer ? kCornerReach : 0.0;
  double end = path.length();
  for (size_t i = 1; i < path.points.size(); ++i)
    if (path.arc[i] > s0 + kSkipWaypoint &&
        (i + 1 == path.points.size() || (path.points[i] - p).norm() > reach || (span && entry <= path.arc[i]))) {
      end = path.arc[i];
      break;
    }
  // a target with another after it is walked through: the next one is given the tick it is reached, and the leg to
  // it turns from rest only if its corner is too sharp to steer round
  const bool moreTargets = random_ || targetIndex_ + 1 < int(fixed_.size());
  c.endStops = end >= path.length() && !moreTargets;
  const bool toStairs = span && entry <= end;
  if (toStairs) end = entry, c.endStops = true;
  // a leg to a staircase ends on the staircase's middle line, square in front of it
  const Eigen::Vector2d endPoint = toStairs ? entryPoint : path.pointAt(end);
  const Eigen::Vector2d to = endPoint - p;
  c.legRemaining = to.norm();
  // with steering, aim at the path a little ahead (back onto its line) rather than at the leg's end
  const double pursuit = s0 + keys_.params().steerPursuit;
  const Eigen::Vector2d aim = keys_.params().steer && pursuit < end ? path.pointAt(pursuit) - p : to;
  c.legHeading = aim.norm() > 1e-6 ? std::atan2(aim.y(), aim.x()) : s.yaw;
  return c;
}

bool GardenPilot::latchedLeg(const Eigen::Vector2d& p, LegCues* c) const {
  const Eigen::Vector2d d = p - latch_.centre;
  const double beyond = latch_.exitAlong - d.dot(latch_.axis);
  const double across = std::abs(latch_.axis.x() * d.y() - latch_.axis.y() * d.x());
  if (beyond <= kStairsExitDone || across >= kStairsLost) return false;
  c->stairsLeg = true;
  c->legRemaining = beyond;
  // squared up to the axis; on the way, aimed at the middle line a little ahead (steered when the stairs can)
  c->legHeading = latch_.heading;
  if (keys_.mode() == GardenKeys::Mode::Go) {
    const Eigen::Vector2d aim = latch_.centre + (d.dot(latch_.axis) + keys_.params().steerPursuit) * latch_.axis - p;
    c->legHeading = std::atan2(aim.y(), aim.x());
  }
  return true;
}

std::vector<engine::KeyEvent> GardenPilot::decide(int64_t tick, const Session& session) {
  const robot::Sensors& s = session.sensors();
  const Eigen::Vector2d p = s.basePosition.head<2>();
  std::string events;
  auto event = [&](const char* e) { events += (events.empty() ? "" : "+") + std::string(e); };
  if (targetIndex_ < 0) {
    nextTarget(p);
    event("target");
  }
  if (yaws_.size() < size_t(kYawWindow))
    yaws_.push_back(s.yaw);
  else
    yaws_[yawNext_] = s.yaw;
  yawNext_ = (yawNext_ + 1) % size_t(kYawWindow);
  nav::NavInput in;
  in.position = p;
  in.yaw = s.yaw;
  in.forward = keys_.mode() == GardenKeys::Mode::Go;
  const Eigen::Vector3d v = s.baseRotation * s.linearVelocity;
  in.speed = v.x() * std::cos(s.yaw) + v.y() * std::sin(s.yaw);
  nav::NavOutput out = nav_->step(session.plane(), in, engine::kTickSeconds);
  if (out.events.reached) {
    ++tally_.reached;
    tally_.reachedTicks.push_back(tick);
    event("reached");
    nextTarget(p);
    event("target");
    out = nav_->step(session.plane(), in, 0.0);  // plan for the new target at once (no time passes)
  }
  if (out.events.stuck) ++tally_.stuck, event("stuck");
  if (out.events.noPath) ++tally_.noPath, event("noPath");
  if (out.events.replanned) ++tally_.replans, event("replanned");
  const LegCues cues = legCues(session, out);
  std::vector<engine::KeyEvent> keys = keys_.decide(tick, cues);

  last_ = GardenTick{};
  last_.target = nav_->hasTarget() ? targetIndex_ : -1;
  if (nav_->hasTarget()) {
    const Eigen::Vector2d d = nav_->target() - p;
    last_.targetDistance = d.norm();
    last_.targetAngle = std::remainder(std::atan2(d.y(), d.x()) - s.yaw, 2.0 * M_PI);
  }
  last_.obstacleFactor = out.follow.obstacleFactor;
  last_.navVr = out.command.vr;
  last_.navWr = out.command.wr;
  last_.events = events;
  last_.mode = keys_.mode();
  return keys;
}

}  // namespace game
