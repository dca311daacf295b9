// ground_card_test.cpp — the ground cards in physics: lying down under the parent, standing up, the walk taking
// over. The priors alone (zero network output) do the motion, so the card's machinery is checked without models.
#include "ai/eval/ground_card.h"

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
  ai::TrainingTree tree = ai::loadTrainingTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const ai::SkillSpec& prone = *tree.find("prone");
  const ai::SkillSpec& walk = *tree.find("walk");
  ai::SkillSpec standup = *tree.find("standup");
  // two episodes of `skill`'s own card at `seed`, on one thread
  static ai::CardRun twoEpisodes(const ai::SkillSpec& skill, uint64_t seed) {
    ai::CardRun r{skill.card, seed, 1};
    r.card.episodes = 2;
    return r;
  }
  // a push-up or crawl card of `skill`, its prior and prone's alone (zero network output)
  ai::CardResult groundCard(const ai::SkillSpec& skill, ai::CardRun run) const {
    return ai::runGroundCard(fixtures::robotModel(), skill, kZero, run, {&prone, kZero}, {});
  }
  ai::CardRun run() const {
    ai::CardRun r{standup.card, 7, 1};
    r.card.episodes = 3;
    r.card.as<ai::StandUpCard>()->lieSeconds = {3.0, 4.0};
    return r;
  }
};

}  // namespace

// the prone prior lies face down by ~2.2 s; the stand-up's keyframes alone stand the robot up 4.64 s after the
// switch (tests/robot/pose_prior_test.cpp); the walk takes over only once it stands and has settled
TEST(StandUpCard, ThePriorsAloneLieDownThenStandUpWithinFiveSeconds) {
  Tree t;
  const ai::CardResult r =
      ai::runGroundCard(fixtures::robotModel(), t.standup, kZero, t.run(), {&t.prone, kZero}, {&t.walk, kZero});
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
  const ai::CardResult r =
      ai::runGroundCard(fixtures::robotModel(), t.standup, kZero, t.run(), {&t.prone, kZero}, {&t.walk, kZero});
  EXPECT_EQ(figure(r, "episodes standing").value, 0.0);
  EXPECT_FALSE(r.pass);
}

// the push-up prior alone (zero network output) after prone's lying down: the torso link's origin goes 0.12 ->
// 0.26 m every 1.6 s cycle (6 push-ups in the 10 s after a 0.6 s lead-in)
TEST(PushUpCard, ThePriorsAloneLieDownThenPushUpSixTimesInTenSeconds) {
  Tree t;
  ai::SkillSpec pushup = *t.tree.find("pushup");
  ai::CardRun run = Tree::twoEpisodes(pushup, 7);
  const ai::CardResult r = t.groundCard(pushup, run);
  EXPECT_EQ(figure(r, "lying face down when").value, 100.0);
  EXPECT_EQ(figure(r, "fewest push-ups").value, 6.0);
  EXPECT_NEAR(figure(r, "mean torso rise per push-up").value, 0.13, 0.02);
  EXPECT_GT(figure(r, "mean chest (shoulders) rise").value, figure(r, "mean torso rise per push-up").value);
  EXPECT_TRUE(r.pass);
  // a bar of 0.2 m for the torso's rise is out of its reach: no push-up counts
  run.card.as<ai::PushUpCard>()->rise = 0.2;
  const ai::CardResult high = t.groundCard(pushup, run);
  EXPECT_EQ(figure(high, "mean push-ups per episode").value, 0.0);
  EXPECT_FALSE(high.pass);
}

// the crawl's prior alone (zero network output) after prone's lying down: on hands and knees under the tunnel's
// 0.6 m ceiling it crawls forward (about 0.3 m/s along its heading, by itself); without its gait the robot
// stays where it lay and fails
TEST(CrawlCard, ThePriorAloneCrawlsForwardUnderTheCeilingAndStandingStillFails) {
  Tree t;
  ai::SkillSpec crawl = *t.tree.find("crawl");
  ai::CardRun run = Tree::twoEpisodes(crawl, 3);
  run.card.as<ai::CrawlCard>()->distance = 1.5;  // 1.5 m within 6 s
  crawl.randomisation.friction = {1.0,
                                  1.0};  // the prior alone is friction-sensitive (docs/skills/crawl.md): at 1 it crawls
  const ai::CardResult r = t.groundCard(crawl, run);
  EXPECT_EQ(figure(r, "lying face down when").value, 100.0);
  EXPECT_GT(figure(r, "mean progress along the tunnel").value, 1.0);
  EXPECT_GT(figure(r, "mean speed over the").value, 0.2);  // from the switch: the 1.5 s onto all fours included
  crawl.prior.kind = robot::PriorDef::Kind::None;          // zero output only holds the default pose: it does not crawl
  const ai::CardResult still = t.groundCard(crawl, run);
  EXPECT_LT(figure(still, "mean progress along the tunnel").value, 0.3);
  EXPECT_EQ(figure(still, "episodes crawling").value, 0.0);
  EXPECT_FALSE(still.pass);
}

// a cycle twisted 0.05 rad at the waist turns the prior's crawl left (docs/skills/crawl.md: about 3 deg/s); the card's
// steering, through the prior's turn term (the shipped one), turns it back toward the tunnel's axis as a player would
TEST(CrawlCard, TheCardSteersATurningCrawlBackTowardTheAxis) {
  Tree t;
  ai::SkillSpec crawl = *t.tree.find("crawl");
  crawl.randomisation.friction = {1.0, 1.0};
  for (robot::PriorDef::Keyframe& key : crawl.prior.keyframes)
    if (key.tick >= crawl.prior.cycleStartTick) key.offset[12] += 0.05;  // waist_yaw: a left turn on every cycle
  ai::CardRun run = Tree::twoEpisodes(crawl, 3);
  run.card.as<ai::CrawlCard>()->distance = 2.0;
  run.card.as<ai::CrawlCard>()->episodeSeconds = 14.0;
  run.card.as<ai::CrawlCard>()->steer = 0.0;  // nobody steers
  const ai::CardResult drifting = t.groundCard(crawl, run);
  run.card.as<ai::CrawlCard>()->steer = 1.0;
  const ai::CardResult steered = t.groundCard(crawl, run);
  const double before = figure(drifting, "heading off the tunnel's axis at the end, mean (left").value;
  const double after = figure(steered, "heading off the tunnel's axis at the end, mean (left").value;
  std::printf("heading at the end: %.1f deg drifting, %.1f deg steered\n", before, after);
  EXPECT_GT(before, 10.0);  // left, as the twist turns it
  EXPECT_LT(std::abs(after), 0.5 * before);
}
