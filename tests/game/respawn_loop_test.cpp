// respawn_loop_test.cpp — kRespawnLoopFalls falls back to one checkpoint within kRespawnLoopSeconds lose the run.
#include <gtest/gtest.h>

#include "game/course.h"

namespace {

const char* kLevel = R"(name = "loop"
[rules]
falls = "respawn"
fall_penalty = 50
checkpoints = [10.0]
[[goal]]
centre = [30.0, 0.0, 0.6]
size = [1.0, 2.0, 1.2]
)";

struct World {
  levels::Level level = levels::parseLevel(kLevel, "loop.toml");
  engine::PhysicsWorld physics;
  engine::PlaneWorld plane;
  game::Course course{level, physics, plane};
  // one tick of the rules with the pelvis standing at x
  void at(int64_t tick, double x) {
    robot::Sensors s;
    s.basePosition = Eigen::Vector3d(x, 0, 0.78);
    course.update(tick, s, {}, physics, plane);
  }
};

}  // namespace

TEST(Course, RepeatedRespawnsAtOneCheckpointLoseTheRun) {
  static_assert(game::kRespawnLoopFalls == 5 && game::kRespawnLoopSeconds == 10.0, "the expectations below");
  World w;
  // a fall every second back to the spawn (x = 0): the first four put the robot back
  for (int64_t tick : {0, 100, 200, 300}) EXPECT_TRUE(w.course.onFall(tick)) << tick;
  EXPECT_EQ(w.course.outcome(), game::Outcome::Playing);
  // the fifth, 4 s after the first: lost, with its reason and a RespawnLoop event before the Lost one
  EXPECT_FALSE(w.course.onFall(400));
  EXPECT_EQ(w.course.outcome(), game::Outcome::Lost);
  EXPECT_EQ(w.course.outcomeReason(), "a respawn loop (5 falls within 10 s back to the checkpoint at x = 0.00)");
  EXPECT_EQ(w.course.falls(), 5);
  EXPECT_EQ(w.course.score(), -250);  // every fall's penalty, the last one's too
  const std::vector<game::CourseEvent>& e = w.course.events();
  ASSERT_GE(e.size(), 2u);
  EXPECT_EQ(e[e.size() - 2].kind, game::CourseEventKind::RespawnLoop);
  EXPECT_EQ(e[e.size() - 2].what, "fell 5 times within 4.0 s back to x = 0.00, -50: a respawn loop");
  EXPECT_EQ(e.back().kind, game::CourseEventKind::Lost);
  EXPECT_EQ(e.back().tick, 400);
}

TEST(Course, FiveFallsExactlyTenSecondsApartAreStillALoop) {
  World w;  // falls 2.5 s apart: the fifth is 10.0 s after the first, within the window (<=)
  for (int64_t tick : {0, 250, 500, 750}) EXPECT_TRUE(w.course.onFall(tick));
  EXPECT_FALSE(w.course.onFall(1000));
  EXPECT_EQ(w.course.outcome(), game::Outcome::Lost);
}

TEST(Course, FallsSlowerThanTheLoopWindowGoOnRespawning) {
  World w;  // 2.6 s apart: any five of them span 10.4 s > 10 s
  for (int64_t i = 0; i < 12; ++i) EXPECT_TRUE(w.course.onFall(i * 260)) << i;
  EXPECT_EQ(w.course.outcome(), game::Outcome::Playing);
  EXPECT_EQ(w.course.falls(), 12);
}

TEST(Course, PassingANewCheckpointStartsItsOwnCountOfFalls) {
  World w;
  for (int64_t tick : {0, 100, 200, 300}) EXPECT_TRUE(w.course.onFall(tick));  // four at the spawn
  w.at(350, 10.5);                                                             // past the checkpoint at 10
  EXPECT_DOUBLE_EQ(w.course.respawnX(), 10.0);
  for (int64_t tick : {400, 500, 600, 700}) EXPECT_TRUE(w.course.onFall(tick)) << tick;  // four at x = 10
  EXPECT_FALSE(w.course.onFall(800));                                                    // the fifth there
  EXPECT_EQ(w.course.outcomeReason(), "a respawn loop (5 falls within 10 s back to the checkpoint at x = 10.00)");
}
