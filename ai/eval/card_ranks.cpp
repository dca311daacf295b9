// card_ranks.cpp — see card_ranks.h.
#include "ai/eval/card_ranks.h"

#include <memory>

#include "engine/core/error.h"

namespace ai {

EpisodeShare episodeShare(int episodes, const dist::Comm& comm) {
  const int n = comm.size(), r = comm.rank();
  const int first = int(int64_t(episodes) * r / n), end = int(int64_t(episodes) * (r + 1) / n);
  return {first, end - first};
}

PolicyFn policyOverRanks(const PolicyFn& policy, const dist::Comm& comm, int episodes) {
  if (comm.size() == 1) return policy;
  const EpisodeShare share = episodeShare(episodes, comm);
  auto all = std::make_shared<Eigen::MatrixXf>(), actions = std::make_shared<Eigen::MatrixXf>();
  return [policy, &comm, share, episodes, all, actions](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) {
    const std::string mine(reinterpret_cast<const char*>(obs.data()), size_t(obs.size()) * sizeof(float));
    all->resize(obs.rows(), episodes);
    size_t at = 0;
    for (const std::string& b : comm.gather(mine)) {
      if (at * sizeof(float) + b.size() > size_t(all->size()) * sizeof(float))
        throw engine::Error("a card over the ranks: the ranks' observations outnumber the card's episodes");
      std::memcpy(all->data() + at, b.data(), b.size());
      at += b.size() / sizeof(float);
    }
    if (at != size_t(all->size()))
      throw engine::Error("a card over the ranks: the ranks' observations do not cover the card's episodes");
    policy(*all, actions.get());
    *act = actions->middleCols(share.first, share.count);
  };
}

}  // namespace ai
