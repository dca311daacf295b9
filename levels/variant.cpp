// variant.cpp — see variant.h. The layout is levels/mario's, stage by stage along +X; what follows a drawn
// stage is placed from where that stage ends, with the gaps levels/mario has (the autopilot lies down 1.8 m before
// a tunnel and stands up 1.2 m past it; the kick lines up from 2 m before the ball).
#include "levels/variant.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "engine/core/error.h"

namespace levels {
namespace {

// levels/mario's fixed geometry [m]
constexpr double kBackWallX = -2.5;                                       // behind the spawn (x = 0)
constexpr double kWallY = 1.05, kWallThickness = 0.1, kWallHeight = 2.0;  // the side walls: inner faces at +-1.0
constexpr double kInnerHalfWidth = kWallY - 0.5 * kWallThickness;
constexpr double kWallsBefore = 0.5, kWallsPast = 1.9;  // the side walls reach this far past the back and end walls
constexpr double kStartCoins[] = {2.0, 3.0, 4.0, 9.0, 12.0};  // the flat start, at chest height
constexpr double kCoinHeight = 0.9;
constexpr double kFirstCheckpoint = 15.0;
constexpr double kStairsStart = 17.0, kLanding = 1.0, kCourseWidth = 2.0;
constexpr double kGhostVanishBeforeStairs = 1.0;  // the ghost gives up at the stairs
constexpr double kCheckpointPastStairs = 0.4;     // kStandHalfFootprint and 0.1 m
constexpr double kTunnelPastStairs = 2.4;
constexpr double kTunnelCoinHeight = 0.3;  // under the lowest roof (0.55 m) with its 0.15 m radius
constexpr double kCheckpointPastTunnel = 1.5;
constexpr double kCheckpointPastBoxes = 1.5;
constexpr double kBallPastBoxes = 3.5;
constexpr double kGoalPastBall = 4.5;
constexpr double kEndWallPastGoal = 0.6;  // behind the goal, as a net

// a double in [0, 1) from the generator's top 53 bits: the same on every platform
double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }
double mm(double v) { return std::round(v * 1000.0) / 1000.0; }
// uniform in [lo, hi], rounded to millimetres (lo and hi are whole millimetres, so the rounding stays inside)
double draw(std::mt19937_64& rng, double lo, double hi) { return mm(lo + (hi - lo) * unit(rng)); }

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

}  // namespace

MarioVariant drawMarioVariant(uint64_t seed, int questionBoxes) {
  using R = VariantRanges;
  std::mt19937_64 rng(seed);
  MarioVariant v;
  v.seed = seed;
  // the draws in a fixed order, every one of them for every seed (a value unused by one variant still advances
  // the stream, so each draw means the same thing at every seed)
  v.steps = std::min(R::kStepsMax, R::kStepsMin + int(unit(rng) * (R::kStepsMax - R::kStepsMin + 1)));
  v.rise = draw(rng, R::kRiseMin, R::kRiseMax);
  v.tread = draw(rng, R::kTreadMin, R::kTreadMax);
  v.tunnelLength = draw(rng, R::kTunnelLengthMin, R::kTunnelLengthMax);
  v.clearance = draw(rng, R::kClearanceMin, R::kClearanceMax);
  // k boxes at least kBoxGap apart in [kBoxesFrom, kBoxesTo]: k points in the span less the gaps, sorted, then
  // each spread out by the gaps before it
  const int k = std::max(0, questionBoxes);
  const double room = std::max(0.0, R::kBoxesTo - R::kBoxesFrom - std::max(0, k - 1) * R::kBoxGap);
  for (int i = 0; i < k; ++i) v.boxesPastTunnel.push_back(draw(rng, 0.0, room));
  std::sort(v.boxesPastTunnel.begin(), v.boxesPastTunnel.end());
  for (int i = 0; i < k; ++i)
    v.boxesPastTunnel[size_t(i)] = mm(v.boxesPastTunnel[size_t(i)] + R::kBoxesFrom + i * R::kBoxGap);
  const int side = std::min(2, int(unit(rng) * 3));
  v.ballSide = side == 0 ? BallSide::Left : side == 1 ? BallSide::Middle : BallSide::Right;
  v.ballFromWall = draw(rng, R::kBallFromWallMin, R::kBallFromWallMax);
  v.ghostMaxSpeed = draw(rng, R::kGhostMaxSpeedMin, R::kGhostMaxSpeedMax);
  return v;
}

