// card_def.h — a skill's report card as the tree file's [skill.NAME.card] table gives it: one type per kind of card.
// The kinds that drive the skill with commands from the spawn stance (or a lead-in) share DrivenCard; the kinds
// entered lying down under the parent share LyingCard. Measured by ai::runSkillCard; the keys of each kind are listed
// in assets/skills/README.md. A bar < 0 is not checked.
#pragma once

#include <array>
#include <type_traits>
#include <utility>
#include <variant>

#include "robot/skill_tree.h"

namespace ai {

using robot::Range;

/// Randomised episodes in which the card drives the skill with commands (velocity, height, balance, stairs, jump, kick
/// and prone cards), the tracking bars and the standing episodes.
struct DrivenCard {
  double episodeSeconds = 20;                     ///< each episode's length
  double segmentSeconds = 20;                     ///< a new command this often (default: once per episode)
  double settleSeconds = 1;                       ///< tracking is not counted this long after a command change
  Range vx, vy, wz;                               ///< command ranges
  Range amplitude;                                ///< amplitude command range (drawn with every command)
  std::array<double, 4> mix{0.4, 0.2, 0.2, 0.2};  ///< chance of a forward, sideways, turn or zero command
  bool pushes = true;                             ///< pushes as in the skill's randomisation
  /// the card's own push strength [m/s] (lo < 0: the randomisation's), so that training can push harder without
  /// changing the card
  Range pushSpeed{-1, -1};
  double pushEverySeconds = -1;  ///< the card's own push interval [s] (< 0: the randomisation's), likewise
  bool ramp = false;             ///< commands ramp at the keyboard's rates (ai::CommandDraws::ramp)
  int standEpisodes = 0;         ///< zero-command episodes without pushes (drift)
  double standSeconds = 10;
  double noFallPercent = -1;  ///< bar: episodes without a fall [%] (>=)
  double speedError = -1;     ///< bar: mean |v - v_cmd| [m/s] (<=)
  double yawError = -1;       ///< bar: mean |wz - wz_cmd| [rad/s] (<=)
  double standDrift = -1;     ///< bar: max drift of a standing episode [m] (<)
  /// each episode starts as the skill's training handover episodes do (from training.handover_from or the parent,
  /// through the skills in between), that is as play enters the skill, rather than from the spawn stance; a lead-in
  /// that falls is drawn again (up to 5 times, then the episode counts as a fall). A branch's velocity, height,
  /// balance, jump or kick card only.
  bool leadIn = false;
};

/// Episodes that start with the parent skill lying down (standup, push-up and crawl cards).
struct LyingCard {
  Range lieSeconds{3.0, 5.5};  ///< the parent lies down this long (drawn per episode) [s] before the switch
};

/// Tracking of vx / vy / wz commands (walk, run).
struct VelocityCard : DrivenCard {};

/// Tracking of the pelvis height that the amplitude command asks for (squat).
struct HeightCard : DrivenCard {
  double heightError = -1;  ///< bar: mean |h - h_target(amplitude)| of the pelvis [m] (<=)
};

/// The right foot lifted (amplitude 1 held): success = lifted for `seconds` in one go without a fall.
struct BalanceCard : DrivenCard {
  double liftHeight = 0.08;  ///< the right sole counts as lifted at this height [m] (the left foot on the ground)
  double liftSeconds = 5;
};

/// A staircase drawn anew for each episode, in training ([terrain] rise, tread, steps) and on the stairs card: the
/// rise, the tread and the number of risers up (as many down) each uniform within its range. Not drawn when rise.hi
/// is 0.
struct StairsDraw {
  Range rise{0, 0};   ///< [m]
  Range tread{0, 0};  ///< [m]
  Range steps{0, 0};  ///< whole numbers, both ends included
  bool drawn() const { return rise.hi > 0; }
};

/// Up and down the skill's staircase at `stepHeight`; success = past its far end without a fall.
struct StairsCard : DrivenCard {
  double stepHeight = 0.15;  ///< [m]
  /// > 0: the card keeps the robot square to the staircase as a player would, with play's heading-hold law
  /// (robot::shapeCommand): wz = -steer x the heading off +X [rad], at most kHeadingMaxRate and the wz range.
  double steer = 0.0;
  /// Stairs drawn anew for each episode (rise, tread, steps; then stepHeight is unused), and the robot's start
  /// within +- heading of square to them (heading_deg) [rad].
  StairsDraw draw;
  double heading = 0.2;
};

/// `jumps` flights in a row (both feet off the ground), each with the pelvis apex at least `height` above its height
/// at the start, and no fall.
struct JumpCard : DrivenCard {
  double height = 0.10;  ///< [m]
  int jumps = 3;
};

/// The ball leaves at >= `speed` within `angleDegrees` of the target direction and the robot is still up at the end.
struct KickCard : DrivenCard {
  double speed = 2.5;  ///< [m/s]
  double angleDegrees = 15;
};

/// From standing: the torso link below `height` with the forward pitch within `pitch`, reached within `seconds` and
/// still so at the end of the episode, without a fall; the peak pelvis acceleration (the impact) is reported.
struct ProneCard : DrivenCard {
  double seconds = 3;
  double height = 0.35;  ///< [m]
  Range pitch{70, 110};  ///< [deg]
};

/// Lies down under the parent, then the switch to this skill as the runtime makes it; success = standing
/// (robot::hasStoodUp) within `riseSeconds` of the switch, then the `up` skill (walk) taking over there and
/// `afterSeconds` with no fall.
struct StandUpCard : LyingCard {
  double riseSeconds = 5;
  double afterSeconds = 3;
};

/// Lies down under the parent, then the skill runs `episodeSeconds`; success = at least `pushUps` rises of the torso
/// link's origin by >= `rise` (trough to crest) and no fall.
struct PushUpCard : LyingCard {
  double episodeSeconds = 20;
  int pushUps = 3;
  double rise = 0.08;  ///< [m]
};

/// Lies down under the parent, then a tunnel (the skill's ceiling terrain, `width` wide) goes over the robot along its
/// heading and the skill crawls at a forward command drawn from `vx`; success = `distance` along the tunnel at a mean
/// speed of at least `speed`, inside the tunnel and without a fall.
struct CrawlCard : LyingCard {
  double episodeSeconds = 20;
  Range vx;
  double distance = 5.0;  ///< [m]
  double speed = 0.25;    ///< [m/s]
  /// > 0: the card steers as a player would: wz = -steer x (heading off the tunnel's axis [rad] + 0.5 x offset across
  /// it [m]), that error averaged over the last second (the gait's rock swings the heading within each cycle), within
  /// the skill's wz range [rad/s per rad]
  double steer = 0.0;
};

/// The kinds, in the order of CardDef::Kinds' alternatives.
enum class CardKind { None, Velocity, Height, Balance, Stairs, Jump, Kick, Prone, StandUp, PushUp, Crawl };

/// A skill's report card: what every kind has, and the kind's own type.
struct CardDef {
  using Kinds = std::variant<std::monostate, VelocityCard, HeightCard, BalanceCard, StairsCard, JumpCard, KickCard,
                             ProneCard, StandUpCard, PushUpCard, CrawlCard>;
  int episodes = 50;           ///< randomised episodes (friction, mass, pushes as in training)
  double successPercent = -1;  ///< bar: episodes that succeed [%] (>=); not a velocity or height card's
  Kinds card;                  ///< std::monostate: the skill has no card

  CardKind kind() const { return CardKind(card.index()); }
  /// The kind's own type, or nullptr when the card is of another kind.
  template <class T>
  const T* as() const {
    return std::get_if<T>(&card);
  }
  template <class T>
  T* as() {
    return std::get_if<T>(&card);
  }
  /// The driven part of a velocity, height, balance, stairs, jump, kick or prone card; nullptr for the other kinds.
  const DrivenCard* driven() const {
    return std::visit(
        [](const auto& c) -> const DrivenCard* {
          if constexpr (std::is_base_of_v<DrivenCard, std::decay_t<decltype(c)>>)
            return &c;
          else
            return nullptr;
        },
        card);
  }
  DrivenCard* driven() { return const_cast<DrivenCard*>(std::as_const(*this).driven()); }
  /// The lying part of a standup, push-up or crawl card; nullptr for the other kinds.
  const LyingCard* lying() const {
    return std::visit(
        [](const auto& c) -> const LyingCard* {
          if constexpr (std::is_base_of_v<LyingCard, std::decay_t<decltype(c)>>)
            return &c;
          else
            return nullptr;
        },
        card);
  }
};

}  // namespace ai
