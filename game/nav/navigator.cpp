// navigator.cpp — see navigator.h.
#include "game/nav/navigator.h"

#include <algorithm>
#include <cmath>

#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"

namespace game::nav {
namespace {

// time is a sum of dt: 100 ticks of 0.01 s may add up to a hair under 1 s
constexpr double kTimeEpsilon = 1e-9;

}  // namespace

const char* stateName(NavState state) {
  switch (state) {
    case NavState::Idle:
      return "idle";
    case NavState::Following:
      return "following";
    case NavState::BackingOff:
      return "backing off";
    case NavState::NoPath:
      return "no path";
  }
  return "?";
}

Navigator::Navigator(const engine::PlaneWorld& plane, const NavigatorParams& params)
    : params_(params), grid_(buildOccupancyGrid(plane, params.grid)), follower_(params.follower) {}

void Navigator::setTarget(const Eigen::Vector2d& target) {
  target_ = target;
  hasTarget_ = true;
  planPending_ = true;
}

void Navigator::clearTarget() {
  hasTarget_ = planPending_ = false;
  path_ = Path();
  state_ = NavState::Idle;
  stateSince_ = time_;
}

void Navigator::replan(const engine::PlaneWorld& plane, const NavInput& in, NavOutput* out) {
  grid_.clearTemporary();
  markMovables(&grid_, plane, in.position, params_.movableWindow, params_.grid.robotRadius);
  if (markStuckSpot_) markDisc(&grid_, stuckSpot_, params_.stuckMarkRadius);
  markStuckSpot_ = false;
  path_ = planPath(grid_, in.position, target_, params_.planner);
  follower_.reset();
  bestRemaining_ = path_.found ? path_.length() : 1e18;
  noProgressTime_ = 0;
  out->events.replanned = true;
  stateSince_ = time_;
  if (path_.found) {
    state_ = NavState::Following;
  } else {
    state_ = NavState::NoPath;
    out->events.noPath = true;
  }
}

NavOutput Navigator::step(const engine::PlaneWorld& plane, const NavInput& in, double dt) {
  NavOutput out;
  time_ += dt;
  if (!hasTarget_) {
    state_ = NavState::Idle;
    out.state = state_;
    return out;
  }
  out.targetDistance = (target_ - in.position).norm();
  if (planPending_) {
    planPending_ = false;
    follower_.resetSkill(NavSkill::Walk);
    replan(plane, in, &out);
  }

  if (state_ == NavState::NoPath && elapsed(params_.retrySeconds)) replan(plane, in, &out);

  if (state_ == NavState::BackingOff) {
    // straight back, unless something is close behind the body
    const Eigen::Vector2d back(-std::cos(in.yaw), -std::sin(in.yaw));
    const engine::RayHit hit =
        plane.rayCast(in.position, in.position + (params_.grid.robotRadius + params_.backOffClearance) * back);
    const bool clearBehind = !hit.hit || engine::isStairTag(hit.tag);
    if (elapsed(params_.backOffSeconds) || !clearBehind) {
      replan(plane, in, &out);
    } else {
      out.command.vr = params_.backOffSpeed;
      out.command.skill = NavSkill::Walk;
      out.state = state_;
      return out;
    }
  }

  if (state_ == NavState::Following) {
    // the target reached
    if ((path_.points.back() - in.position).norm() <= params_.reachRadius) {
      out.events.reached = true;
      hasTarget_ = false;
      path_ = Path();
      state_ = NavState::Idle;
      stateSince_ = time_;
      out.state = state_;
      return out;
    }
    // a movable body on the path ahead, or the robot off its path: plan again
    const PathProgress at = projectOnPath(path_, in.position, follower_.segment());
    bool blockedNow = false;
    if (time_ - lastBlockReplan_ >= params_.replanCooldown - kTimeEpsilon) {
      // the disc checked is a little smaller than the robot's: a path replanned around the body passes cell centres
      // a full radius from it, and between them it may come closer by up to half a cell's diagonal
      const double cell = params_.grid.cellSize;
      const double blockedAt =
          firstBlockedArc(plane, path_, at.arc, params_.blockLookahead,
                          std::max(0.5 * params_.grid.robotRadius, params_.grid.robotRadius - 0.71 * cell), 0.5 * cell);
      if (blockedAt >= 0) {
        out.events.blocked = blockedNow = true;
        lastBlockReplan_ = time_;
        replan(plane, in, &out);
      }
    }
    if (state_ == NavState::Following && !blockedNow && at.offPath > params_.offPathDistance) replan(plane, in, &out);
  }

  if (state_ == NavState::Following) {
    out.command = follower_.follow(path_, plane, in.position, in.yaw, in.speed, &out.follow);
    // the stuck clock: runs while the robot is asked to move forward, stops on progress
    const double remaining = out.follow.remaining;
    if (remaining < bestRemaining_ - params_.stuckProgress) {
      bestRemaining_ = remaining;
      noProgressTime_ = 0;
    } else if (in.forward && !out.follow.turningInPlace && !out.follow.squaringUp) {
      noProgressTime_ += dt;
    }
    if (noProgressTime_ >= params_.stuckSeconds - kTimeEpsilon) {
      out.events.stuck = true;
      state_ = NavState::BackingOff;
      stateSince_ = time_;
      noProgressTime_ = 0;
      markStuckSpot_ = true;
      stuckSpot_ = in.position + params_.stuckMarkAhead * Eigen::Vector2d(std::cos(in.yaw), std::sin(in.yaw));
      out.command = NavCommand();
      out.command.vr = params_.backOffSpeed;
      follower_.resetSkill(NavSkill::Walk);
    }
  } else {
    out.command = NavCommand();  // NoPath: stand still
  }
  out.state = state_;
  return out;
}

}  // namespace game::nav