std::string marioVariantToml(const Level& base, const MarioVariant& v) {
  if (!base.isGame() || base.ghosts.size() != 1 || base.balls.size() != 1 || base.goals.size() != 1 ||
      base.questionBoxes.empty())
    throw engine::Error(base.path +
                        ": a variant needs a Mario-style course: a game level with one ghost, one ball, "
                        "one goal and at least one question box (levels/mario)");
  using R = VariantRanges;
  const int fit = 1 + int((R::kBoxesTo - R::kBoxesFrom) / R::kBoxGap);
  if (int(base.questionBoxes.size()) > fit)
    throw engine::Error(base.path + ": a variant has room for " + std::to_string(fit) + " question boxes " +
                        std::to_string(R::kBoxGap).substr(0, 3) + " m apart past the tunnel, the level has " +
                        std::to_string(base.questionBoxes.size()));
  if (v.boxesPastTunnel.size() != base.questionBoxes.size())
    throw engine::Error(base.path + ": the variant was drawn for " + std::to_string(v.boxesPastTunnel.size()) +
                        " question boxes, the level has " + std::to_string(base.questionBoxes.size()));
  // the stages' x, each from the one before
  const double stairsEnd = kStairsStart + 2 * (v.steps - 1) * v.tread + kLanding;
  const double tunnelStart = stairsEnd + kTunnelPastStairs;
  const double tunnelEnd = tunnelStart + v.tunnelLength;
  std::vector<double> boxX;
  for (double d : v.boxesPastTunnel) boxX.push_back(tunnelEnd + d);
  const double lastBox = boxX.back();
  const double ballX = lastBox + kBallPastBoxes;
  const double ballY = v.ballSide == BallSide::Middle ? 0.0
                       : v.ballSide == BallSide::Left ? kInnerHalfWidth - v.ballFromWall
                                                      : -(kInnerHalfWidth - v.ballFromWall);
  const double goalX = ballX + kGoalPastBall;
  const double endWallX = goalX + kEndWallPastGoal;
  const std::vector<double> checkpoints = {kFirstCheckpoint, stairsEnd + kCheckpointPastStairs,
                                           tunnelEnd + kCheckpointPastTunnel, lastBox + kCheckpointPastBoxes};

  const RulesDef& rules = base.rules;
  const GhostDef& ghost = base.ghosts.front();
  const BallSpawnDef& ball = base.balls.front();
  const GoalDef& goal = base.goals.front();
  std::string t;
  auto line = [&](const std::string& s) { t += s + "\n"; };
  auto vec = [&](std::initializer_list<double> xs) {
    std::string s = "[";
    for (double x : xs) s += (s.size() > 1 ? ", " : "") + num(x);
    return s + "]";
  };
  line("# A variant of " + base.path + " (seed " + std::to_string(v.seed) + "), written by `treelearn variant`:");
  line("# " + describeVariant(v) + ".");
  line("# The ranges and the layout: levels/variant.h. Format: levels/README.md.");
  line("name = \"" + base.name + "-variant-" + std::to_string(v.seed) + "\"");
  line("description = \"" + base.name + " with its geometry drawn from seed " + std::to_string(v.seed) + "\"");
  line("plane = \"side\"");
  line("time_limit = " + num(base.timeLimit));
  line("");
  line("[spawn]");
  line("position = [0.000, 0.000]");
  line("yaw = 0.000");
  line("");
  line("[rules]");
  line(std::string("falls = \"") + (rules.falls == FallRule::Lose ? "lose" : "respawn") + "\"");
  line("fall_penalty = " + std::to_string(rules.fallPenalty));
  line("coin_value = " + std::to_string(rules.coinValue));
  line("gift_value = " + std::to_string(rules.giftValue));
  line("win_bonus = " + std::to_string(rules.winBonus));
  std::string cps = "checkpoints = [";
  for (size_t i = 0; i < checkpoints.size(); ++i) cps += (i ? ", " : "") + num(checkpoints[i]);
  line(cps + "]");

  const double wallsFrom = kBackWallX - kWallsBefore, wallsTo = endWallX + kWallsPast;
  for (const char* side : {"left", "right"}) {
    line("");
    line("[[wall]]");
    line(std::string("name = \"wall_") + side + "\"");
    line("centre = " + vec({0.5 * (wallsFrom + wallsTo), side[0] == 'l' ? kWallY : -kWallY, 0.5 * kWallHeight}));
    line("size = " + vec({wallsTo - wallsFrom, kWallThickness, kWallHeight}));
  }
  line("");
  line("[[wall]]");
  line("name = \"wall_back\"");
  line("centre = " + vec({kBackWallX, 0.0, 0.5 * kWallHeight}));
  line("size = " + vec({kWallThickness, 2 * kInnerHalfWidth, kWallHeight}));
  line("");
  line("[[wall]]");
  line("name = \"wall_end\"");
  line("centre = " + vec({endWallX, 0.0, 0.5 * kWallHeight}));
  line("size = " + vec({kWallThickness, 2 * kInnerHalfWidth, kWallHeight}));

  auto coin = [&](double x, double z) {
    line("");
    line("[[coin]]");
    line("centre = " + vec({x, 0.0, z}));
  };
  for (double x : kStartCoins) coin(x, kCoinHeight);

  line("");
  line("[[ghost]]");
  line("appear_x = " + num(ghost.appearX));
  line("behind = " + num(ghost.behind));
  line("height = " + num(ghost.height));
  line("radius = " + num(ghost.radius));
  line("speed = " + num(ghost.speed));
  line("acceleration = " + num(ghost.acceleration));
  line("max_speed = " + num(v.ghostMaxSpeed));
  line("catch_distance = " + num(ghost.catchDistance));
  line("vanish_x = " + num(kStairsStart - kGhostVanishBeforeStairs));

  line("");
  line("[[stairs]]");
  line("name = \"stairs\"");
  line("start = " + vec({kStairsStart, 0.0}));
  line("steps = " + std::to_string(v.steps));
  line("rise = " + num(v.rise));
  line("run = " + num(v.tread));
  line("width = " + num(kCourseWidth));
  line("top = " + num(kLanding));
  line("down = true");
  coin(kStairsStart + (v.steps - 1) * v.tread + 0.5 * kLanding, v.steps * v.rise + kCoinHeight);  // over the landing

  line("");
  line("[[tunnel]]");
  line("name = \"tunnel\"");
  line("start = " + num(tunnelStart));
  line("length = " + num(v.tunnelLength));
  line("clearance = " + num(v.clearance));
  line("width = " + num(kCourseWidth));
  coin(tunnelStart + 0.5 * v.tunnelLength, kTunnelCoinHeight);

  for (size_t i = 0; i < boxX.size(); ++i) {
    const QuestionBoxDef& q = base.questionBoxes[i];
    line("");
    line("[[question_box]]");
    line("centre = " + vec({boxX[i], 0.0, q.centre.z()}));
    line("size = " + vec({q.size.x(), q.size.y(), q.size.z()}));
    line(std::string("content = \"") + (q.gift ? "gift" : "coin") + "\"");
  }

  line("");
  line("[[ball]]");
  line("position = " + vec({ballX, ballY}));
  line("radius = " + num(ball.radius));
  line("mass = " + num(ball.mass));
  line("");
  line("[[goal]]");
  line("centre = " + vec({goalX, 0.0, goal.centre.z()}));
  line("size = " + vec({goal.size.x(), goal.size.y(), goal.size.z()}));

  parseLevel(t, base.path + " (variant " + std::to_string(v.seed) + ")");  // a variant always loads: throws if not
  return t;
}

std::string describeVariant(const MarioVariant& v) {
  char buf[320];
  std::string boxes;
  for (double d : v.boxesPastTunnel) boxes += (boxes.empty() ? "" : ", ") + num(d);
  const char* side = v.ballSide == BallSide::Left    ? "from the left wall"
                     : v.ballSide == BallSide::Right ? "from the right wall"
                                                     : "";
  std::snprintf(buf, sizeof buf,
                "%d steps %.3f m up on %.3f m treads, tunnel %.3f m long at %.3f m, question boxes %s m past it, "
                "ball %s%s, ghost up to %.3f m/s",
                v.steps, v.rise, v.tread, v.tunnelLength, v.clearance, boxes.c_str(),
                v.ballSide == BallSide::Middle ? "in the middle" : (num(v.ballFromWall) + " m ").c_str(), side,
                v.ghostMaxSpeed);
  return buf;
}

}  // namespace levels
