// command.cpp — held-key bookkeeping, the interlocked velocity ramps and the amplitude ramp.
#include "engine/input/command.h"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace engine {
namespace {

constexpr std::string_view kLetterOrder = "WASDQERF";

// Differences this small count as "reached": absorbs the rounding of repeated additions, so a ramp of
// n steps of size r lands exactly on its target (e.g. 60 steps of 0.02 m/s reach exactly 1.2 m/s).
constexpr double kSnapEpsilon = 1e-9;

// Moves current toward target by at most maxDelta (maxDelta >= 0), landing exactly on target.
double moveTowards(double current, double target, double maxDelta) {
  const double diff = target - current;
  if (std::abs(diff) <= maxDelta + kSnapEpsilon) return target;
  return current + (diff > 0 ? maxDelta : -maxDelta);
}

// +1, -1 or 0 for a pair of opposing keys (both or neither held: 0).
int direction(uint32_t keys, char positive, char negative) {
  const bool p = (keys & keyMask(positive)) != 0;
  const bool n = (keys & keyMask(negative)) != 0;
  return p == n ? 0 : (p ? 1 : -1);
}

}  // namespace

uint32_t keyMask(char key) {
  if (key >= '0' && key <= '9') return 1u << (key - '0');
  const size_t i = kLetterOrder.find(key);
  return i == std::string_view::npos ? 0u : 1u << (10 + i);
}

std::string keysHeldString(const CommandState& state) {
  std::string s;
  const auto add = [&](char key) {
    if (!(state.keysHeld & keyMask(key))) return;
    if (!s.empty()) s += '+';
    s += key;
  };
  for (char key : kLetterOrder) add(key);
  for (char key = '0'; key <= '9'; ++key) add(key);
  return s;
}

CommandInput::CommandInput(CommandLimits limits) : limits_(limits) {}

void CommandInput::apply(const KeyEvent& event) {
  const uint32_t bit = keyMask(event.key);
  if (bit == 0) return;
  const bool isDigit = event.key >= '0' && event.key <= '9';
  switch (event.action) {
    case KeyAction::kDown:
      state_.keysHeld |= bit;
      tapped_ &= ~bit;  // a down after a tap in the same tick keeps the key held
      if (isDigit) state_.skillRequest = event.key - '0';
      break;
    case KeyAction::kUp:
      state_.keysHeld &= ~bit;
      tapped_ &= ~bit;
      break;
    case KeyAction::kTap:
      if (isDigit) state_.skillRequest = event.key - '0';
      if (!(state_.keysHeld & bit)) {
        state_.keysHeld |= bit;
        tapped_ |= bit;
      }
      break;
  }
}

void rampVelocityCommand(double targetVx, double targetVy, double targetWz, double vRate, double wzRate, double* vx,
                         double* vy, double* wz) {
  *vx = moveTowards(*vx, *vy == 0.0 && *wz == 0.0 ? targetVx : 0.0, vRate);
  *vy = moveTowards(*vy, *vx == 0.0 && *wz == 0.0 ? targetVy : 0.0, vRate);
  *wz = moveTowards(*wz, *vx == 0.0 && *vy == 0.0 ? targetWz : 0.0, wzRate);
}

void CommandInput::tick() {
  const uint32_t keys = state_.keysHeld;
  CommandState& s = state_;

  // Velocity axes in a fixed order; each sees the others as already updated this tick.
  const int forward = direction(keys, 'W', 'S'), side = direction(keys, 'Q', 'E'), turn = direction(keys, 'A', 'D');
  const bool canSteer = limits_.steerVx > 0.0 && limits_.steerWz > 0.0 && side == 0 && forward >= 0 && s.vy == 0.0;
  const bool steering = canSteer && forward > 0 && turn != 0;  // W with A or D
  const bool mixed = canSteer && s.vx > 0.0 && s.wz != 0.0;    // a steer under way
  if (steering || mixed) {
    s.vx = moveTowards(s.vx, steering ? limits_.steerVx : forward * limits_.vxForward, limits_.vRate);
    s.wz = moveTowards(s.wz, turn * (steering ? limits_.steerWz : limits_.wzMax), limits_.wzRate);
  } else {
    rampVelocityCommand(forward > 0   ? limits_.vxForward
                        : forward < 0 ? limits_.vxBackward
                                      : 0.0,
                        side * limits_.vyMax, turn * limits_.wzMax, limits_.vRate, limits_.wzRate, &s.vx, &s.vy, &s.wz);
  }

  // Amplitude: R raises, F lowers, kept in [0, 1].
  const int raise = direction(keys, 'R', 'F');
  if (raise != 0) s.amplitude = moveTowards(s.amplitude, raise > 0 ? 1.0 : 0.0, limits_.amplitudeRate);
  s.amplitude = std::clamp(s.amplitude, 0.0, 1.0);

  // Taps last exactly one tick.
  s.keysHeld &= ~tapped_;
  tapped_ = 0;
}

}  // namespace engine
