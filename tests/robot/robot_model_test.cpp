// robot_model_test.cpp — the URDF/TOML loader: facts from FACTS.md come out, bad files are located.
#include "robot/robot_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "robot/kinematics.h"

namespace {

const std::string kSource = TREELEARN_SOURCE_DIR;

std::string shippedUrdf() { return engine::readFile(kSource + "/assets/robots/g1_23dof.urdf"); }

std::string errorOf(const std::string& urdf) {
  robot::RobotModel m;
  try {
    robot::parseG1Urdf(urdf, "g1.urdf", &m);
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}

void replaceOnce(std::string* s, const std::string& from, const std::string& to) {
  const size_t at = s->find(from);
  ASSERT_NE(at, std::string::npos) << from;
  s->replace(at, from.size(), to);
}

}  // namespace

TEST(RobotModel, LoadsAll23JointsInTheSharedOrder) {
  const robot::RobotModel m = robot::loadRobotModel(kSource + "/assets/robots/g1_23dof.toml");
  ASSERT_EQ(m.joints.size(), 23u);
  ASSERT_EQ(m.articulation.links.size(), 23u);
  EXPECT_EQ(m.joints[0].name, "left_hip_pitch_joint");
  EXPECT_EQ(m.joints[12].name, "waist_yaw_joint");
  EXPECT_EQ(m.joints[22].name, "right_wrist_roll_joint");
  // FACTS §1: 32.10686 kg minus the 1 g pelvis_contour dummy we drop
  EXPECT_NEAR(m.totalMass, 32.10586, 1e-4);
  // FACTS §2 / §4c: knee effort 139 N m, armature 0.025101925 kg m^2
  EXPECT_DOUBLE_EQ(m.joints[3].effort, 139.0);
  EXPECT_DOUBLE_EQ(m.joints[3].armature, 0.025101925);
  EXPECT_EQ(m.articulation.links[size_t(m.leftFoot)].name, "left_ankle_roll_link");
}

TEST(RobotModel, SpawnHeightMatchesTheReferenceKinematics) {
  // FACTS §1: pelvis 0.7842 m above the sole in the rl_gym default pose, 0.7919 m at all-zero joints
  const robot::RobotModel m = robot::loadRobotModel(kSource + "/assets/robots/g1_23dof.toml");
  EXPECT_NEAR(m.spawnHeight, 0.7842, 0.001);
  EXPECT_NEAR(-robot::lowestColliderPoint(m.articulation, std::vector<double>(23, 0.0)), 0.7919, 0.001);
}

TEST(RobotModel, MissingJointIsReportedByName) {
  std::string urdf = shippedUrdf();
  replaceOnce(&urdf, "name=\"right_knee_joint\"", "name=\"right_knee_jnt\"");
  EXPECT_NE(errorOf(urdf).find("missing joint 'right_knee_joint'"), std::string::npos) << errorOf(urdf);
}

TEST(RobotModel, RemovedJointElementIsRejected) {
  std::string urdf = shippedUrdf();
  const size_t start = urdf.find("<joint name=\"left_elbow_joint\"");
  const size_t end = urdf.find("</joint>", start) + 8;
  urdf.erase(start, end - start);
  const std::string e = errorOf(urdf);
  EXPECT_EQ(e.rfind("g1.urdf:", 0), 0u) << e;
}

TEST(RobotModel, TruncatedXmlReportsALine) {
  const std::string urdf = shippedUrdf().substr(0, 3000);
  const std::string e = errorOf(urdf);
  EXPECT_EQ(e.rfind("g1.urdf:", 0), 0u) << e;
  EXPECT_NE(e.find("malformed XML"), std::string::npos) << e;
}

TEST(RobotModel, FixedJointIsRejectedWithItsLine) {
  std::string urdf = shippedUrdf();
  replaceOnce(&urdf, "<joint name=\"waist_yaw_joint\" type=\"revolute\">",
              "<joint name=\"waist_yaw_joint\" type=\"fixed\">");
  const std::string e = errorOf(urdf);
  EXPECT_NE(e.find("'waist_yaw_joint' is not revolute"), std::string::npos) << e;
  // the line is the joint element's own line
  int line = 1;
  const std::string text = shippedUrdf();
  for (size_t i = 0; i < text.find("<joint name=\"waist_yaw_joint\""); ++i) line += text[i] == '\n';
  EXPECT_NE(e.find("g1.urdf:" + std::to_string(line) + ":"), std::string::npos) << e;
}

TEST(RobotModel, NegativeMassIsRejected) {
  std::string urdf = shippedUrdf();
  replaceOnce(&urdf, "<mass value=\"3.813\"/>", "<mass value=\"-3.813\"/>");
  EXPECT_NE(errorOf(urdf), "");
}

// values no robot has make the solver diverge: refused at their line rather than simulated as NaN
TEST(RobotModel, PhysicallyAbsurdValuesAreRefused) {
  std::string heavy = shippedUrdf();
  replaceOnce(&heavy, "<mass value=\"3.813\"/>", "<mass value=\"1e308\"/>");
  EXPECT_NE(errorOf(heavy).find("must have a mass in (0, 1000] kg"), std::string::npos) << errorOf(heavy);
  std::string spinning = shippedUrdf();
  replaceOnce(&spinning, "<armature value=\"0.01017752\"/>", "<armature value=\"1e300\"/>");
  EXPECT_NE(errorOf(spinning).find("<armature value> must be a number in [0, 10]"), std::string::npos)
      << errorOf(spinning);
  std::string wide = shippedUrdf();
  replaceOnce(&wide, "ixx=\"0.010549\"", "ixx=\"1e300\"");
  EXPECT_NE(errorOf(wide), "");
}

TEST(RobotConfig, ANonFiniteGainOrDefaultIsRefusedWithItsLine) {
  const std::string dir = testing::TempDir() + "/robot_cfg_nan";
  engine::makeDirectories(dir);
  engine::writeFileAtomic(dir + "/g1.urdf", shippedUrdf());
  std::string cfg = engine::readFile(kSource + "/assets/robots/g1_23dof.toml");
  replaceOnce(&cfg, "left_hip_pitch_joint       = { default = -0.1, kp = 500.0,",
              "left_hip_pitch_joint       = { default = -0.1, kp = nan,");
  replaceOnce(&cfg, "urdf = \"g1_23dof.urdf\"", "urdf = \"g1.urdf\"");
  engine::writeFileAtomic(dir + "/g1.toml", cfg);
  try {
    robot::loadRobotModel(dir + "/g1.toml");
    FAIL() << "accepted kp = nan";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("g1.toml:15: left_hip_pitch_joint.kp must be a finite number"),
              std::string::npos)
        << e.what();
  }
}

