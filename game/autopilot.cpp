// autopilot.cpp — see autopilot.h. Thresholds are in metres along the course and in ticks of 0.01 s.
#include "game/autopilot.h"

#include <algorithm>
#include <cmath>

#include "game/session.h"

namespace game {
namespace {

constexpr double kGhostRun = 4.0;      // run while a ghost is this close
constexpr double kStairsStart = 2.0;   // stop this far before a step, then the stairs from rest (from the walk's
                                       // 0.7 m/s they fell at the first step)
constexpr double kStairsSlow = 3.0;    // leave run for walk this far before a step
constexpr double kCeilingStart = 1.8;  // lie down this far before a tunnel (the body falls ~1 m ahead)
constexpr double kProneY = 0.3;        // lie down this far left of the middle: from the walk's stance the prone
                                       // falls ~0.4 m to the right, and the crawl drifts on rightward
constexpr double kCeilingClear = 1.2;  // stand up this far past the tunnel's end (the stand-up kneels back ~0.8 m)
constexpr double kBallAlignAt = 0.8;   // stop and line up with the ball this far before it (the walk stops in ~0.4 m)
constexpr double kBallKick = 0.30;     // the kick's card: the ball 0.30 m ahead of the pelvis ...
constexpr double kBallSide = -0.12;    // ... and 0.12 m to its right (in front of the right foot)
// kick only from the card's spot, within these: a line-up that timed out or ran out of steps, or a ball that moved
// during the one-leg stand, lines up again
// (the ball measured in the pelvis's heading frame). The one-leg stand turns the robot by up to ~0.3 rad: after it
// the kick may face up to kKickYawTol off +X (the goal spans the course; over autopilot seeds 1-40 the ball phase
// took 39 s on average against 48 s with 0.10, most of the saving line-ups after the stand)
constexpr double kBallAheadTol = 0.08, kBallSideTol = 0.06, kBallYawTol = 0.10, kKickYawTol = 0.25;
constexpr double kBallBehind = 1.5;  // a ball up to this far behind the pelvis is still to be kicked: back up to it
constexpr double kBallClear = 0.45;  // step this far to the side of it before backing up (not into it)
constexpr double kBallReach = 0.75;  // line up at most this far off the course's middle (the walls are at +-1.0)
// the kick's line at most this far off the middle (0.35 m from a wall; on variants with the ball 0.31-0.46 m from the
// left wall the line-up at 0.75 missed its spot for a minute at a time, the pelvis pushed off the wall)
constexpr double kKickLineMax = 0.65;
constexpr double kDribbleUntil = 0.1;  // the dribble goes on until the ball's kick line is this far inside kKickLineMax
// a ball too near a wall for the right-footed kick's spot (kickOutOfReach) is pushed on instead: the robot lines up
// with the ball in front of the foot nearer that wall and walks through it (the goal spans the course, so a ball
// rolled along the wall goes in as well as a kicked one; by the right wall the kick's stance left the ball short)
constexpr double kDribbleSide = 0.12;   // a foot's offset from the pelvis (feet 0.237 m apart)
constexpr double kDribbleYaw = 0.1;     // facing a little toward the wall: the arms keep the pelvis ~0.25 m from it,
                                        // and walking straight the left foot passed beside a ball resting there
constexpr double kDribblePassed = 0.3;  // walk on until the ball is this far behind the pelvis (the robot got past
                                        // it), or it rolled away from the wall, or kDribbleTimeout
constexpr double kOffLine = 0.45;  // walking this far off y = 0 (or kOffHeading off +X) with nothing close: re-align
constexpr double kOffHeading = 0.3;
constexpr double kWalkYawTol = 0.03;       // the heading that re-alignment leaves before walking on [rad]
constexpr double kRestSpeed = 0.06;        // at rest for the align steps [m/s]
constexpr double kStairsTurnedAway = 1.2;  // [rad] the stairs skill facing this far off +X before it climbed: stop
constexpr double kStairsStopFrom = 1.3;    // stop for the stairs below this speed [m/s] (until then the keys stay)
constexpr double kAlignFrom = 0.8;         // re-align only below this speed [m/s] (the walk's W is released until then)
constexpr double kKeyRamp = 2.0;           // the keys' velocity ramp [m/s^2] and turn ramp [rad/s^2] (engine/input)
constexpr double kTurnRamp = 3.0;
constexpr double kProneHeight = 0.40;   // lying when the pelvis is this low
constexpr double kStoodHeight = 0.70;   // standing again
constexpr double kFlightHeight = 0.86;  // pelvis [m] above which a jump has left the ground (standing: 0.78)
// kBalanceTicks: the one-leg stand before the kick. Over 10 seeds of levels/mario the kick fell 37 times after
// 1.5 s of it, 22 after 3 s, 18 after 5 s (the same 6 wins as 1.5 s), 17 after 8 s (4 wins: the waits ran the clock
// out). Counted from the stand's takeover (the switch into it waits up to 3 s for the robot to stop drifting,
// robot::kSettleDrift; counted from the key, as before, the stand shrank to 2 s and seeds 3 and 9 of 1-60 ran out of
// time re-lining up); kBalanceTimeout from the key, in case the stand never takes over.
constexpr int64_t kBalanceTimeout = 700;
constexpr int64_t kProneLie = 300, kProneTimeout = 600, kStandTimeout = 600, kJumpTimeout = 400, kBalanceTicks = 400,
                  kKickTicks = 250, kRecoverTicks = 150, kSettleTicks = 40, kAlignTimeout = 1500,
                  kApproachTimeout = 1500, kBackUpTimeout = 600, kDribbleTimeout = 2000;
constexpr int kAlignTries = 4;
constexpr int kMaxPulses = 8;
constexpr int64_t kPulseTicks = 15;

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }
// where the line-up puts the pelvis across the course: kBallSide from the ball, or as near as the walls let it
double kickLineY(const Cues& c) { return std::clamp(c.ballY - kBallSide, -kBallReach, kBallReach); }
// the kick's spot is out of reach: its line would put the pelvis within 0.35 m of a wall (kKickLineMax), where the
// arms touch it and the short steps of the line-up could not hold the spot. `margin` > 0 asks for a ball further in
// (the dribble pushes on until the ball is well clear of that line)
bool kickOutOfReach(const Cues& c, double margin = 0) { return std::abs(c.ballY - kBallSide) > kKickLineMax - margin; }

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
  c.stepAhead = ahead(ground + 0.05, 4.0);  // far enough to slow from the run (kStairsSlow)
  const double low = ahead(ground + 0.7, 2.0), open = ahead(ground + 0.3, 2.0);
  if (low < 1e9 && open > low + 0.3) c.ceilingAhead = low;
  c.underCeiling = plane.rayCast({p.x(), ground + 0.3}, {p.x(), ground + 1.0}).hit;
  c.boxAhead = ahead(ground + 1.5, 3.0);
  c.boxOverhead = plane.rayCast({p.x() - 0.15, ground + 1.2}, {p.x() - 0.15, ground + 2.0}).hit ||
                  plane.rayCast({p.x() + 0.15, ground + 1.2}, {p.x() + 0.15, ground + 2.0}).hit;
  if (const Course* course = s.course()) {
    c.ghost = course->ghostDistance();
    if (course->firstBall() >= 0) {
      const Eigen::Vector3d ball = s.physics().ballState(course->firstBall()).position;
      c.ballAhead = ball.x() - p.x();
      c.ballY = ball.y();
    }
    const auto& ev = course->events();
    c.boxJustHit = !ev.empty() && ev.back().tick + 1 >= s.tick() && ev.back().kind == game::CourseEventKind::BoxHit;
  }
  c.y = p.y();
  c.yaw = s.sensors().yaw;
  c.speed = (s.sensors().baseRotation * s.sensors().linearVelocity).head<2>().norm();
  c.commandVx = s.command().vx, c.commandVy = s.command().vy, c.commandWz = s.command().wz;
  c.respawns = int(s.telemetry().respawns.size());
  c.canJump = s.skills() && s.skills()->byName("jump");
  c.skill = s.activeSkillName();
  return c;
}

