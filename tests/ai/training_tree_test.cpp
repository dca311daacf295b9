// training_tree_test.cpp — the tables of the tree file that training and the cards own ([draws], [rewards],
// [randomisation], [training], [ball], [terrain], [curriculum], [card]): read onto the runtime's skills, and every bad
// entry refused with its file and line.
#include "ai/tree/training_tree.h"

#include <gtest/gtest.h>

#include "engine/core/error.h"
#include "tests/fixtures.h"

namespace {

// the error loading `text` as a tree file (t.toml in a temp folder `name`) for training, or "" when it loads
std::string treeError(const std::string& name, const std::string& text) {
  try {
    ai::loadTrainingTree(fixtures::writeTree(name, text), fixtures::robotModel());
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TrainingTree, TheShippedWalkHasItsVelocityCardAndItsOwnDraws) {
  const ai::TrainingTree tree =
      ai::loadTrainingTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const ai::SkillSpec* walk = tree.find("walk");
  ASSERT_NE(walk, nullptr);
  EXPECT_EQ(walk->key, 0);  // the runtime's part comes with it
  ASSERT_EQ(walk->card.kind(), ai::CardKind::Velocity);
  EXPECT_EQ(walk->card.episodes, 50);
  const ai::DrivenCard& card = *walk->card.driven();
  EXPECT_DOUBLE_EQ(card.noFallPercent, 95.0);
  EXPECT_DOUBLE_EQ(card.speedError, 0.15);
  EXPECT_DOUBLE_EQ(card.yawError, 0.2);
  EXPECT_DOUBLE_EQ(card.standDrift, 0.2);
  EXPECT_EQ(walk->card.lying(), nullptr);
  EXPECT_EQ(walk->card.as<ai::StairsCard>(), nullptr);
  EXPECT_DOUBLE_EQ(walk->draws.resampleJitter, 0.5);
  // the crawl steers back to its line in play too: a runtime setting, in [commands]
  EXPECT_DOUBLE_EQ(tree.find("crawl")->commands.lineSteer, 0.5);
  EXPECT_TRUE(tree.find("kick")->commands.ballCommand);
  EXPECT_TRUE(tree.find("kick")->ball.enabled);
}

TEST(TrainingTree, ABranchWithoutRandomisationTakesItsParents) {
  const std::string text = "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" +
                           fixtures::kWalkGains +
                           "[skill.walk.randomisation]\nfriction = [0.5, 1.5]\n"
                           // 'a' sorts before 'walk', so the file order is not the resolution order
                           "[skill.a]\nparent = \"walk\"\nkey = 1\n[skill.a.rewards]\nlive = 1\n"
                           "[skill.b]\nparent = \"walk\"\nkey = 2\n[skill.b.rewards]\nlive = 1\n"
                           "[skill.b.randomisation]\nadded_mass = [0, 2]\n";
  const ai::TrainingTree tree =
      ai::loadTrainingTree(fixtures::writeTree("tree_randomisation", text), fixtures::robotModel());
  EXPECT_DOUBLE_EQ(tree.find("a")->randomisation.friction.lo, 0.5);
  EXPECT_DOUBLE_EQ(tree.find("b")->randomisation.friction.lo, 1.0);  // its own table, read whole
  EXPECT_DOUBLE_EQ(tree.find("b")->randomisation.addedMass.hi, 2.0);
}

TEST(TrainingTree, BadEntriesAreLocated) {
  auto errorOf = [](const std::string& text) { return treeError("tree_training_bad", text); };
  const std::string walk =
      "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" + fixtures::kWalkGains;
  EXPECT_NE(errorOf("[skill.walk]\nparent = \"\"\nkey = 0\n" + fixtures::kWalkGains)
                .find("t.toml:1: skill.walk: missing [rewards]"),
            std::string::npos);
  // what only training reads is refused at load too, so that `tree` and `play` refuse what `train` would
  std::string badTerm = walk;
  badTerm.replace(badTerm.find("live = 1"), 8, "speed = 1");
  EXPECT_NE(errorOf(badTerm).find("t.toml:5: skill.walk: unknown reward term 'speed'"), std::string::npos)
      << errorOf(badTerm);
  EXPECT_NE(errorOf(walk + "[skill.walk.ppo]\nlearning_rat = 1e-4\n").find("t.toml:20: unknown key 'learning_rat'"),
            std::string::npos)
      << errorOf(walk + "[skill.walk.ppo]\nlearning_rat = 1e-4\n");
  // the runtime's errors come first (robot::loadSkillTree reads the file before)
  EXPECT_NE(errorOf(walk + "[skill.walk.commands]\nramp = true\n")
                .find("t.toml:20: unknown key 'ramp' in skill.walk.commands"),
            std::string::npos);
  const std::string badMix = walk + "[skill.walk.card]\ntype = \"velocity\"\nmix = [0.5, 0.5, 0.5, 0.0]\n";
  EXPECT_NE(errorOf(badMix).find("t.toml:21: skill.walk.card.mix must add up to 1"), std::string::npos)
      << errorOf(badMix);
  const std::string flatSpawn = walk + "[skill.walk.terrain]\ntype = \"flat\"\nspawn_along = 0.5\n";
  EXPECT_NE(
      errorOf(flatSpawn).find("t.toml:21: skill.walk.terrain.spawn_along starts episodes on a staircase's treads"),
      std::string::npos)
      << errorOf(flatSpawn);
  const std::string spawnOverOne =
      walk + "[skill.walk.terrain]\ntype = \"stairs\"\nlessons = [0.1]\nspawn_along = 1.5\n";
  EXPECT_NE(errorOf(spawnOverOne).find("spawn_along"), std::string::npos) << errorOf(spawnOverOne);
  const std::string badType = walk + "[skill.walk.card]\ntype = \"juggling\"\n";
  EXPECT_NE(errorOf(badType).find("t.toml:19: skill.walk.card.type"), std::string::npos) << errorOf(badType);
  const std::string rootStandUp =
      walk + "[skill.walk.card]\ntype = \"standup\"\n";  // who lies it down, who takes over?
  EXPECT_NE(errorOf(rootStandUp).find("t.toml:19: skill.walk.card: a standup card needs the skill's parent"),
            std::string::npos)
      << errorOf(rootStandUp);
  const std::string rootLeadIn =
      walk + "[skill.walk.card]\ntype = \"velocity\"\nlead_in = true\n";  // nobody drives first
  EXPECT_NE(errorOf(rootLeadIn).find("t.toml:21: skill.walk.card.lead_in: only a branch's"), std::string::npos)
      << errorOf(rootLeadIn);
  const std::string badLeadIn = walk + "[skill.walk.card]\ntype = \"velocity\"\nlead_in = 1\n";
  EXPECT_NE(errorOf(badLeadIn).find("t.toml:21: skill.walk.card.lead_in must be true or false"), std::string::npos)
      << errorOf(badLeadIn);
  const std::string badRamp = walk + "[skill.walk.draws]\nzero_probability = 0.5\nramp = 2\n";
  EXPECT_NE(errorOf(badRamp).find("t.toml:21: skill.walk.draws.ramp must be true or false"), std::string::npos)
      << errorOf(badRamp);
  const std::string badSteer =
      walk + "[skill.walk.draws]\nzero_probability = 0.5\nsteer = 3\n";  // 3 rad/s: no heading hold
  EXPECT_NE(errorOf(badSteer).find("t.toml:21:"), std::string::npos) << errorOf(badSteer);
  EXPECT_NE(errorOf(badSteer).find("steer"), std::string::npos) << errorOf(badSteer);
  // a ball goes with ball_command (the aux slots show it), and ball_command with a ball to show
  const std::string ballUnseen = walk + "[skill.walk.commands]\nvx = [0, 1]\n[skill.walk.ball]\n";
  EXPECT_NE(errorOf(ballUnseen)
                .find("t.toml:21: skill.walk.ball: a ball skill sees its ball in the aux command slots: it "
                      "needs [commands] ball_command = true"),
            std::string::npos)
      << errorOf(ballUnseen);
  const std::string noBall = walk + "[skill.walk.commands]\nball_command = true\n";
  EXPECT_NE(errorOf(noBall).find("t.toml:1: skill.walk: [commands] ball_command shows a ball that training places"),
            std::string::npos)
      << errorOf(noBall);
  const std::string jitterNoLine = walk + "[skill.walk.training]\nline_jitter = [0.3, 0.3]\n";
  EXPECT_NE(errorOf(jitterNoLine)
                .find("t.toml:20: skill.walk.training.line_jitter moves the line a skill sees, and it sees none"),
            std::string::npos)
      << errorOf(jitterNoLine);
  const std::string headingNoTurn =
      walk + "[skill.walk.commands]\nvx = [0, 1]\nwz = [0, 0]\n[skill.walk.training]\nheading_steer = 2.0\n";
  EXPECT_NE(errorOf(headingNoTurn)
                .find("t.toml:23: skill.walk.training.heading_steer steers with wz, and the skill's commands need"),
            std::string::npos)
      << errorOf(headingNoTurn);
  const std::string twoSteers = walk +
                                "[skill.walk.commands]\nvx = [0, 1]\nwz = [-1, 1]\nline_steer = "
                                "1.0\n[skill.walk.training]\nheading_steer = 2.0\n";
  EXPECT_NE(errorOf(twoSteers).find(
                "t.toml:24: skill.walk.training: heading_steer and [commands] line_steer both set the yaw-rate"),
            std::string::npos)
      << errorOf(twoSteers);
  const std::string shareNoSteer =
      walk + "[skill.walk.commands]\nvx = [0, 1]\nwz = [-1, 1]\n[skill.walk.training]\nheading_steer_share = 0.5\n";
  EXPECT_NE(
      errorOf(shareNoSteer)
          .find("t.toml:23: skill.walk.training.heading_steer_share is the share of episodes heading_steer steers"),
      std::string::npos)
      << errorOf(shareNoSteer);
  const std::string shareTooBig = walk +
                                  "[skill.walk.commands]\nvx = [0, 1]\nwz = [-1, "
                                  "1]\n[skill.walk.training]\nheading_steer = 2.0\nheading_steer_share = 1.5\n";
  EXPECT_NE(errorOf(shareTooBig).find("t.toml:24"), std::string::npos) << errorOf(shareTooBig);
  const std::string rootHandover = walk + "[skill.walk.training]\nhandover = 0.5\n";  // the root has no parent
  EXPECT_NE(errorOf(rootHandover).find("t.toml:20: skill.walk.training.handover needs a parent"), std::string::npos)
      << errorOf(rootHandover);
  const std::string branch = walk + "[skill.a]\nparent = \"walk\"\nkey = 1\n[skill.a.rewards]\nlive = 1\n";
  const std::string notAncestor = branch +
                                  "[skill.b]\nparent = \"walk\"\nkey = 2\n[skill.b.rewards]\nlive = 1\n"
                                  "[skill.b.training]\nhandover = 0.5\nhandover_from = \"a\"\n";  // a sibling
  EXPECT_NE(errorOf(notAncestor).find("t.toml:24: skill.b: training.handover_from = 'a' is not one of its ancestors"),
            std::string::npos)
      << errorOf(notAncestor);
  const std::string grandparent = branch +
                                  "[skill.c]\nparent = \"a\"\nkey = 2\n[skill.c.rewards]\nlive = 1\n"
                                  "[skill.c.training]\nhandover = 0.5\nhandover_from = \"walk\"\n";
  EXPECT_EQ(errorOf(grandparent), "");
  EXPECT_EQ(errorOf(grandparent + "handover_via_s = [0.5, 1.5]\n"), "");  // time in a, between walk and c
  // handover_back_from names a child (the way back up the tree), and goes with a share of episodes
  EXPECT_EQ(errorOf(grandparent + "[skill.a.training]\nhandover_back = 0.4\nhandover_back_from = \"c\"\n"), "");
  EXPECT_NE(errorOf(branch + "[skill.a.training]\nhandover_back = 0.4\nhandover_back_from = \"walk\"\n")
                .find("t.toml:19: skill.a: training.handover_back_from = 'walk' is not one of its children"),
            std::string::npos)
      << errorOf(branch + "[skill.a.training]\nhandover_back = 0.4\nhandover_back_from = \"walk\"\n");
  const std::string shareAlone = branch + "[skill.a.training]\nhandover_back = 0.4\n";
  EXPECT_NE(errorOf(shareAlone).find("t.toml:24: skill.a.training: handover_back and handover_back_from go together"),
            std::string::npos)
      << errorOf(shareAlone);
  const std::string overOne =
      grandparent + "[skill.a.training]\nhandover = 0.7\nhandover_back = 0.4\nhandover_back_from = \"c\"\n";
  EXPECT_NE(errorOf(overOne).find("skill.a.training.handover + handover_back must be at most 1"), std::string::npos)
      << errorOf(overOne);
  const std::string nothingBetween = branch + "[skill.a.training]\nhandover = 0.5\nhandover_via_s = [0.5, 1.5]\n";
  EXPECT_NE(
      errorOf(nothingBetween).find("t.toml:26: skill.a.training.handover_via_s is the time in the skills between"),
      std::string::npos)
      << errorOf(nothingBetween);
  // a command curriculum ends at what the skill ships with (its commands' vx top, the prior's T1)
  const std::string phase =
      walk + "[skill.walk.prior]\ntype = \"phase\"\nT1 = 30\n[skill.walk.commands]\nvx = [0.5, 2.0]\n";
  const std::string shortTop = phase + "[skill.walk.curriculum]\nvx_max = [1.0, 1.5]\n";
  EXPECT_NE(errorOf(shortTop).find("t.toml:24: skill.walk.curriculum.vx_max must end at the commands' vx top"),
            std::string::npos)
      << errorOf(shortTop);
  const std::string otherT1 = phase + "[skill.walk.curriculum]\nvx_max = [1.0, 2.0]\nT1 = [40, 35]\n";
  EXPECT_NE(errorOf(otherT1).find("t.toml:24: skill.walk.curriculum.T1 must end at the prior's T1 (30)"),
            std::string::npos)
      << errorOf(otherT1);
  const std::string ragged = phase + "[skill.walk.curriculum]\nvx_max = [1.0, 2.0]\nT1 = [40, 35, 30]\n";
  EXPECT_NE(errorOf(ragged).find("one value per lesson"), std::string::npos) << errorOf(ragged);
  const std::string belowBottom = phase + "[skill.walk.curriculum]\nvx_max = [0.4, 2.0]\n";
  EXPECT_NE(errorOf(belowBottom).find("above the commands' vx bottom"), std::string::npos) << errorOf(belowBottom);
  const std::string both = phase + "[skill.walk.curriculum]\nvx_max = [1.0, 2.0]\namplitude_max = [0.5, 1.0]\n";
  EXPECT_NE(errorOf(both).find("t.toml:24: skill.walk.curriculum needs one of vx_max"), std::string::npos)
      << errorOf(both);
  const std::string squatT1 =
      walk +
      "[skill.walk.prior]\ntype = \"pose\"\noffset = { knee = 1 }\n[skill.walk.commands]\nvx = [0.5, 2.0]\n"
      "[skill.walk.curriculum]\nvx_max = [1.0, 2.0]\nT1 = [40, 40]\n";
  EXPECT_NE(errorOf(squatT1).find("T1 and stride lessons are for a \"phase\" prior"), std::string::npos)
      << errorOf(squatT1);
  const std::string good = phase + "[skill.walk.curriculum]\nvx_max = [1.0, 2.0]\nT1 = [40, 30]\nadvance_at = 1.2\n";
  EXPECT_EQ(errorOf(good), "");
}

TEST(TrainingTree, PlayEpisodesNeedTheirShareAndAFileNameInTheTreesFolder) {
  auto errorOf = [](const std::string& text) { return treeError("tree_training_play", text); };
  const std::string walk = "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" +
                           fixtures::kWalkGains + "[skill.walk.training]\n";  // line 19
  EXPECT_EQ(errorOf(walk + "play_entries = \"walk.entries\"\nplay_share = 0.3\n"), "");
  EXPECT_NE(errorOf(walk + "play_share = 0.3\n")
                .find("t.toml:19: skill.walk.training: play_share and play_entries go together"),
            std::string::npos);
  EXPECT_NE(errorOf(walk + "play_entries = \"../walk.entries\"\nplay_share = 0.3\n")
                .find("t.toml:20: skill.walk.training.play_entries must be a file name in the tree's folder"),
            std::string::npos);
  EXPECT_NE(errorOf(walk + "play_entries = \"walk.entries\"\nplay_share = 1.5\n").find("t.toml:21"), std::string::npos);
}

TEST(TrainingTree, ACardTakesOnlyTheKeysItsTypeReads) {
  auto errorOf = [](const std::string& text) { return treeError("tree_card_keys", text); };
  const std::string walk =
      "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" + fixtures::kWalkGains;
  // a velocity card has no success figure, and a lift is a balance card's
  const std::string liftOnVelocity = walk + "[skill.walk.card]\ntype = \"velocity\"\nlift_s = 5.0\n";
  EXPECT_NE(errorOf(liftOnVelocity).find("t.toml:21: skill.walk.card.lift_s is not a key of a velocity card"),
            std::string::npos)
      << errorOf(liftOnVelocity);
  const std::string successOnVelocity = walk + "[skill.walk.card]\ntype = \"velocity\"\nsuccess_pct = 90\n";
  EXPECT_NE(errorOf(successOnVelocity).find("t.toml:21: skill.walk.card.success_pct is not a key of a velocity card"),
            std::string::npos)
      << errorOf(successOnVelocity);
  // lead_in = false is no lead-in, but a stairs card has no lead-in to turn off
  const std::string leadInOnStairs = walk + "[skill.walk.card]\ntype = \"stairs\"\nlead_in = false\n";
  EXPECT_NE(errorOf(leadInOnStairs).find("t.toml:21: skill.walk.card.lead_in is not a key of a stairs card"),
            std::string::npos)
      << errorOf(leadInOnStairs);
  // a stand-up card runs no commands and no pushes
  const std::string branch =
      walk + "[skill.a]\nparent = \"walk\"\nup = \"walk\"\nkey = 1\n[skill.a.rewards]\nlive = 1\n";
  const std::string mixOnStandUp =
      branch + "[skill.a.card]\ntype = \"standup\"\nrise_s = 4.0\nmix = [1.0, 0.0, 0.0, 0.0]\n";
  EXPECT_NE(errorOf(mixOnStandUp).find("t.toml:28: skill.a.card.mix is not a key of a standup card"), std::string::npos)
      << errorOf(mixOnStandUp);
  // a key the type does not read is reported as such, whatever its value
  const std::string badValue = walk + "[skill.walk.card]\ntype = \"velocity\"\nlift_s = -1\n";
  EXPECT_NE(errorOf(badValue).find("t.toml:21: skill.walk.card.lift_s is not a key of a velocity card"),
            std::string::npos)
      << errorOf(badValue);
  // each type's own keys load
  EXPECT_EQ(errorOf(walk + "[skill.walk.card]\ntype = \"balance\"\nepisodes = 5\nepisode_s = 8.0\nlift_height = 0.08\n"
                           "lift_s = 5.0\nsuccess_pct = 90\nno_fall_pct = 90\nmix = [0.0, 0.0, 0.0, 1.0]\n"),
            "");
  EXPECT_EQ(errorOf(branch + "[skill.a.card]\ntype = \"standup\"\nepisodes = 5\nlie_s = [3.0, 5.5]\nrise_s = 5.0\n"
                             "after_s = 3.0\nsuccess_pct = 90\n"),
            "");
}

TEST(TrainingTree, DrawnStairsNeedRiseTreadAndStepsAndNoLessons) {
  auto errorOf = [](const std::string& text) { return treeError("tree_training_stairs_draw", text); };
  const std::string walk =
      "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" + fixtures::kWalkGains;
  const std::string terrain = walk + "[skill.walk.terrain]\ntype = \"stairs\"\n";  // the table is at line 19
  const std::string drawn = terrain + "rise = [0.08, 0.15]\ntread = [0.28, 0.6]\nsteps = [3, 6]\n";
  EXPECT_EQ(errorOf(drawn), "");
  const ai::TrainingTree tree = ai::loadTrainingTree(
      fixtures::writeTree("tree_training_stairs_draw", drawn + "entry_heading_deg = 20\n"), fixtures::robotModel());
  const ai::TerrainDef& t = tree.find("walk")->terrain;
  EXPECT_TRUE(t.draw.drawn());
  EXPECT_DOUBLE_EQ(t.draw.tread.hi, 0.6);
  EXPECT_EQ(t.steps, 6);  // the written staircase is the largest drawn
  EXPECT_DOUBLE_EQ(t.entryYaw, 20.0 * M_PI / 180.0);
  const std::string noSteps = terrain + "rise = [0.08, 0.15]\ntread = [0.28, 0.6]\n";
  EXPECT_NE(errorOf(noSteps).find("t.toml:19: skill.walk.terrain: stairs drawn for each episode need rise, tread and "
                                  "steps"),
            std::string::npos)
      << errorOf(noSteps);
  EXPECT_NE(errorOf(drawn + "lessons = [0.1]\n").find("without lessons"), std::string::npos);
  const std::string halfStep = terrain + "rise = [0.08, 0.15]\ntread = [0.28, 0.6]\nsteps = [3, 5.5]\n";
  EXPECT_NE(errorOf(halfStep).find("t.toml:23: skill.walk.terrain.steps must be a whole number"), std::string::npos)
      << errorOf(halfStep);
  const std::string lowAboveHigh = terrain + "rise = [0.15, 0.08]\ntread = [0.28, 0.6]\nsteps = [3, 6]\n";
  EXPECT_NE(errorOf(lowAboveHigh).find("t.toml:21: skill.walk.terrain.rise: low is above high"), std::string::npos)
      << errorOf(lowAboveHigh);
  // the card draws its own staircases, so it gives no step_height
  const std::string card = walk +
                           "[skill.walk.terrain]\ntype = \"stairs\"\nlessons = [0.1]\n[skill.walk.card]\n"
                           "type = \"stairs\"\nstep_height = 0.1\nrise = [0.08, 0.15]\ntread = [0.3, 0.3]\n"
                           "steps = [3, 3]\n";
  EXPECT_NE(errorOf(card).find("t.toml:24: skill.walk.card.step_height: the rise is drawn"), std::string::npos)
      << errorOf(card);
}
