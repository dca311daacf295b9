// checkpoint_test.cpp — the spawn and a checkpoint are where the robot is put, upright on both feet: the loader refuses
// one without room to stand (levels::kStandHeight, levels::kStandHalfFootprint: 1.35 m up, 0.3 m around).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "engine/core/error.h"
#include "levels/level.h"

namespace {

// a game level: a tunnel roof over x 5..8 (0.6 to 0.8 m up), one step over x 10..10.6 (0.1 m), a goal far away;
// `checkpoints` goes on line 4 and `extra` after everything else (from line 20)
std::string course(const std::string& checkpoints, const std::string& extra = "") {
  return "name = \"cp\"\n"        // 1
         "[rules]\n"              // 2
         "falls = \"respawn\"\n"  // 3
         "checkpoints = " +
         checkpoints +
         "\n"                           // 4
         "[[tunnel]]\n"                 // 5
         "start = 5.0\n"                // 6
         "length = 3.0\n"               // 7
         "clearance = 0.6\n"            // 8
         "width = 2.0\n"                // 9
         "[[stairs]]\n"                 // 10
         "name = \"step\"\n"            // 11
         "start = [10.0, 0.0]\n"        // 12
         "steps = 1\n"                  // 13
         "rise = 0.1\n"                 // 14
         "run = 0.6\n"                  // 15
         "width = 2.0\n"                // 16
         "[[goal]]\n"                   // 17
         "centre = [30.0, 0.0, 0.6]\n"  // 18
         "size = [1.0, 2.0, 1.2]\n"     // 19
         + extra;
}

// loads the text from a level file in a temporary folder (as `play` would); "" if it loads, else the error
std::string loadError(const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("treelearn_checkpoint_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "level.toml") << text;
  std::string error;
  try {
    levels::loadLevel(dir.string());
  } catch (const engine::Error& e) {
    error = e.what();
  }
  fs::remove_all(dir);
  return error;
}

}  // namespace

TEST(Level, CheckpointUnderCeilingIsRefused) {
  // at x = 8.2 the robot's 0.3 m around reach back to 7.9, under the roof that ends at 8.0 (0.6 m < 1.35 m up)
  const std::string e = loadError(course("[8.2]"));
  EXPECT_NE(e.find("level.toml:4: checkpoint at x = 8.2 has no room to stand: 'tunnel' (defined on line 5) is within "
                   "0.30 m of it and lower than 1.35 m"),
            std::string::npos)
      << e;
  // in the middle of the tunnel too
  EXPECT_NE(loadError(course("[6.5]")).find("'tunnel'"), std::string::npos);
  // at 8.35 it reaches back to 8.05, clear of the roof
  EXPECT_EQ(loadError(course("[8.35]")), "");
}

TEST(Level, CheckpointOnOrAgainstAStepIsRefused) {
  // the step is a 0.1 m column over x 10..10.6: the feet would be put inside it
  const std::string onTop = loadError(course("[10.3]"));
  EXPECT_NE(onTop.find("level.toml:4: checkpoint at x = 10.3 has no room to stand: 'step_up1' (defined on line 10)"),
            std::string::npos)
      << onTop;
  // 9.75 reaches 10.05 (refused), 9.65 reaches 9.95 (clear); past it, 10.95 reaches back to 10.65 (clear)
  EXPECT_NE(loadError(course("[9.75]")).find("'step_up1'"), std::string::npos);
  EXPECT_EQ(loadError(course("[9.65, 10.95]")), "");
}

TEST(Level, TheFirstCheckpointWithoutRoomIsNamed) {
  const std::string e = loadError(course("[2.0, 10.3, 20.0]"));
  EXPECT_NE(e.find("checkpoint at x = 10.3"), std::string::npos) << e;
}

TEST(Level, ACheckpointBesideAWallIsRefusedOnlyWithinTheFootprint) {
  // a wall along the course whose near face is 0.25 m from the centre line (y 0.25..0.35): inside the 0.3 m
  const std::string wall = "[[wall]]\nname = \"rail\"\ncentre = [15.0, 0.3, 1.0]\nsize = [4.0, 0.1, 2.0]\n";
  const std::string e = loadError(course("[15.0]", wall));
  EXPECT_NE(e.find("level.toml:4: checkpoint at x = 15 has no room to stand: 'rail' (defined on line 20)"),
            std::string::npos)
      << e;
  // moved 0.1 m out (near face at 0.35 m): room
  const std::string away = "[[wall]]\nname = \"rail\"\ncentre = [15.0, 0.4, 1.0]\nsize = [4.0, 0.1, 2.0]\n";
  EXPECT_EQ(loadError(course("[15.0]", away)), "");
}

TEST(Level, AQuestionBoxOverACheckpointIsRefusedOnlyBelowStandingHeight) {
  // levels/mario's boxes hang 1.38 m up (bottom of a 0.4 m box centred at 1.58): the robot stands under them
  EXPECT_EQ(loadError(course("[15.0]", "[[question_box]]\ncentre = [15.0, 0.0, 1.58]\n")), "");
  // centred at 1.50 its bottom is at 1.30 m, lower than 1.35
  const std::string e = loadError(course("[15.0]", "[[question_box]]\ncentre = [15.0, 0.0, 1.50]\n"));
  EXPECT_NE(e.find("level.toml:4: checkpoint at x = 15 has no room to stand: a question box (defined on line 20)"),
            std::string::npos)
      << e;
}

TEST(Level, TheShippedMarioCheckpointsHaveRoomToStand) {
  const levels::Level m = levels::loadLevel(std::string(TREELEARN_SOURCE_DIR) + "/levels/mario");
  EXPECT_EQ(m.rules.checkpoints.size(), 4u);
}

TEST(Level, SpawnInsideABoxIsRefusedAtTheSpawnsLine) {
  // a 1 m cube on the default spawn at (0, 0) threw the pelvis 15 m up on the first tick
  const std::string cube =
      "[[box]]\n"                   // 20
      "name = \"crate\"\n"          // 21
      "centre = [0.0, 0.0, 0.5]\n"  // 22
      "size = [1.0, 1.0, 1.0]\n";   // 23
  const std::string e = loadError(course("[]", cube));
  EXPECT_NE(e.find("level.toml: the spawn at (0, 0) (the default: the level has no [spawn]) has no room to stand: "
                   "'crate' (defined on line 20)"),
            std::string::npos)
      << e;
  // with a [spawn] table the error points at it; 0.8 m away the robot's 0.3 m around clear the cube's 0.5 m
  const std::string at = "[spawn]\nposition = [0.75, 0.0]\n";  // 20, 21
  EXPECT_NE(loadError(course("[]", at + cube)).find("level.toml:20: the spawn at (0.75, 0) has no room to stand"),
            std::string::npos);
  EXPECT_EQ(loadError(course("[]", "[spawn]\nposition = [-0.85, 0.0]\n" + cube)), "");
}

TEST(Level, SpawnUnderALowCeilingIsRefused) {
  // the tunnel's roof is 0.6 m up over x 5..8: a robot spawned at x = 6 would stand into it
  const std::string e = loadError(course("[]", "[spawn]\nposition = [6.0, 0.0]\n"));
  EXPECT_NE(e.find("level.toml:20: the spawn at (6, 0) has no room to stand: 'tunnel'"), std::string::npos) << e;
}
