// held_keys.h — the movement keys a pilot (the Mario autopilot, the garden pilot) holds down, and the key events that
// change them: a press only for a key not held, a release only for one held, so a recorded run replays exactly.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/input/key_script.h"

namespace game {

class HeldKeys {
 public:
  /// Presses (down) or releases `key` at `tick`, adding the event to *out unless it is already so.
  void hold(int64_t tick, char key, bool down, std::vector<engine::KeyEvent>* out) {
    const size_t at = keys_.find(key);
    if (down == (at != std::string::npos)) return;
    out->push_back({tick, down ? engine::KeyAction::kDown : engine::KeyAction::kUp, key});
    if (down)
      keys_ += key;
    else
      keys_.erase(at, 1);
  }
  /// Releases every held key, the last pressed first.
  void releaseAll(int64_t tick, std::vector<engine::KeyEvent>* out) {
    while (!keys_.empty()) hold(tick, keys_.back(), false, out);
  }
  bool empty() const { return keys_.empty(); }
  bool holds(char key) const { return keys_.find(key) != std::string::npos; }

 private:
  std::string keys_;  // in the order pressed
};

}  // namespace game
