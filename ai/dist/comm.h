// comm.h — the processes that train one run together (data-parallel PPO over MPI ranks, as DeepMimic and OpenAI's
// baselines scale it). A run under `mpirun -np N` has N ranks: each steps its share of the environments, and the
// collectives below keep every rank's policy, normaliser, optimiser and random streams identical. Without mpirun
// (or in a build without MPI) the process is one rank and every collective is the identity, so a single process runs
// exactly the arithmetic it ran before MPI existed.
//
// Every reduction is deterministic: a sum is added in rank order by one rank per element (an alltoall of chunks, a
// sum in rank order, an allgather: the bytes of a ring allreduce), so every rank gets the same bits, run after run.
// MPI_Allreduce promises neither.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace ai::dist {

class Comm {
 public:
  /// A single process: rank 0 of 1.
  Comm() = default;

  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Rank 0 writes the log, checkpoints, exports and cards, and prints.
  bool isRoot() const { return rank_ == 0; }

  /// Element-wise sum over the ranks into data (count entries on every rank), added in rank order.
  void sum(float* data, size_t count) const;
  void sum(double* data, size_t count) const;
  double sum(double value) const {
    sum(&value, 1);
    return value;
  }
  /// Every rank's bytes (any length), in rank order.
  std::vector<std::string> gather(const std::string& mine) const;
  /// True on every rank when flag is true on any rank.
  bool any(bool flag) const;
  /// Ends every rank of the run with this exit code (a rank that failed alone would leave the others waiting).
  [[noreturn]] void abort(int code) const;

 private:
  friend const Comm& world();
  int rank_ = 0;
  int size_ = 1;
};

/// *comm, or a single process when comm is null (the default of every option that takes the ranks).
const Comm& orOneProcess(const Comm* comm);

/// The process's ranks: MPI_COMM_WORLD when started by mpirun in a build with MPI (MPI_Init on first use, finalised
/// at exit), else a single process. Throws engine::Error when started by mpirun in a build without MPI: each rank
/// would train the whole run on its own and write over the others' files.
const Comm& world();

/// The threads a rank should use by default: the machine's cores divided by the ranks on it (Open MPI's
/// OMPI_COMM_WORLD_LOCAL_SIZE, else every rank counts as local), at least 1.
int threadsPerRank();

/// True when this build can run under mpirun (cmake -DTREELEARN_MPI=ON, as scripts/setup.sh builds).
bool builtWithMpi();

/// The share of `total` environments that rank `rank` of `size` steps: [first, first + count). The total must divide
/// evenly (throws engine::Error naming the numbers otherwise).
struct EnvShare {
  int first = 0;
  int count = 0;
};
EnvShare envShare(int total, const Comm& comm);

}  // namespace ai::dist
