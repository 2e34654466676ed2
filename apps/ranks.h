// The processes of an MPI run (`mpirun -n N rubcont ...`), or this one process.
//
// MPI is initialised only when rubcont was built with it (RUBCONT_MPI) and the process was started
// by an MPI launcher (its environment says so: Open MPI's OMPI_COMM_WORLD_SIZE, PMI_SIZE or
// PMIX_RANK). Otherwise there is one rank and every call is a no-op: the commands run exactly as
// without MPI. MPI_Finalize runs at exit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "solvers/parallel.h"

namespace rubcont {

// Values into one string and back, to send over GatherToRoot (same machine type on every rank).
class Packer {
 public:
  template <class T>
  void Put(const T& value) {  // trivially copyable
    buffer_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void Put(const std::string& text) {
    Put(static_cast<uint64_t>(text.size()));
    buffer_ += text;
  }
  const std::string& str() const { return buffer_; }

 private:
  std::string buffer_;
};

class Unpacker {
 public:
  explicit Unpacker(const std::string& buffer) : buffer_(buffer) {}
  template <class T>
  T Get() {
    T value;
    Take(reinterpret_cast<char*>(&value), sizeof(T));
    return value;
  }
  std::string GetString() {
    std::string text(static_cast<size_t>(Get<uint64_t>()), '\0');
    Take(text.data(), text.size());
    return text;
  }
  bool done() const { return at_ == buffer_.size(); }

 private:
  void Take(char* to, size_t n);
  const std::string& buffer_;
  size_t at_ = 0;
};

class Ranks {
 public:
  // The world communicator (initialised on first use).
  static Ranks& World();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool mpi() const { return mpi_; }
  // "MPI, rank r of N" or "one process".
  std::string Describe() const;

  void Barrier() const;
  // Every rank's `mine`, in rank order, at rank 0; the other ranks get an empty vector.
  std::vector<std::string> GatherToRoot(const std::string& mine) const;
  // Every rank's `mine`, in rank order, at every rank.
  std::vector<std::string> AllGather(const std::string& mine) const;

  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;
  ~Ranks();

 private:
  Ranks();
  // MPI_Gatherv (root 0) or MPI_Allgatherv of the strings, split back per rank where received.
  std::vector<std::string> Gather(const std::string& mine, bool everywhere) const;
  int rank_ = 0;
  int size_ = 1;
  bool mpi_ = false;
  bool owns_mpi_ = false;  // MPI was initialised here (not before, by mpi4py): finalise it here
};

// The process was started by mpirun / srun (their environment variables are set).
bool LaunchedByMpi();

// Jobs over the ranks and, within each, `threads` threads: rank r runs the jobs r, r + N, r + 2N, …
// and every rank receives every result, in order (AllGather). With one rank it is ThreadJobs.
JobRunner RankJobs(const Ranks& ranks, int threads);

}  // namespace rubcont
