// terrain_test.cpp — one episode's staircase: the terrain as written, or drawn from its ranges.
#include "ai/env/terrain.h"

#include <gtest/gtest.h>

TEST(Terrain, ADrawnStaircaseSpansItsRangesWithBothEndsOfTheSteps) {
  ai::TerrainDef t;
  t.kind = ai::TerrainDef::Kind::Stairs;
  t.steps = 10, t.stepDepth = 0.30;
  const ai::Staircase written = ai::drawStaircase(t, ai::StairsDraw{}, 0.12, 0.5, 0.5, 0.5);
  EXPECT_EQ(written.terrain.steps, 10);
  EXPECT_DOUBLE_EQ(written.terrain.stepDepth, 0.30);
  EXPECT_DOUBLE_EQ(written.rise, 0.12);  // the lesson's
  const ai::StairsDraw d{{0.08, 0.15}, {0.28, 0.60}, {3, 6}};
  const ai::Staircase low = ai::drawStaircase(t, d, 0.12, 0.0, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(low.rise, 0.08);
  EXPECT_DOUBLE_EQ(low.terrain.stepDepth, 0.28);
  EXPECT_EQ(low.terrain.steps, 3);
  const ai::Staircase high = ai::drawStaircase(t, d, 0.12, 0.999999, 0.999999, 0.999999);
  EXPECT_NEAR(high.rise, 0.15, 1e-6);
  EXPECT_NEAR(high.terrain.stepDepth, 0.60, 1e-6);
  EXPECT_EQ(high.terrain.steps, 6);  // four counts (3, 4, 5, 6), each a quarter of [0, 1)
  EXPECT_EQ(ai::drawStaircase(t, d, 0.12, 0, 0, 0.26).terrain.steps, 4);
  EXPECT_EQ(ai::drawStaircase(t, d, 0.12, 0, 0, 0.74).terrain.steps, 5);
  // the far end moves with the draw: 1 m run-up, 2 treads up, a 1.5 m landing, 2 treads down
  t.startX = 1.0, t.topDepth = 1.5;
  EXPECT_NEAR(ai::terrainEndX(ai::drawStaircase(t, d, 0.12, 0, 0, 0).terrain), 1.0 + 2 * 0.28 + 1.5 + 2 * 0.28, 1e-9);
}
