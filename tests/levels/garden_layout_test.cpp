// garden_layout_test.cpp — random garden layouts (levels/garden_layout.h): they load, keep the river, the bridge and
// the short staircase clear and their houses apart, have one narrow alley, and are the same for the same seed.
#include "levels/garden_layout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "levels/level.h"

namespace {

using R = levels::GardenRanges;

// the gap between two rectangles (0 when they touch or overlap)
double gap(const levels::GroundRect& a, const levels::GroundRect& b) {
  const double dx = std::max({0.0, a.x0 - b.x1, b.x0 - a.x1}), dy = std::max({0.0, a.y0 - b.y1, b.y0 - a.y1});
  return std::hypot(dx, dy);
}

}  // namespace

TEST(GardenLayout, TheSameSeedGivesTheSameFileAndAnotherSeedAnother) {
  EXPECT_EQ(levels::gardenLayoutToml(levels::drawGardenLayout(5)),
            levels::gardenLayoutToml(levels::drawGardenLayout(5)));
  EXPECT_NE(levels::gardenLayoutToml(levels::drawGardenLayout(5)),
            levels::gardenLayoutToml(levels::drawGardenLayout(6)));
}

TEST(GardenLayout, EveryLayoutLoadsWithItsRiverBridgeAndStaircaseClearOfHousesThatKeepTheirStreets) {
  for (uint64_t seed = 1; seed <= 100; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const levels::GardenLayout g = levels::drawGardenLayout(seed);
    const levels::Level l = levels::parseLevel(levels::gardenLayoutToml(g), "layout.toml");
    // the bridge's 8 risers up (the top one with its deck) and 7 down, the short staircase's 3 and 2
    EXPECT_EQ(std::count_if(l.boxes.begin(), l.boxes.end(), [](const levels::BoxDef& b) { return b.stairs; }), 20);
    EXPECT_EQ(l.balls.size(), 3u);
    EXPECT_GE(g.riverX, R::kRiverXMin);
    EXPECT_LE(g.riverX, R::kRiverXMax);
    EXPECT_GE(g.bridgeY, R::kBridgeYMin);
    EXPECT_LE(g.bridgeY, R::kBridgeYMax);
    ASSERT_GE(g.houses.size(), 4u);
    // the alley's pair: side by side, 1.1-1.2 m apart
    EXPECT_GE(gap(g.houses[0], g.houses[1]), R::kAlleyMin - 1e-9);
    EXPECT_LE(gap(g.houses[0], g.houses[1]), R::kAlleyMax + 1e-9);
    const levels::GroundRect river{g.riverX, 0.0, g.riverX + R::kRiverWidth, g.riverTop};
    // the bridge from 1.7 m west of the river, 6.25 m long, and its run-ups
    const levels::GroundRect bridge{g.riverX - 1.7 - 5.0, g.bridgeY - 1.0, g.riverX - 1.7 + 6.25 + 4.0,
                                    g.bridgeY + 1.0};
    const levels::GroundRect steps{g.flightStart.x() - 2.0, g.flightStart.y() - 1.0, g.flightStart.x() + 4.0 + 2.0,
                                   g.flightStart.y() + 1.0};
    for (size_t i = 0; i < g.houses.size(); ++i) {
      const levels::GroundRect& h = g.houses[i];
      EXPECT_GE(std::min({h.x0, h.y0, R::kSize - h.x1, R::kSize - h.y1}), R::kWallGap - 1e-9);
      EXPECT_GE(gap(h, river), 1.2 - 1e-9);
      EXPECT_GT(gap(h, bridge), 0.0);
      EXPECT_GT(gap(h, steps), 0.0);
      for (size_t j = i + 1; j < g.houses.size(); ++j) {
        if (i == 0 && j == 1) continue;  // the alley's pair
        EXPECT_GE(gap(h, g.houses[j]), R::kStreet - 1e-9) << i << " and " << j;
      }
    }
  }
}
