// checkpoint.h — binary files of training state: checkpoint.bin (everything needed to continue a run
// bit-identically) and policy files such as best.bin (a PolicyState with where it came from). Both share
// one container: 8-byte magic, u32 version, u64 payload length, u64 FNV-1a of the payload, payload.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "ai/nn/adam.h"
#include "ai/ppo/ppo.h"

namespace ai {

class ByteWriter;
class ByteReader;

/// Container version written by this build; loaders reject others.
constexpr uint32_t kCheckpointVersion = 1;

/// Where a saved policy came from.
struct PolicyInfo {
  uint64_t configHash = 0;                                  ///< ppoConfigHash of the run's config
  int64_t iteration = 0;                                    ///< completed iterations when saved
  int64_t envSteps = 0;                                     ///< environment steps when saved
  double score = std::numeric_limits<double>::quiet_NaN();  ///< evaluation score (NaN if none)
};

/// The complete state of a run at an iteration boundary.
struct TrainerCheckpoint {
  uint64_t configHash = 0;                                      ///< ppoConfigHash of the run's config
  uint64_t seed = 0;                                            ///< the run seed
  int64_t totalSteps = 0;                                       ///< the run's step budget (the schedules depend on it)
  int64_t iteration = 0;                                        ///< completed iterations
  int64_t envSteps = 0;                                         ///< environment steps so far
  double bestScore = -std::numeric_limits<double>::infinity();  ///< best evaluation score so far (-inf: none)
  PolicyState policy;                                           ///< actor, critic, normaliser, log-std
  Adam optimizer;                                               ///< moments and step count
  std::string rngState;  ///< the trainer's std::mt19937_64, as written by operator<<
  std::string envState;  ///< VecEnv::saveState()
  /// the adaptive learning rate (PpoUpdater::adaptiveLearningRate; NaN: none). Written last; a checkpoint from
  /// before adaptive rates ends without it and reads as NaN.
  double adaptiveLearningRate = std::nan("");
};

/// Appends / reads a PolicyState (weights, normaliser statistics, log-std).
void writePolicyState(ByteWriter* out, const PolicyState& policy);
PolicyState readPolicyState(ByteReader* in);

/// Writes a policy file atomically (magic "TLPOLICY"). Throws engine::Error on I/O failure.
void savePolicyState(const std::string& path, const PolicyState& policy, const PolicyInfo& info = {});
/// Reads a policy file; fills info if given. Throws engine::Error "path: ..." on a missing, truncated,
/// corrupted or foreign file.
PolicyState loadPolicyState(const std::string& path, PolicyInfo* info = nullptr);

/// Writes a checkpoint atomically (magic "TLCHKPT1"). Throws engine::Error on I/O failure.
void saveCheckpoint(const std::string& path, const TrainerCheckpoint& checkpoint);
/// Reads and validates a checkpoint. Throws engine::Error "path: ..." as loadPolicyState.
TrainerCheckpoint loadCheckpoint(const std::string& path);

}  // namespace ai
