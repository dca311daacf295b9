// follower.cpp — see follower.h.
#include "game/nav/follower.h"

#include <algorithm>
#include <cmath>

#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"

namespace game::nav {
namespace {

// segments a projection may move on to in one tick: those starting within this of the current one's end [m]
constexpr double kProjectionWindow = 2.0;

const SpeedProfile& profileOf(const FollowerParams& p, NavSkill s) {
  return s == NavSkill::Run ? p.run : s == NavSkill::Stairs ? p.stairs : p.walk;
}

// the first stairs span that the robot has not yet left (arc <= its end + exit), or nullptr
const StairsSpan* nextSpan(const Path& path, double arc, double exit) {
  for (const StairsSpan& s : path.stairs)
    if (arc <= s.to + exit) return &s;
  return nullptr;
}

}  // namespace

const char* skillName(NavSkill skill) {
  switch (skill) {
    case NavSkill::Walk:
      return "walk";
    case NavSkill::Run:
      return "run";
    case NavSkill::Stairs:
      return "stairs";
  }
  return "?";
}

double wrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

double interlockLimit(const SpeedProfile& p, double wr) {
  const double w = std::abs(wr);
  if (w <= p.wFree) return p.vMax;
  if (w >= p.wMax) return p.vMin;
  return p.vMax + (p.vMin - p.vMax) * (w - p.wFree) / (p.wMax - p.wFree);
}

double clearAhead(const engine::PlaneWorld& plane, const Eigen::Vector2d& from, double yaw, double length) {
  const Eigen::Vector2d ahead(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d to = from + length * ahead;
  Eigen::Vector2d at = from;
  // a staircase is walked on, not into: look through its boxes (one at a time; a ray starting inside a box does not
  // hit it)
  for (int i = 0; i < 32; ++i) {
    const engine::RayHit hit = plane.rayCast(at, to);
    if (!hit.hit) break;
    if (engine::isStairTag(hit.tag)) {
      at = hit.point + 1e-4 * ahead;
      if ((to - at).dot(ahead) <= 0) break;
      continue;
    }
    return (hit.point - from).dot(ahead);
  }
  return 1e9;
}

double obstacleFactor(const engine::PlaneWorld& plane, const Eigen::Vector2d& position, double yaw,
                      const FollowerParams& params, double* nearestOut) {
  const Eigen::Vector2d left(-std::sin(yaw), std::cos(yaw));
  double nearest = 1e9;
  for (const double k : {-1.0, -0.5, 0.0, 0.5, 1.0})
    nearest =
        std::min(nearest, clearAhead(plane, position + k * params.obstacleHalfWidth * left, yaw, params.obstacleClear));
  if (nearestOut) *nearestOut = nearest;
  if (nearest >= params.obstacleClear) return 1.0;
  return std::clamp((nearest - params.obstacleStop) / (params.obstacleClear - params.obstacleStop), 0.0, 1.0);
}

PathProgress projectOnPath(const Path& path, const Eigen::Vector2d& p, int fromSegment) {
  PathProgress best;
  if (path.points.size() < 2) {
    best.offPath = path.points.empty() ? 0.0 : (p - path.points.front()).norm();
    return best;
  }
  const int last = static_cast<int>(path.points.size()) - 2;
  const int first = std::clamp(fromSegment, 0, last);
  double bestDistance = 1e18;
  for (int k = first; k <= last; ++k) {
    if (k > first && path.arc[k] > path.arc[first + 1] + kProjectionWindow) break;
    const Eigen::Vector2d a = path.points[k], d = path.points[k + 1] - a;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    const double distance = (a + t * d - p).norm();
    if (distance < bestDistance) {
      bestDistance = distance;
      best.segment = k;
      best.arc = path.arc[k] + t * std::sqrt(len2);
      best.offPath = distance;
    }
  }
  return best;
}

double straightAhead(const Path& path, double s, double cornerAngle) {
  if (path.points.size() < 2) return 0;
  const int n = static_cast<int>(path.points.size()) - 1;  // segments
  int k = path.segmentAt(s);
  double straight = path.arc[k + 1] - std::max(s, path.arc[k]);
  for (++k; k < n; ++k) {
    const Eigen::Vector2d before = path.points[k] - path.points[k - 1], after = path.points[k + 1] - path.points[k];
    const double turn = std::abs(wrapAngle(std::atan2(after.y(), after.x()) - std::atan2(before.y(), before.x())));
    if (turn > cornerAngle) break;
    straight += path.arc[k + 1] - path.arc[k];
  }
  return straight;
}

NavSkill chooseSkill(const SkillCues& c, const FollowerParams& p) {
  if (c.stairsZone) {
    if (c.current == NavSkill::Stairs) return NavSkill::Stairs;
    return c.squaredUp && c.speed <= p.stairsEntrySpeed ? NavSkill::Stairs : NavSkill::Walk;
  }
  const double heading = std::abs(c.headingError);
  if (c.current == NavSkill::Run && c.straightAhead >= p.runLeaveStraight && heading <= p.runLeaveHeading &&
      c.obstacleFactor >= p.runLeaveObstacle)
    return NavSkill::Run;
  if (c.straightAhead >= p.runStraight && heading <= p.runHeading && c.obstacleFactor >= p.runObstacle)
    return NavSkill::Run;
  return NavSkill::Walk;
}

NavCommand PathFollower::follow(const Path& path, const engine::PlaneWorld& plane, const Eigen::Vector2d& position,
                                double yaw, double speed, FollowInfo* infoOut) {
  FollowInfo info;
  NavCommand cmd;
  if (!path.found || path.points.size() < 2) {
    cmd.skill = skill_ = NavSkill::Walk;
    if (infoOut) *infoOut = info;
    return cmd;
  }
  const FollowerParams& p = params_;
  info.progress = projectOnPath(path, position, segment_);
  segment_ = info.progress.segment;
  const double arc = info.progress.arc;
  info.remaining = path.length() - arc;

  // the staircase ahead (or under the robot) and its zone
  const StairsSpan* span = nextSpan(path, arc, p.stairsExit);
  info.stairsZone = span && arc >= span->from - p.stairsApproach;
  const double stairsError = span ? wrapAngle(span->heading - yaw) : 0.0;

  // heading control toward the lookahead point (the current skill's)
  auto aimError = [&](const SpeedProfile& prof) {
    const Eigen::Vector2d aim = path.pointAt(arc + prof.lookahead) - position;
    return aim.norm() > 1e-9 ? wrapAngle(std::atan2(aim.y(), aim.x()) - yaw) : 0.0;
  };
  info.headingError = aimError(profileOf(p, skill_));
  info.obstacleFactor = obstacleFactor(plane, position, yaw, p);

  SkillCues cues;
  cues.current = skill_;
  cues.straightAhead = straightAhead(path, arc, p.runCornerAngle);
  if (span && !info.stairsZone) cues.straightAhead = std::min(cues.straightAhead, span->from - p.stairsApproach - arc);
  cues.headingError = info.headingError;
  cues.obstacleFactor = info.obstacleFactor;
  cues.stairsZone = info.stairsZone;
  cues.squaredUp = info.stairsZone && std::abs(stairsError) <= p.stairsAlignTolerance;
  cues.speed = speed;
  skill_ = chooseSkill(cues, p);
  cmd.skill = skill_;
  const SpeedProfile& prof = profileOf(p, skill_);
  info.headingError = aimError(prof);

  if (info.stairsZone && skill_ != NavSkill::Stairs && !cues.squaredUp) {
    // square up to the staircase: turn in place to its heading
    info.squaringUp = info.turningInPlace = true;
    const double rate = std::clamp(std::max(p.minTurnInPlace, p.turnGain * std::abs(stairsError)), 0.0, prof.wMax);
    cmd.wr = stairsError >= 0 ? rate : -rate;
    cmd.vr = 0;
  } else {
    cmd.wr = std::clamp(p.turnGain * info.headingError, -prof.wMax, prof.wMax);
    const double limit = interlockLimit(prof, cmd.wr);
    info.turningInPlace = limit <= 1e-9;
    cmd.vr = std::min(prof.vMax, limit) * info.obstacleFactor;
    if (info.stairsZone && skill_ != NavSkill::Stairs) cmd.vr = std::min(cmd.vr, p.stairsApproachSpeed);  // slowing
    cmd.vr = std::min(cmd.vr, p.arrivalGain * info.remaining);
  }
  if (infoOut) *infoOut = info;
  return cmd;
}

}  // namespace game::nav
