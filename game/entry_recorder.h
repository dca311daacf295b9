// entry_recorder.h — records play's handover states (robot/entry_state.h) as a run goes: every switch into a skill
// (a respawn's hand-over to the root excepted) opens an entry with the state after the skill's first control tick;
// the entry's segment collects the key events that follow and closes when the skill hands over, the robot falls,
// the run ends or robot::kSegmentCapTicks pass.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/input/key_script.h"
#include "robot/entry_state.h"

namespace game {

class Session;

class EntryRecorder {
 public:
  /// level: the level as play was given it (levels/mario); source: "autopilot" or the key script's file name.
  EntryRecorder(std::string level, std::string source, uint64_t seed)
      : level_(std::move(level)), source_(std::move(source)), seed_(seed) {}
  /// After each Session::step, with the key events that tick applied.
  void afterTick(const Session& session, const std::vector<engine::KeyEvent>& events);
  /// Closes the open segment (the run ended).
  void finish(const Session& session);
  const std::vector<robot::EntryState>& entries() const { return entries_; }

 private:
  void close(int64_t tick, bool fell);
  std::string level_, source_;
  uint64_t seed_ = 0;
  std::vector<robot::EntryState> entries_;
  bool open_ = false;
  size_t switchesSeen_ = 0;
  int fallsAtOpen_ = 0;
};

}  // namespace game
