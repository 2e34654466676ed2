#include "apps/ranks.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#ifdef RUBCONT_MPI
#include <mpi.h>
#endif

namespace rubcont {

bool LaunchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

void Unpacker::Take(char* to, size_t n) {
  if (n > buffer_.size() - at_) {
    throw std::runtime_error("Unpacker: message shorter than its contents (ranks out of step)");
  }
  std::copy_n(buffer_.data() + at_, n, to);
  at_ += n;
}

Ranks& Ranks::World() {
  static Ranks world;
  return world;
}

// Debian's sequential MUMPS (under Ipopt: libdmumps_seq, libmumps_common_seq) exports dummy
// MPI_Init, MPI_Comm_rank, MPI_Finalize and MPI_Wtime, and it comes first in the link: every rank
// was rank 0 of 2 (measured). Those four are called by their profiling names (PMPI_), which only
// Open MPI defines.
// MPI may be running already: a Python script that imported mpi4py first (issue 50 item 8)
// initialised it, and a second MPI_Init_thread is an error that aborts every rank. Then rubcont
// uses it and leaves finalising to its owner.
Ranks::Ranks() {
#ifdef RUBCONT_MPI
  if (!LaunchedByMpi()) return;
  int initialized = 0;
  PMPI_Initialized(&initialized);
  if (initialized == 0) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    owns_mpi_ = true;
  }
  PMPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  mpi_ = true;
#endif
}

Ranks::~Ranks() {
#ifdef RUBCONT_MPI
  int finalized = 0;
  if (owns_mpi_ && PMPI_Finalized(&finalized) == MPI_SUCCESS && finalized == 0) PMPI_Finalize();
#endif
}

std::string Ranks::Describe() const {
  return mpi_ ? fmt::format("MPI, rank {} of {}", rank_, size_) : std::string("one process");
}

void Ranks::Barrier() const {
#ifdef RUBCONT_MPI
  if (mpi_) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

std::vector<std::string> Ranks::GatherToRoot(const std::string& mine) const {
  return Gather(mine, false);
}

std::vector<std::string> Ranks::AllGather(const std::string& mine) const {
  return Gather(mine, true);
}

std::vector<std::string> Ranks::Gather(const std::string& mine, bool everywhere) const {
  if (!mpi_) return {mine};
#ifdef RUBCONT_MPI
  const int length = static_cast<int>(mine.size());
  std::vector<int> lengths(static_cast<size_t>(size_));
  if (everywhere) {
    MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, MPI_COMM_WORLD);
  } else {
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  }
  std::vector<int> offsets(static_cast<size_t>(size_), 0);
  int total = 0;
  for (int r = 0; r < size_; ++r) {
    offsets[static_cast<size_t>(r)] = total;
    total += lengths[static_cast<size_t>(r)];
  }
  const bool receives = everywhere || rank_ == 0;
  std::string all(receives ? static_cast<size_t>(total) : 0, '\0');
  if (everywhere) {
    MPI_Allgatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(),
                   MPI_CHAR, MPI_COMM_WORLD);
  } else {
    MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
                0, MPI_COMM_WORLD);
  }
  if (!receives) return {};
  std::vector<std::string> parts;
  for (int r = 0; r < size_; ++r) {
    parts.push_back(all.substr(static_cast<size_t>(offsets[static_cast<size_t>(r)]),
                               static_cast<size_t>(lengths[static_cast<size_t>(r)])));
  }
  return parts;
#else
  return {mine};
#endif
}

JobRunner RankJobs(const Ranks& ranks, int threads) {
  if (ranks.size() == 1) return ThreadJobs(threads);
  return [&ranks, threads](int n, const std::function<std::string(int)>& job) {
    const int size = ranks.size(), rank = ranks.rank();
    const int mine = n > rank ? (n - rank + size - 1) / size : 0;
    const std::vector<std::string> local =
        ThreadJobs(threads)(mine, [&](int k) { return job(rank + k * size); });
    Packer packer;
    for (const std::string& r : local) packer.Put(r);
    const std::vector<std::string> parts = ranks.AllGather(packer.str());
    std::vector<std::string> results(static_cast<std::size_t>(n));
    for (int r = 0; r < size; ++r) {
      Unpacker unpacker(parts[static_cast<std::size_t>(r)]);
      for (int i = r; i < n; i += size) results[static_cast<std::size_t>(i)] = unpacker.GetString();
    }
    return results;
  };
}

}  // namespace rubcont
