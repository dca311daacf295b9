// plane_tags.h — what a body's tag in a level's 2D layer (engine::PlaneWorld) says about it, so that a reader of
// the layer (the garden's navigation, game/nav/) can tell a wall from a staircase or from something that moves,
// with ray casts and circle queries alone. Stand-alone: the level loader that fills the layer includes it too.
//
//   tag                          what it is                                    navigation treats it as
//   0 .. kStairTagBase-1         a static obstacle (the loader's box index)    a wall: never crossed
//   kStairTagBase + d, d 0..359  a staircase (one step column, or the whole    crossed only along its axis, the
//                                flight) climbing toward heading d degrees     heading d or d + 180 degrees
//                                (0 = +X, 90 = +Y, counter-clockwise)
//   kMovableTagBase + k, k >= 0  something that moves: a ball, a pushable      not in the map; a temporary obstacle
//   and every negative tag       box, a ghost (the course's ghosts use -1)     where it is seen, replanned around
//
// A level's straight staircase (levels::StairsDef, along +X) therefore tags each of its boxes kStairTagBase + 0.
// Tags kStairTagBase + 360 .. kMovableTagBase - 1 are reserved.
#pragma once

#include <cmath>

namespace engine {

constexpr int kStairTagBase = 1000000;
constexpr int kMovableTagBase = 2000000;

/// A static obstacle (wall, box): every tag below kStairTagBase that is not negative.
inline bool isWallTag(int tag) { return tag >= 0 && tag < kStairTagBase; }
/// A staircase: kStairTagBase + whole degrees of its climbing heading.
inline bool isStairTag(int tag) { return tag >= kStairTagBase && tag < kStairTagBase + 360; }
/// A movable obstacle: negative tags and kMovableTagBase and up.
inline bool isMovableTag(int tag) { return tag < 0 || tag >= kMovableTagBase; }

/// The tag of a staircase climbing toward `heading` [rad] (rounded to whole degrees, wrapped to 0..359).
inline int stairTag(double heading) {
  int degrees = static_cast<int>(std::lround(heading * 180.0 / M_PI)) % 360;
  if (degrees < 0) degrees += 360;
  return kStairTagBase + degrees;
}
/// A staircase tag's climbing heading [rad], 0 .. 2 pi.
inline double stairHeading(int tag) { return (tag - kStairTagBase) * M_PI / 180.0; }

}  // namespace engine