SkillKeys skillKeys(const robot::SkillSet& skills) {
  auto key = [&](const char* name) -> char {
    const robot::Skill* s = skills.byName(name);
    const int k = s ? skills.requestKey(*s) : -1;
    return k >= 0 ? char('0' + k) : 0;
  };
  SkillKeys k;
  k.walk = key("walk"), k.run = key("run"), k.stairs = key("stairs"), k.jump = key("jump");
  k.oneLeg = key("one_leg"), k.kick = key("kick"), k.prone = key("prone"), k.crawl = key("crawl");
  return k;
}

const char* Autopilot::modeName(Mode m) {
  switch (m) {
    case Mode::Walk:
      return "walk";
    case Mode::Run:
      return "run";
    case Mode::Stairs:
      return "stairs";
    case Mode::Prone:
      return "prone";
    case Mode::Crawl:
      return "crawl";
    case Mode::StandUp:
      return "stand up";
    case Mode::Jump:
      return "jump";
    case Mode::Align:
      return "align";
    case Mode::Approach:
      return "approach";
    case Mode::Balance:
      return "balance";
    case Mode::Kick:
      return "kick";
    case Mode::Recover:
      return "recover";
    case Mode::BackUp:
      return "back up";
    case Mode::Dribble:
      return "dribble";
  }
  return "?";
}