TEST(RobotModel, RandomBytesNeverCrash) {
  std::string urdf = shippedUrdf();
  uint32_t state = 12345;
  for (int i = 0; i < 50; ++i) {
    std::string broken = urdf;
    for (int k = 0; k < 20; ++k) {
      state = state * 1664525u + 1013904223u;
      broken[state % broken.size()] = char(state >> 24);
    }
    robot::RobotModel m;
    try {
      robot::parseG1Urdf(broken, "g1.urdf", &m);
    } catch (const engine::Error&) {
    }
  }
}

TEST(RobotConfig, UnknownJointReportsFileAndLine) {
  const std::string dir = testing::TempDir() + "/robot_cfg";
  engine::makeDirectories(dir);
  engine::writeFileAtomic(dir + "/g1.urdf", shippedUrdf());
  std::string cfg = engine::readFile(kSource + "/assets/robots/g1_23dof.toml");
  cfg = "urdf = \"g1.urdf\"\n[joints]\nleft_hip_pich_joint = { default = 0.0, kp = 1.0, kd = 1.0 }\n";
  engine::writeFileAtomic(dir + "/g1.toml", cfg);
  try {
    robot::loadRobotModel(dir + "/g1.toml");
    FAIL() << "accepted an unknown joint";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("g1.toml:3: unknown joint 'left_hip_pich_joint'"), std::string::npos)
        << e.what();
  }
}
