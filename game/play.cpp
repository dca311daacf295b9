// play.cpp — the fixed-tick loop: one clock (the session's tick), events delivered on their tick.
#include "game/play.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "engine/input/input_timeline.h"
#include "engine/loop/clock.h"
#include "game/autopilot.h"
#include "game/garden_pilot.h"

namespace game {

PlayResult play(const levels::Level& level, const robot::RobotModel& model, const PlayOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Session session(level, model, SessionOptions{options.seed, options.skills});
  engine::InputTimeline timeline(options.events);
  PlayResult result;
  size_t nextExpected = 0;

  if (options.frameEvery > 0 && options.onFrame) options.onFrame(session.snapshot(options.camera));
  Autopilot autopilot(options.skills ? skillKeys(*options.skills) : SkillKeys{});
  std::unique_ptr<GardenPilot> garden;
  if (options.autopilot && isMapLevel(level)) {
    // W with A or D steers a skill that has forward_turn
    auto steers = [&](const char* name) {
      const robot::Skill* skill = options.skills ? options.skills->byName(name) : nullptr;
      return skill && skill->def.commands.steerWz > 0;
    };
    GardenKeyParams keyParams;
    keyParams.steer = steers("walk");
    keyParams.steerStairs = steers("stairs");
    garden =
        std::make_unique<GardenPilot>(session.plane(), options.skills ? skillKeys(*options.skills) : SkillKeys{},
                                      options.seed, options.targets, GardenPilot::gardenNavigatorParams(), keyParams);
  }
  std::string gardenEvents;  // since the last 50 Hz sample
  std::vector<double> comX;  // per tick, for the switch reports
  while (session.tick() < options.ticks) {
    std::vector<engine::KeyEvent> events = timeline.eventsAt(session.tick());
    if (garden) {
      const std::vector<engine::KeyEvent> own = garden->decide(session.tick(), session);
      events.insert(events.end(), own.begin(), own.end());
      const std::string& e = garden->last().events;
      if (!e.empty()) gardenEvents += (gardenEvents.empty() ? "" : "+") + e;
    } else if (options.autopilot) {
      const std::vector<engine::KeyEvent> own = autopilot.decide(session.tick(), senseCues(session));
      events.insert(events.end(), own.begin(), own.end());
    }
    const Eigen::Vector3d before = session.sensors().basePosition;
    result.keyEvents.insert(result.keyEvents.end(), events.begin(), events.end());
    session.step(events);
    if (options.entries) options.entries->afterTick(session, events);
    const int64_t done = session.tick();  // ticks completed
    if (garden) {
      const robot::Sensors& sensed = session.sensors();
      GardenSkillStats& st = result.garden.skills[session.activeSkillName()];
      ++st.ticks;
      st.distance += (sensed.basePosition - before).head<2>().norm();
      st.maxRoll = std::max(st.maxRoll, std::abs(sensed.roll));
      st.maxPitch = std::max(st.maxPitch, std::abs(sensed.pitch));
      if (session.fallen() && gardenEvents.find("fell") == std::string::npos)
        gardenEvents += (gardenEvents.empty() ? "" : "+") + std::string("fell");
      if (done % 2 == 0) {
        const GardenTick& g = garden->last();
        GardenSample m;
        m.t = double(done) * engine::kTickSeconds;
        m.x = sensed.basePosition.x(), m.y = sensed.basePosition.y(), m.z = sensed.basePosition.z();
        const Eigen::Vector3d v = sensed.baseRotation * sensed.linearVelocity;
        m.vx = v.x(), m.vy = v.y();
        m.vr = session.command().vx, m.wr = session.command().wz;
        m.navVr = g.navVr, m.navWr = g.navWr;
        m.target = g.target, m.targetDistance = g.targetDistance, m.targetAngle = g.targetAngle;
        m.obstacleFactor = g.obstacleFactor;
        m.skill = session.activeSkillName();
        m.roll = sensed.roll, m.pitch = sensed.pitch, m.yaw = sensed.yaw;
        m.mode = GardenKeys::modeName(g.mode);
        m.events = gardenEvents;
        gardenEvents.clear();
        result.garden.samples.push_back(std::move(m));
      }
    }
    const Eigen::Vector3d com = session.sensors().centreOfMass;
    comX.push_back(com.x());
    if (done % 2 == 0) {
      const double vx = comX.size() > 2 ? (comX.back() - comX[comX.size() - 3]) / (2 * engine::kTickSeconds) : 0.0;
      const robot::Sensors& sensed = session.sensors();
      const Eigen::Vector2d feet = 0.5 * (sensed.footPosition[0] + sensed.footPosition[1]).head<2>();
      const double left = (com.head<2>() - feet).dot(Eigen::Vector2d(-std::sin(sensed.yaw), std::cos(sensed.yaw)));
      result.comLog.push_back({double(done) * engine::kTickSeconds, com.x(), com.z(), vx, session.activeSkillName(),
                               com.y(), sensed.yaw, left});
    }

    if (options.hashEvery > 0 && done % options.hashEvery == 0) {
      const engine::StateHash h{done, session.stateHash()};
      result.hashes.push_back(h);
      if (options.expected) {
        while (nextExpected < options.expected->size() && (*options.expected)[nextExpected].tick < done) ++nextExpected;
        if (nextExpected < options.expected->size() && (*options.expected)[nextExpected].tick == done &&
            (*options.expected)[nextExpected].hash != h.hash) {
          result.divergedTick = done;
          break;
        }
      }
    }
    if (options.frameEvery > 0 && options.onFrame && done % options.frameEvery == 0)
      options.onFrame(session.snapshot(options.camera));
    if ((options.stopOnFall || garden) && session.fallen()) break;  // nothing puts a robot back up in a map
    if (session.outcome() != Outcome::Playing) break;
  }
  if (garden) {
    const GardenTally& t = garden->tally();
    result.garden.played = true;
    result.garden.targetsGiven = t.given, result.garden.targetsReached = t.reached, result.garden.stuck = t.stuck;
    result.garden.noPath = t.noPath, result.garden.replans = t.replans;
    result.garden.targets = t.targets;
  }
  if (options.entries) options.entries->finish(session);
  result.ticks = session.tick();
  result.fallen = session.fallen();
  result.fallTick = session.fallTick();
  result.finalHash = session.stateHash();
  result.telemetry = session.telemetry();
  result.finalSensors = session.sensors();
  if (const Course* c = session.course()) {
    result.outcome = c->outcome();
    result.outcomeReason = c->outcomeReason();
    result.score = c->score();
    result.coins = c->coins();
    result.gifts = c->gifts();
    result.events = c->events();
  }
  // switch continuity: the forward speed of the centre of mass, smoothed over 0.1 s (10 ticks)
  const int64_t n = int64_t(comX.size());
  std::vector<double> speed(size_t(n), 0.0);
  for (int64_t i = 10; i < n; ++i)
    speed[size_t(i)] = (comX[size_t(i)] - comX[size_t(i - 10)]) / (10 * engine::kTickSeconds);
  auto mean = [&](int64_t a, int64_t b) {
    a = std::clamp<int64_t>(a, 0, n), b = std::clamp<int64_t>(b, 0, n);
    double s = 0;
    for (int64_t i = a; i < b; ++i) s += speed[size_t(i)];
    return b > a ? s / double(b - a) : 0.0;
  };
  const std::vector<SwitchEvent>& sw = result.telemetry.switches;
  const std::vector<int64_t>& respawns = result.telemetry.respawns;
  for (size_t k = 0; k < sw.size(); ++k) {
    if (sw[k].from == "stand") continue;
    const int64_t t = sw[k].tick;
    // a respawn's hand-over to the root is no switch in motion; and no window reaches across a respawn's teleport
    // (made in tick r: comX[r] is the new place, so the smoothed speeds r .. r + 9 span it, and the acceleration
    // at r + 10 takes the one before)
    if (sw[k].respawn) continue;
    int64_t first = t - 50, last = t + 300;
    for (int64_t r : respawns) {
      if (r < t)
        first = std::max(first, r + 11);
      else
        last = std::min(last, r);
    }
    SwitchReport rep;
    rep.event = sw[k];
    const int64_t next = std::min(last, k + 1 < sw.size() ? sw[k + 1].tick : n);
    rep.speedBefore = mean(first, t);
    rep.speedAfter = mean(std::min(t + 200, next - 100), std::min(t + 300, next));
    for (int64_t i = std::max<int64_t>(first, 11); i < std::min(last, n); ++i)
      rep.peakAcceleration =
          std::max(rep.peakAcceleration, std::abs(speed[size_t(i)] - speed[size_t(i - 1)]) / engine::kTickSeconds);
    result.switchReports.push_back(rep);
  }
  result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

bool isMapLevel(const levels::Level& level) { return level.plane == levels::Plane2d::Top && !level.isGame(); }

}  // namespace game