void Autopilot::hold(int64_t tick, char key, bool down, std::vector<engine::KeyEvent>* out) {
  held_.hold(tick, key, down, out);
}

void Autopilot::releaseAll(int64_t tick, std::vector<engine::KeyEvent>* out) { held_.releaseAll(tick, out); }

void Autopilot::enter(int64_t tick, Mode m, char skillKey, bool forward, std::vector<engine::KeyEvent>* out) {
  mode_ = m;
  since_ = tick;
  if (skillKey) out->push_back({tick, engine::KeyAction::kTap, skillKey});
  for (const char k : std::string("SADQE")) hold(tick, k, false, out);
  hold(tick, 'W', forward, out);
  alignStep_ = 0, alignTries_ = 0, keyUpTick_ = -1, alignYaw_ = 0;
}

// one key at a time (the interlock): pressed toward the target, released early enough that the command's ramp
// down (rate `ramp`, the command now `command`) stops the motion within half the tolerance of it
void Autopilot::nudge(int64_t tick, double error, double command, double ramp, double tolerance, char plus, char minus,
                      std::vector<engine::KeyEvent>* out) {
  if (held_.empty()) {
    hold(tick, error > 0 ? plus : minus, true, out);
    ++alignTries_;
    keyUpTick_ = -1;
  } else if (std::abs(error) < command * command / (2 * ramp) + 0.5 * tolerance) {
    releaseAll(tick, out);
    keyUpTick_ = tick;
  }
}

bool Autopilot::align(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out) {
  const bool still = c.speed < kRestSpeed && c.commandVx == 0 && c.commandVy == 0 && c.commandWz == 0;
  const bool settled = still && keyUpTick_ >= 0 && tick - keyUpTick_ >= kSettleTicks;
  const double yawError = wrap(alignYaw_ - c.yaw), yError = alignY_ - c.y;
  if (alignStep_ == 0) {  // stop
    if (still) keyUpTick_ = keyUpTick_ < 0 ? tick : keyUpTick_;
    if (settled) alignStep_ = 1, alignTries_ = 0;
    return false;
  }
  if (held_.empty() && !settled) return false;
  if (alignStep_ == 1) {  // turn toward +X
    if (held_.empty() && (std::abs(yawError) < alignYawTol_ || alignTries_ >= kAlignTries))
      alignStep_ = 2;
    else
      nudge(tick, yawError, c.commandWz, kTurnRamp, alignYawTol_, 'A', 'D', out);
    return false;
  }
  // step sideways to the line
  if (held_.empty()) {
    if (alignTries_ >= 2 * kAlignTries) return true;
    if (std::abs(yError) < alignYTol_) {
      if (std::abs(yawError) < alignYawTol_) return true;
      alignStep_ = 1;  // the side steps turned it: face +X again
      return false;
    }
  }
  nudge(tick, yError, c.commandVy, kKeyRamp, alignYTol_, 'Q', 'E', out);
  return false;
}

