// input_timeline.h — hands a recorded or scripted list of key events to the game loop tick by tick.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/input/key_script.h"

namespace engine {

/// A cursor over key events sorted by tick (ties keep their given order).
class InputTimeline {
 public:
  /// Takes the events; sorts them by tick if they are not already (stable, so file order is kept).
  explicit InputTimeline(std::vector<KeyEvent> events);

  /// Returns and consumes the events not yet returned whose tick is <= `tick`, in order. Called once per
  /// tick with consecutive ticks this is exactly the events whose tick == `tick`; an event whose tick was
  /// skipped is delivered late rather than lost. O(1) amortised per event.
  std::vector<KeyEvent> eventsAt(int64_t tick);

  /// True when every event has been returned.
  bool done() const { return next_ >= events_.size(); }

  /// Number of events not yet returned.
  size_t remaining() const { return events_.size() - next_; }

 private:
  std::vector<KeyEvent> events_;
  size_t next_ = 0;  // index of the first event not yet returned
};

}  // namespace engine
