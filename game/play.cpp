// play.cpp — the fixed-tick loop: one clock (the session's tick), events delivered on their tick.
#include "game/play.h"

#include <chrono>

#include "engine/input/input_timeline.h"
#include "game/autopilot.h"

namespace game {

PlayResult play(const levels::Level& level, const robot::RobotModel& model, const PlayOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Session session(level, model, SessionOptions{options.seed, options.skills});
  engine::InputTimeline timeline(options.events);
  PlayResult result;
  size_t nextExpected = 0;

  if (options.frameEvery > 0 && options.onFrame) options.onFrame(session.snapshot(options.camera));
  Autopilot autopilot;
  while (session.tick() < options.ticks) {
    std::vector<engine::KeyEvent> events = timeline.eventsAt(session.tick());
    if (options.autopilot) {
      const std::vector<engine::KeyEvent> own = autopilot.decide(session.tick(), senseCues(session));
      events.insert(events.end(), own.begin(), own.end());
    }
    result.keyEvents.insert(result.keyEvents.end(), events.begin(), events.end());
    session.step(events);
    const int64_t done = session.tick();  // ticks completed

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
    if (options.stopOnFall && session.fallen()) break;
    if (session.outcome() != Outcome::Playing) break;
  }
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
  result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace game