bool Autopilot::approach(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out) {
  const bool still = c.speed < kRestSpeed && c.commandVx == 0;
  const double error = c.ballAhead - kBallKick;  // > 0: still short of the ball
  if (held_.empty()) {
    if (keyUpTick_ >= 0 && (!still || tick - keyUpTick_ < kSettleTicks)) return false;
    if (std::abs(error) < 0.05 || pulses_ >= kMaxPulses) return true;
    hold(tick, error > 0 ? 'W' : 'S', true, out);
    keyUpTick_ = -1;
    pulses_++;
    pulseTick_ = tick;
  } else if (tick - pulseTick_ >= kPulseTicks) {  // a short step's worth of W or S (longer steps pushed the ball)
    releaseAll(tick, out);
    keyUpTick_ = tick;
  }
  return false;
}

bool Autopilot::atKickSpot(const Cues& c, double yawTol) {
  // the ball in the pelvis's heading frame, where the kick's card puts it
  const double dx = c.ballAhead, dy = c.ballY - c.y, cy = std::cos(c.yaw), sy = std::sin(c.yaw);
  const double ahead = cy * dx + sy * dy, side = -sy * dx + cy * dy;
  return std::abs(ahead - kBallKick) < kBallAheadTol && std::abs(side - kBallSide) < kBallSideTol &&
         std::abs(wrap(c.yaw)) < yawTol;
}

void Autopilot::lineUpWithBall(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out) {
  enter(tick, Mode::Align, 0, false, out);
  alignY_ = kickLineY(c);
  alignYTol_ = 0.04, alignYawTol_ = 0.05, afterAlign_ = Mode::Approach;
  if (kickOutOfReach(c)) {  // by a wall: push it on with the foot nearer that wall instead
    const double wall = c.ballY - kBallSide > 0 ? 1.0 : -1.0;
    alignY_ = std::clamp(c.ballY - wall * kDribbleSide, -kBallReach, kBallReach);
    alignYaw_ = wall * kDribbleYaw, alignYTol_ = 0.06, alignYawTol_ = 0.1, afterAlign_ = Mode::Dribble;
  }
}

// the ball beside or behind the pelvis: clear of it sideways (toward the middle), then back up (Mode::BackUp)
void Autopilot::backOffBall(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out) {
  enter(tick, Mode::Align, 0, false, out);
  alignY_ = std::abs(c.y - c.ballY) >= kBallClear ? c.y : c.ballY + (c.ballY > 0 ? -kBallClear : kBallClear);
  alignY_ = std::clamp(alignY_, -kBallReach, kBallReach);
  alignYTol_ = 0.1, alignYawTol_ = 0.1, afterAlign_ = Mode::BackUp;
}

