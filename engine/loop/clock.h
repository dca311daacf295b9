// clock.h — the one control tick length (0.01 s, 100 Hz, the paper's fixed step) and the
// seconds-to-ticks conversion every time-based input (key scripts, level timers) goes through.
#pragma once

#include <cmath>
#include <cstdint>

namespace engine {

/// Length of one control tick (s): 100 Hz.
constexpr double kTickSeconds = 0.01;

/// Nearest whole tick for a time in seconds: llround(s / kTickSeconds). s must be finite and small
/// enough for the result to fit in int64_t (callers validate user input first).
inline int64_t secondsToTicks(double s) { return std::llround(s / kTickSeconds); }

}  // namespace engine
