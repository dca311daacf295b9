// entry_recorder.cpp — see entry_recorder.h.
#include "game/entry_recorder.h"

#include <algorithm>

#include "game/session.h"

namespace game {

void EntryRecorder::close(int64_t tick, bool fell) {
  robot::EntryState& e = entries_.back();
  e.segmentTicks = std::min(tick - e.tick, robot::kSegmentCapTicks);
  e.fellInPlay = fell;
  open_ = false;
}

void EntryRecorder::afterTick(const Session& session, const std::vector<engine::KeyEvent>& events) {
  const int64_t tick = session.tick() - 1;  // the tick just stepped
  const Telemetry& t = session.telemetry();
  if (open_) {
    robot::EntryState& e = entries_.back();
    for (const engine::KeyEvent& ev : events)
      if (ev.tick > e.tick) e.events.push_back(ev);
    if (t.falls > fallsAtOpen_)
      close(tick, true);
    else if (t.switches.size() > switchesSeen_ || tick - e.tick >= robot::kSegmentCapTicks)
      close(tick, false);
  }
  if (t.switches.size() > switchesSeen_) {
    const SwitchEvent& s = t.switches.back();
    switchesSeen_ = t.switches.size();
    if (!s.respawn && s.tick == tick && session.runtime().active) {
      robot::EntryState e = session.captureEntry();
      e.level = level_, e.source = source_, e.seed = seed_;
      entries_.push_back(std::move(e));
      open_ = true;
      fallsAtOpen_ = t.falls;
    }
  }
}

void EntryRecorder::finish(const Session& session) {
  if (open_) close(session.tick() - 1, false);
}

}  // namespace game