std::vector<engine::KeyEvent> Autopilot::decide(int64_t tick, const Cues& c) {
  std::vector<engine::KeyEvent> out;
  if (!started_) {
    started_ = true;
    respawnsSeen_ = c.respawns;
    enter(tick, Mode::Walk, keys_.walk, true, &out);
    return out;
  }
  if (c.respawns > respawnsSeen_) {  // put back at a checkpoint: start over from there, walking
    respawnsSeen_ = c.respawns;
    releaseAll(tick, &out);
    enter(tick, Mode::Walk, keys_.walk, true, &out);
    return out;
  }
  const int64_t in = tick - since_;
  const bool ghostClose = c.ghost >= 0 && c.ghost < kGhostRun;
  switch (mode_) {
    case Mode::Walk:
    case Mode::Run:
      if (c.ballAhead < kBallAlignAt && c.ballAhead > kBallKick - 0.15 && !ghostClose) {
        lineUpWithBall(tick, c, &out);
      } else if (c.ballAhead <= kBallKick - 0.15 && c.ballAhead > -kBallBehind && !ghostClose) {
        backOffBall(tick, c, &out);
      } else if (c.boxOverhead && c.canJump && std::abs(c.x - jumpedAtX_) > 1.0) {
        jumpedAtX_ = c.x, flew_ = false;
        enter(tick, Mode::Jump, keys_.jump, false, &out);
      } else if (c.ceilingAhead <
                 kCeilingStart) {  // stop square to the course a little left of its middle, then lie down
        enter(tick, Mode::Align, 0, false, &out);
        alignY_ = kProneY, alignYTol_ = 0.08, alignYawTol_ = 0.05, afterAlign_ = Mode::Prone;
      } else if (c.stepAhead < kStairsStart) {
        // the stop for the stairs waits for the walk's own speeds: the walk taking over from the run at 1.6-1.9 m/s
        // with W released spun half round (autopilot seeds 17 and 19)
        if (c.speed <= kStairsStopFrom) {
          enter(tick, Mode::Stairs, 0, false, &out);
          stairsStarted_ = false, climbed_ = false;
        }
      } else if (mode_ == Mode::Walk && ghostClose && c.stepAhead > kStairsSlow) {
        enter(tick, Mode::Run, keys_.run, true, &out);
      } else if (mode_ == Mode::Run && (c.ghost < 0 || c.stepAhead < kStairsSlow)) {
        enter(tick, Mode::Walk, keys_.walk, true, &out);
      } else if (mode_ == Mode::Walk && !ghostClose && c.stepAhead > 1.0 && c.ceilingAhead > 2.5 && !c.boxOverhead &&
                 (std::abs(c.y) > kOffLine || std::abs(wrap(c.yaw)) > kOffHeading)) {
        // facing +X within 0.03 rad: W from rest sets the heading the walk and then the run hold (the heading hold,
        // robot::shapeCommand), and at 0.1 the run, holding up to 0.1 rad off the course for 10 m, went into a wall
        // (levels/mario autopilot seeds 1-40: 35 run falls at 0.1, 23 at 0.03; 84 falls in all against 61).
        // From a run's speed the walk first slows straight on (W released): turning while it braked from 1.7 m/s,
        // it spun half round (autopilot seed 19)
        if (c.speed > kAlignFrom) {
          hold(tick, 'W', false, &out);
        } else {
          enter(tick, Mode::Align, 0, false, &out);
          alignY_ = 0, alignYTol_ = 0.1, alignYawTol_ = kWalkYawTol, afterAlign_ = Mode::Walk;
        }
      } else if (mode_ == Mode::Walk) {
        hold(tick, 'W', true, &out);  // (again, after slowing for a re-alignment that was no longer needed)
      }
      break;
    case Mode::Align:
      if (ghostClose && afterAlign_ == Mode::Walk) {  // a ghost came while it stood: run
        enter(tick, Mode::Run, keys_.run, true, &out);
      } else if (align(tick, c, &out) || in > kAlignTimeout) {
        if (afterAlign_ == Mode::Approach) {
          enter(tick, Mode::Approach, 0, false, &out);
          pulses_ = 0;
        } else if (afterAlign_ == Mode::Dribble) {
          enter(tick, Mode::Dribble, 0, true, &out);
        } else if (afterAlign_ == Mode::Prone) {
          enter(tick, Mode::Prone, keys_.prone, false, &out);
        } else if (afterAlign_ == Mode::BackUp) {
          enter(tick, Mode::BackUp, 0, false, &out);
          hold(tick, 'S', true, &out);
        } else {
          enter(tick, Mode::Walk, 0, true, &out);
        }
      }
      break;
    case Mode::Dribble:
      // walking into the ball along the wall: done once it rolled away from the wall (the walk lines up to kick it)
      // or the robot got past it (the walk backs off and lines up again)
      if (!kickOutOfReach(c, kDribbleUntil) || c.ballAhead < -kDribblePassed || in > kDribbleTimeout)
        enter(tick, Mode::Walk, 0, true, &out);
      break;
    case Mode::BackUp:
      if (c.ballAhead > kBallAlignAt - 0.1 || in > kBackUpTimeout) lineUpWithBall(tick, c, &out);
      break;
    case Mode::Approach:
      // the line-up walked past the ball (side steps drift forward): the short steps cannot get back behind it
      if (c.ballAhead <= kBallKick - 0.15 && held_.empty()) {
        backOffBall(tick, c, &out);
      } else if (approach(tick, c, &out) || in > kApproachTimeout) {
        if (atKickSpot(c, kBallYawTol))
          enter(tick, Mode::Balance, keys_.oneLeg, false, &out);
        else
          lineUpWithBall(tick, c, &out);
      }
      break;
    case Mode::Stairs:
      if (!stairsStarted_) {  // at rest first, then the stairs skill and W
        if (c.speed < kRestSpeed && c.commandVx == 0 && in > kSettleTicks) {
          if (std::abs(wrap(c.yaw)) > kOffHeading) {  // turned away (a hard stop spun it): face the stairs again
            enter(tick, Mode::Align, 0, false, &out);
            alignY_ = c.y, alignYTol_ = 1.0, alignYawTol_ = kWalkYawTol, afterAlign_ = Mode::Walk;
          } else {
            stairsStarted_ = true;
            enter(tick, Mode::Stairs, keys_.stairs, true, &out);
          }
        }
        break;
      }
      if (!climbed_ && std::abs(wrap(c.yaw)) > kStairsTurnedAway) {  // turned round before it climbed: stop, again
        enter(tick, Mode::Stairs, keys_.walk, false, &out);
        stairsStarted_ = false;
        break;
      }
      // back to walk once the robot has climbed and is on flat ground with no step ahead for 0.5 m of travel
      if (c.pelvisHeight > 0.85) climbed_ = true;
      if (climbed_ && c.stepAhead > 1.0 && std::abs(c.pelvisHeight - 0.78) < 0.04) {
        if (flatSince_ < 0) flatSince_ = c.x;
        if (c.x - flatSince_ > 0.5) {
          flatSince_ = -1;
          enter(tick, Mode::Walk, keys_.walk, true, &out);
        }
      } else {
        flatSince_ = -1;
      }
      break;
    case Mode::Prone:
      // lying, and for as long as the crawl's card lets prone lie first (crawling off a fresh landing rolled it over)
      if ((c.pelvisHeight < kProneHeight && in > kProneLie) || in > kProneTimeout) {
        ceilingEndX_ = 1e9;  // not under the ceiling yet: it lies down before the tunnel
        enter(tick, Mode::Crawl, keys_.crawl, true, &out);
      }
      break;
    case Mode::Crawl:
      if (c.underCeiling)
        ceilingEndX_ = c.x;
      else if (c.x - ceilingEndX_ > kCeilingClear)
        enter(tick, Mode::StandUp, keys_.walk, false, &out);  // routed via standup
      break;
    case Mode::StandUp:
      if ((c.pelvisHeight > kStoodHeight && in > 100) || in > kStandTimeout) enter(tick, Mode::Walk, 0, true, &out);
      break;
    case Mode::Jump:
      // one jump: the walk is asked for once the pelvis has been up (it takes over when the robot stands settled
      // again); the jump's later landings were where it fell
      if (c.pelvisHeight > kFlightHeight) flew_ = true;
      if (c.boxJustHit || flew_ || in > kJumpTimeout) {
        // walk out from under the box (the release floats down in front of it)
        enter(tick, Mode::Walk, keys_.walk, true, &out);
      }
      break;
    case Mode::Balance:
      if (c.skill != "one_leg")
        standSince_ = -1;
      else if (standSince_ < 0)
        standSince_ = tick;
      if ((standSince_ >= 0 && tick - standSince_ >= kBalanceTicks) || in > kBalanceTimeout) {
        if (atKickSpot(c, kKickYawTol))
          enter(tick, Mode::Kick, keys_.kick, false, &out);
        else
          enter(tick, Mode::Walk, keys_.walk, false, &out);  // the walk's rules line it up again (or back up)
      }
      break;
    case Mode::Kick:
      if (in > kKickTicks) enter(tick, Mode::Recover, keys_.walk, false, &out);
      break;
    case Mode::Recover:
      // the ball went on (or not): walk after it
      if (in > kRecoverTicks) enter(tick, Mode::Walk, 0, true, &out);
      break;
  }
  return out;
}

}  // namespace game
