// autopilot.cpp — see autopilot.h. Thresholds are in metres along the course and in ticks of 0.01 s.
#include "game/autopilot.h"

#include <cmath>

#include "game/session.h"

namespace game {
namespace {

constexpr double kGhostRun = 4.0;        // run while a ghost is this close
constexpr double kStairsStart = 0.45;    // switch to stairs this far before a step
constexpr double kStairsSlow = 1.5;      // leave run for walk this far before a step
constexpr double kCeilingStart = 1.8;    // lie down this far before a tunnel (the body falls ~1 m ahead)
constexpr double kCeilingClear = 0.5;    // stand up this far past the tunnel's end
constexpr double kBallStop = 0.42;       // stop and kick when the ball is this far ahead
constexpr double kProneHeight = 0.40;    // lying when the pelvis is this low
constexpr double kStoodHeight = 0.70;    // standing again
constexpr int64_t kProneTimeout = 400, kStandTimeout = 600, kJumpTimeout = 400, kBalanceTicks = 150,
                  kKickTicks = 250, kRecoverTicks = 150;

}  // namespace

Cues senseCues(const Session& s) {
  Cues c;
  const Eigen::Vector3d p = s.sensors().basePosition;
  c.x = p.x();
  c.pelvisHeight = p.z();
  const engine::PlaneWorld& plane = s.plane();
  auto ahead = [&](double z, double range) {
    const engine::RayHit h = plane.rayCast({p.x() + 0.05, z}, {p.x() + range, z});
    return h.hit ? h.point.x() - p.x() : 1e9;
  };
  // the ground under the robot may be a stair tread: measure heights from the feet
  const double ground = std::min(s.sensors().footHeight[0], s.sensors().footHeight[1]);
  c.stepAhead = ahead(ground + 0.05, 2.0);
  const double low = ahead(ground + 0.7, 2.0), open = ahead(ground + 0.3, 2.0);
  if (low < 1e9 && open > low + 0.3) c.ceilingAhead = low;
  c.underCeiling = plane.rayCast({p.x(), ground + 0.3}, {p.x(), ground + 1.0}).hit;
  c.boxAhead = ahead(ground + 1.5, 3.0);
  c.boxOverhead = plane.rayCast({p.x() - 0.15, ground + 1.2}, {p.x() - 0.15, ground + 2.0}).hit ||
                  plane.rayCast({p.x() + 0.15, ground + 1.2}, {p.x() + 0.15, ground + 2.0}).hit;
  if (const Course* course = s.course()) {
    c.ghost = course->ghostDistance();
    if (course->firstBall() >= 0) c.ballAhead = s.physics().ballState(course->firstBall()).position.x() - p.x();
    const auto& ev = course->events();
    c.boxJustHit = !ev.empty() && ev.back().tick + 1 >= s.tick() && ev.back().what.find("question box") != std::string::npos;
  }
  return c;
}

const char* Autopilot::modeName(Mode m) {
  switch (m) {
    case Mode::Walk: return "walk";
    case Mode::Run: return "run";
    case Mode::Stairs: return "stairs";
    case Mode::Prone: return "prone";
    case Mode::Crawl: return "crawl";
    case Mode::StandUp: return "stand up";
    case Mode::Jump: return "jump";
    case Mode::Balance: return "balance";
    case Mode::Kick: return "kick";
    case Mode::Recover: return "recover";
  }
  return "?";
}

void Autopilot::enter(int64_t tick, Mode m, char skillKey, bool forward, std::vector<engine::KeyEvent>* out) {
  mode_ = m;
  since_ = tick;
  if (skillKey) out->push_back({tick, engine::KeyAction::kTap, skillKey});
  if (forward != forwardHeld_) out->push_back({tick, forward ? engine::KeyAction::kDown : engine::KeyAction::kUp, 'W'});
  forwardHeld_ = forward;
}

std::vector<engine::KeyEvent> Autopilot::decide(int64_t tick, const Cues& c) {
  std::vector<engine::KeyEvent> out;
  if (!started_) {
    started_ = true;
    enter(tick, Mode::Walk, '0', true, &out);
    return out;
  }
  const int64_t in = tick - since_;
  switch (mode_) {
    case Mode::Walk:
    case Mode::Run:
      if (c.ballAhead < kBallStop && c.ballAhead > -0.2) enter(tick, Mode::Balance, '5', false, &out);
      else if (c.boxOverhead) enter(tick, Mode::Jump, '4', false, &out);
      else if (c.ceilingAhead < kCeilingStart) enter(tick, Mode::Prone, '7', false, &out);
      else if (c.stepAhead < kStairsStart) enter(tick, Mode::Stairs, '2', true, &out);
      else if (mode_ == Mode::Walk && c.ghost >= 0 && c.ghost < kGhostRun && c.stepAhead > kStairsSlow)
        enter(tick, Mode::Run, '1', true, &out);
      else if (mode_ == Mode::Run && (c.ghost < 0 || c.stepAhead < kStairsSlow)) enter(tick, Mode::Walk, '0', true, &out);
      break;
    case Mode::Stairs:
      // back to walk once the robot is on flat ground with no step ahead for 0.5 m of travel
      if (c.stepAhead > 1.0 && std::abs(c.pelvisHeight - 0.78) < 0.04) {
        if (flatSince_ < 0) flatSince_ = c.x;
        if (c.x - flatSince_ > 0.5) {
          flatSince_ = -1;
          enter(tick, Mode::Walk, '0', true, &out);
        }
      } else {
        flatSince_ = -1;
      }
      break;
    case Mode::Prone:
      if (c.pelvisHeight < kProneHeight || in > kProneTimeout) enter(tick, Mode::Crawl, '9', true, &out);
      break;
    case Mode::Crawl:
      if (c.underCeiling || c.ceilingAhead < 0.3) ceilingEndX_ = c.x;
      else if (c.x - ceilingEndX_ > kCeilingClear) enter(tick, Mode::StandUp, '0', false, &out);  // routed via standup
      break;
    case Mode::StandUp:
      if ((c.pelvisHeight > kStoodHeight && in > 100) || in > kStandTimeout) enter(tick, Mode::Walk, 0, true, &out);
      break;
    case Mode::Jump:
      if (c.boxJustHit || in > kJumpTimeout) {
        // walk out from under the box (the release floats down in front of it)
        enter(tick, Mode::Walk, '0', true, &out);
      }
      break;
    case Mode::Balance:
      if (in > kBalanceTicks) enter(tick, Mode::Kick, '6', false, &out);
      break;
    case Mode::Kick:
      if (in > kKickTicks) enter(tick, Mode::Recover, '0', false, &out);
      break;
    case Mode::Recover:
      // the ball went on (or not): walk after it
      if (in > kRecoverTicks) enter(tick, Mode::Walk, 0, true, &out);
      break;
  }
  return out;
}

}  // namespace game
