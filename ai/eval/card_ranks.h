// card_ranks.h — a report card's episodes split over the ranks of an mpirun (ai/dist/comm.h), with the card's figures
// the same bits as one process's: every rank steps its share of the episodes' physics, but the policy runs on every
// episode's observations at once (gathered each tick), since a batched product gives a column other bits when the
// batch has another width; each episode's outcome (a plain struct) is then gathered, and every rank computes the
// figures from all of them.
#pragma once

#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "ai/dist/comm.h"
#include "ai/eval/velocity_card.h"

namespace ai {

/// Rank r's episodes of n: [first, first + count), the remainder spread over the first ranks.
struct EpisodeShare {
  int first = 0;
  int count = 0;
};
EpisodeShare episodeShare(int episodes, const dist::Comm& comm);

/// policy for a rank's columns of a batch of `episodes` columns split by episodeShare: each call gathers every rank's
/// columns, runs policy on the whole batch and keeps this rank's actions. Every rank must call it alike (a
/// collective). One process: policy itself.
PolicyFn policyOverRanks(const PolicyFn& policy, const dist::Comm& comm, int episodes);

/// Every rank's outcomes, in rank order (so in episode order when each rank holds its episodeShare).
template <typename Outcome>
std::vector<Outcome> gatherOutcomes(const std::vector<Outcome>& mine, const dist::Comm& comm) {
  static_assert(std::is_trivially_copyable_v<Outcome>, "an outcome travels as bytes");
  if (comm.size() == 1) return mine;
  std::string bytes(mine.size() * sizeof(Outcome), '\0');
  if (!mine.empty()) std::memcpy(bytes.data(), mine.data(), bytes.size());
  std::vector<Outcome> all;
  for (const std::string& b : comm.gather(bytes)) {
    const size_t at = all.size(), count = b.size() / sizeof(Outcome);
    all.resize(at + count);
    if (count > 0) std::memcpy(static_cast<void*>(&all[at]), b.data(), count * sizeof(Outcome));
  }
  return all;
}

}  // namespace ai
