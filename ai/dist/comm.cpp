// comm.cpp — single-process collectives, and MPI's when built with TREELEARN_MPI (see comm.h).
#include "ai/dist/comm.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "engine/core/error.h"

#ifdef TREELEARN_MPI
#include <mpi.h>
#endif

namespace ai::dist {
namespace {

// started by a launcher that expects MPI_Init: Open MPI's mpirun, or a PMI launcher (Slurm's srun, MPICH's hydra)
bool launchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

#ifdef TREELEARN_MPI
template <typename T>
MPI_Datatype mpiType();
template <>
MPI_Datatype mpiType<float>() {
  return MPI_FLOAT;
}
template <>
MPI_Datatype mpiType<double>() {
  return MPI_DOUBLE;
}

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw engine::Error(std::string("MPI: ") + what + " failed");
}

// the deterministic allreduce: rank k sums chunk k of every rank's vector in rank order, then all chunks are gathered
template <typename T>
void sumInRankOrder(T* data, size_t count, int size) {
  const size_t chunk = (count + size_t(size) - 1) / size_t(size);
  std::vector<T> padded(chunk * size_t(size), T(0)), received(chunk * size_t(size)), mine(chunk);
  std::copy(data, data + count, padded.begin());
  check(
      MPI_Alltoall(padded.data(), int(chunk), mpiType<T>(), received.data(), int(chunk), mpiType<T>(), MPI_COMM_WORLD),
      "alltoall");
  for (size_t k = 0; k < chunk; ++k) {
    T s = received[k];
    for (int r = 1; r < size; ++r) s += received[size_t(r) * chunk + k];
    mine[k] = s;
  }
  check(MPI_Allgather(mine.data(), int(chunk), mpiType<T>(), padded.data(), int(chunk), mpiType<T>(), MPI_COMM_WORLD),
        "allgather");
  std::copy(padded.begin(), padded.begin() + std::ptrdiff_t(count), data);
}
#endif

}  // namespace

const Comm& orOneProcess(const Comm* comm) {
  static const Comm single;
  return comm ? *comm : single;
}

int threadsPerRank() {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  const int ranks = std::max(1, local ? std::atoi(local) : world().size());
  return std::max(1, int(cores) / ranks);
}

bool builtWithMpi() {
#ifdef TREELEARN_MPI
  return true;
#else
  return false;
#endif
}

const Comm& world() {
  static const Comm comm = [] {
    Comm c;
    if (!launchedByMpi()) return c;
#ifdef TREELEARN_MPI
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      check(MPI_Init(nullptr, nullptr), "MPI_Init");
      std::atexit([] {
        int finalised = 0;
        MPI_Finalized(&finalised);
        if (!finalised) MPI_Finalize();
      });
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &c.rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &c.size_);
    return c;
#else
    throw engine::Error(
        "started by mpirun, but this treelearn was built without MPI: every rank would run the whole job on its own. "
        "Build with MPI (scripts/setup.sh does; by hand, cmake -DTREELEARN_MPI=ON) or run without mpirun");
#endif
  }();
  return comm;
}

// one process: the identity
template <typename T>
void sumOverRanks(T* data, size_t count, int size) {
#ifdef TREELEARN_MPI
  if (size > 1) sumInRankOrder(data, count, size);
#else
  (void)data, (void)count, (void)size;
#endif
}

void Comm::sum(float* data, size_t count) const { sumOverRanks(data, count, size_); }
void Comm::sum(double* data, size_t count) const { sumOverRanks(data, count, size_); }

std::vector<std::string> Comm::gather(const std::string& mine) const {
  if (size_ == 1) return {mine};
  std::vector<std::string> out(static_cast<size_t>(size_));
#ifdef TREELEARN_MPI
  int length = int(mine.size());
  std::vector<int> lengths(static_cast<size_t>(size_)), offsets(static_cast<size_t>(size_));
  check(MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, MPI_COMM_WORLD), "allgather");
  int total = 0;
  for (int r = 0; r < size_; ++r) offsets[size_t(r)] = total, total += lengths[size_t(r)];
  std::string all(size_t(total), '\0');
  check(MPI_Allgatherv(mine.data(), length, MPI_BYTE, all.data(), lengths.data(), offsets.data(), MPI_BYTE,
                       MPI_COMM_WORLD),
        "allgatherv");
  for (int r = 0; r < size_; ++r) out[size_t(r)] = all.substr(size_t(offsets[size_t(r)]), size_t(lengths[size_t(r)]));
#endif
  return out;
}

bool Comm::any(bool flag) const {
  if (size_ == 1) return flag;
  int mine = flag ? 1 : 0, result = mine;
#ifdef TREELEARN_MPI
  check(MPI_Allreduce(&mine, &result, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD), "allreduce");
#endif
  return result != 0;
}

void Comm::abort(int code) const {
#ifdef TREELEARN_MPI
  if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

EnvShare envShare(int total, const Comm& comm) {
  if (total % comm.size() != 0)
    throw engine::Error(std::to_string(total) + " environments cannot be shared evenly by " +
                        std::to_string(comm.size()) + " ranks: give --envs a multiple of the rank count");
  const int count = total / comm.size();
  return {comm.rank() * count, count};
}

}  // namespace ai::dist
