// standup_card_test.cpp — the standup card in physics: lying down under the parent, standing up, the walk taking
// over. The priors alone (zero network output) do the motion, so the card's machinery is checked without models.
#include "ai/eval/standup_card.h"

#include <gtest/gtest.h>

#include "tests/fixtures.h"

namespace {

const ai::PolicyFn kZero = [](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) {
  act->setZero(robot::kActionSize, obs.cols());
};

const ai::CardFigure& figure(const ai::CardResult& r, const std::string& start) {
  for (const ai::CardFigure& f : r.figures)
    if (f.name.rfind(start, 0) == 0) return f;
  ADD_FAILURE() << "no figure starting '" << start << "'";
  static const ai::CardFigure none;
  return none;
}

struct Tree {
  robot::SkillTree tree = robot::loadSkillTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const robot::SkillDef& prone = *tree.find("prone");
  const robot::SkillDef& walk = *tree.find("walk");
  robot::SkillDef standup = *tree.find("standup");
  ai::CardRun run() const {
    ai::CardRun r{standup.card, 7, 1};
    r.card.episodes = 3;
    r.card.lieSeconds = {3.0, 4.0};
    return r;
  }
};

}  // namespace

// the prone prior lies face down by ~2.2 s; the stand-up's keyframes alone stand the robot up 4.64 s after the
// switch (tests/robot/pose_prior_test.cpp); the walk takes over only once it stands and has settled
TEST(StandUpCard, ThePriorsAloneLieDownThenStandUpWithinFiveSeconds) {
  Tree t;
  const ai::CardResult r = ai::runStandUpCard(fixtures::robotModel(), t.standup, kZero, t.run(), {&t.prone, kZero}, {&t.walk, kZero});
  EXPECT_EQ(figure(r, "lying face down when").value, 100.0);
  EXPECT_NEAR(figure(r, "mean time to stand").value, 4.64, 0.2);
  EXPECT_LE(figure(r, "slowest stand").value, 5.0);
  const double takeover = figure(r, "mean time to walk's takeover").value;
  EXPECT_GT(takeover, figure(r, "mean time to stand").value);  // settled after the first standing tick
  EXPECT_LT(takeover, 5.5);
}

TEST(StandUpCard, ASkillThatDoesNotRiseFailsIt) {
  Tree t;
  t.standup.prior.kind = robot::PriorDef::Kind::None;  // no keyframes: zero output only holds the default pose
  const ai::CardResult r = ai::runStandUpCard(fixtures::robotModel(), t.standup, kZero, t.run(), {&t.prone, kZero}, {&t.walk, kZero});
  EXPECT_EQ(figure(r, "episodes standing").value, 0.0);
  EXPECT_FALSE(r.pass);
}
