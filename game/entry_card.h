// entry_card.h — the play-entry card: a skill started from the states in which play handed it over
// (robot/entry_state.h), on the level each was recorded on, with the keys play pressed after it. It sits beside
// the skill's own card (which starts from the spawn stance or its parent's handover) so that a gap between the card
// and play shows in the numbers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot/entry_state.h"
#include "robot/robot_model.h"
#include "robot/skill_runtime.h"

namespace game {

/// How long past its recorded segment an entry goes on (a segment that ended in a fall in play ends there) [ticks].
constexpr int64_t kEntryCardMarginTicks = 200;

/// One entry on the card.
struct EntryTrial {
  int64_t ticks = 0;        ///< ticks the skill drove
  bool fell = false;        ///< it fell while it drove
  bool handedOver = false;  ///< it handed over to another skill (the segment's keys asked for one)
};

struct EntryCardResult {
  std::string skill;
  std::vector<EntryTrial> trials;  ///< in the entries' order
  int held() const;                ///< trials without a fall
  double percent() const;          ///< held() in percent of the trials (0 with none)
  int fellInPlay = 0;              ///< of the entries, how many ended in a fall in play
};

/// Runs the card over `entries` (all of `skill`; others are skipped) with the loaded skills. Each entry starts on its
/// level (loaded once per level file, its ghosts, rules and time limit taken out: the card measures the skill, not
/// the chase) at the entry's state and replays the segment's key events; the skill holds when it drives until it
/// hands over, or for its segment and kEntryCardMarginTicks more, without a fall. Deterministic; `threads` run
/// entries side by side. Throws engine::Error if a level does not load or an entry does not fit it.
EntryCardResult runEntryCard(const std::vector<robot::EntryState>& entries, const std::string& skill,
                             const robot::SkillSet& skills, const robot::RobotModel& model, int threads);

/// "held 17 of 20 play entries (85.0 %); in play 4 of them fell".
std::string entryCardLine(const EntryCardResult& result);

}  // namespace game
