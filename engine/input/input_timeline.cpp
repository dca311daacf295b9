// input_timeline.cpp — the cursor behind InputTimeline.
#include "engine/input/input_timeline.h"

#include <algorithm>
#include <utility>

namespace engine {

InputTimeline::InputTimeline(std::vector<KeyEvent> events) : events_(std::move(events)) {
  const auto byTick = [](const KeyEvent& a, const KeyEvent& b) { return a.tick < b.tick; };
  if (!std::is_sorted(events_.begin(), events_.end(), byTick)) {
    std::stable_sort(events_.begin(), events_.end(), byTick);
  }
}

std::vector<KeyEvent> InputTimeline::eventsAt(int64_t tick) {
  std::vector<KeyEvent> out;
  while (next_ < events_.size() && events_[next_].tick <= tick) out.push_back(events_[next_++]);
  return out;
}

}  // namespace engine
