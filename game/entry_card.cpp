// entry_card.cpp — see entry_card.h.
#include "game/entry_card.h"

#include <cstdio>
#include <map>
#include <memory>

#include "engine/core/file_io.h"
#include "engine/core/worker_pool.h"
#include "engine/input/input_timeline.h"
#include "game/session.h"
#include "levels/level.h"

namespace game {

int EntryCardResult::held() const {
  int n = 0;
  for (const EntryTrial& t : trials) n += t.fell ? 0 : 1;
  return n;
}

double EntryCardResult::percent() const { return trials.empty() ? 0.0 : 100.0 * held() / double(trials.size()); }

EntryCardResult runEntryCard(const std::vector<robot::EntryState>& entries, const std::string& skill,
                             const robot::SkillSet& skills, const robot::RobotModel& model, int threads) {
  std::vector<const robot::EntryState*> mine;
  std::map<std::string, std::unique_ptr<levels::Level>> levelsByPath;
  for (const robot::EntryState& e : entries) {
    if (e.skill != skill) continue;
    mine.push_back(&e);
    std::unique_ptr<levels::Level>& level = levelsByPath[e.level];
    if (!level) {
      level = std::make_unique<levels::Level>(levels::loadLevel(engine::projectFile(e.level)));
      level->ghosts.clear();
      level->rules = levels::RulesDef{};
      level->timeLimit = 0;
    }
  }
  EntryCardResult result;
  result.skill = skill;
  result.trials.resize(mine.size());
  engine::WorkerPool pool(threads);
  pool.parallelFor(int(mine.size()), [&](int i) {
    const robot::EntryState& e = *mine[size_t(i)];
    Session session(*levelsByPath.at(e.level), model, SessionOptions{e.seed, &skills});
    session.restoreEntry(e);
    EntryTrial& trial = result.trials[size_t(i)];
    engine::InputTimeline keys(e.events);
    const int64_t end = e.tick + e.segmentTicks + kEntryCardMarginTicks;
    while (session.tick() <= end) {
      session.step(keys.eventsAt(session.tick()));
      if (session.telemetry().falls > 0) {
        trial.fell = true;
        break;
      }
      if (session.activeSkillName() != skill) {
        trial.handedOver = true;
        break;
      }
      ++trial.ticks;
    }
  });
  for (const robot::EntryState* e : mine) result.fellInPlay += e->fellInPlay ? 1 : 0;
  return result;
}

std::string entryCardLine(const EntryCardResult& r) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "held %d of %d play entries (%.1f %%); in play %d of them fell", r.held(),
                int(r.trials.size()), r.percent(), r.fellInPlay);
  return buf;
}

}  // namespace game
