// Claims on jobs that processes share through a directory, on one host or many (the ranks of an
// MPI run, the allocations of a cluster, the tasks of a Slurm array): who runs which job, and a
// take-over of the claims whose owner has stopped.
//
// A job's claim is a small file `<stem>.<g>` (stem `<out>/<job>.claim`, generation g = 0, 1, …)
// naming its owner (ClaimOwner: host, boot, pid and the process's start, the Slurm allocation, the
// rank, the heartbeat interval). Its modification time is the heartbeat: a thread of the owner
// touches it every `heartbeat interval` seconds while the job runs (HeldClaim). A claim is taken
// over only when
//   - it is stale: its heartbeat is older than ClaimOptions::stale_after_s (and than three of its
//     owner's heartbeat intervals, should the owner have used a longer one), or
//   - its owner is provably dead: the same host and boot, and the pid no longer exists or belongs to
//     a process started at another time (the pid was reused).
// A live claim (fresh heartbeat, owner alive or elsewhere) is never taken over.
//
// Taking a claim is atomic and exclusive through link(2): the owner's record is written to a
// temporary of its own and hard-linked to the name `<stem>.<g>`; link fails with EEXIST when the
// name exists, so of any number of processes (on any host of a POSIX or NFSv3+ file system) exactly
// one creates it, with its content already complete. A free job is taken by creating generation 0;
// a stale or dead claim of generation g by creating g + 1, which leaves the old file in place: two
// processes that both found g stale race for the same new name and one wins; nobody ever removes a
// claim that another may still be judging. The owner of the newest generation removes the job's
// claim files when it lets go; an owner that was taken over from leaves its file to the new owner.
//
// The heartbeat is a thread rather than the job's progress points: it beats whatever the job does
// (a branch set or one row of a map has no progress point for minutes), it stops exactly when the
// process stops (killed, or suspended by the scheduler), and the commands need no hook. A job that
// hangs in a live process keeps its claim; the allocation's time limit ends it.
//
// Clocks: the age of a heartbeat is this host's clock minus the file's modification time, so hosts
// are assumed to agree within a small fraction of stale_after_s (NTP: milliseconds), and a file
// system's attribute cache (NFS: up to 60 s, nfs(5) acregmax) delays what a heartbeat shows; the
// default threshold covers both (docs/robustness.md, "Batch on a cluster").
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace rubcont {

struct ClaimOptions {
  // A claim whose heartbeat is older than this is stale and may be taken over, seconds, in
  // (0, 1e7]. The owner beats every stale_after_s / 10. Default 300 s: ten beats of 30 s, so that a
  // live owner is not judged stale through NFS's attribute cache (up to 60 s, nfs(5) acregmax),
  // clock skew and a late beat, while a killed allocation's job is taken over 5 minutes later.
  // Beats are late by scheduling only: measured 2026-11-28 on this 2-core machine at load average
  // 8, 107 beats of 0.1 s came at most 28 ms late (median 0 ms; docs/robustness.md).
  double stale_after_s = 300.0;
  double HeartbeatSeconds() const { return stale_after_s / 10.0; }
  void Validate() const;  // throws std::invalid_argument naming --stale-after, its value and rule
};

// Who holds a claim, as its file records it.
struct ClaimOwner {
  std::string host;          // gethostname
  std::string boot_id;       // /proc/sys/kernel/random/boot_id: a reboot is a new boot
  int64_t pid = 0;
  uint64_t start_ticks = 0;  // the process's start, clock ticks after boot (/proc/PID/stat); 0 unknown
  std::string started;       // the same as UTC time, for people ("2026-11-28T22:53:29Z")
  std::string allocation;    // "<SLURM_ARRAY_JOB_ID>_<SLURM_ARRAY_TASK_ID>", else SLURM_JOB_ID, else ""
  int rank = 0;              // MPI rank
  double heartbeat_s = 0.0;  // its heartbeat interval, seconds (0: unknown)

  // "pid 4242 on node12 (Slurm job 123_4, rank 0, started 2026-11-28T22:53:29Z)"
  std::string Describe() const;
};

// This process as an owner.
ClaimOwner ThisProcess(int rank, double heartbeat_s);

enum class OwnerLife {
  kAlive,    // this host and boot, the pid's process started when the owner did
  kDead,     // this host: another boot, or no process with the pid, or one started at another time
  kUnknown,  // another host (or the record says too little): only the heartbeat can tell
};
OwnerLife LifeOf(const ClaimOwner& owner);

// What a look at a job's claim found.
struct ClaimState {
  int generation = -1;            // the newest claim file's generation; -1 none (the job is free)
  std::filesystem::path file;     // <stem>.<generation>
  bool owner_known = false;       // the file held a readable owner record
  ClaimOwner owner;
  double heartbeat_age_s = 0.0;   // seconds since the file was last touched (≥ 0)
  int64_t heartbeat_ns = 0;       // the modification time itself, to see a heartbeat move
};
ClaimState LookAtClaim(const std::filesystem::path& stem);

// Why a claim may be taken over ("its heartbeat is 412 s old", "its owner ... is gone"), or ""
// while it is live.
std::string WhyStale(const ClaimState& state, const ClaimOptions& options);

// A claim this process holds: its heartbeat beats until the object is destroyed, which lets go.
class HeldClaim {
 public:
  HeldClaim(std::filesystem::path stem, int generation, int fd, double heartbeat_s);
  ~HeldClaim();
  HeldClaim(const HeldClaim&) = delete;
  HeldClaim& operator=(const HeldClaim&) = delete;
  const std::filesystem::path& file() const { return file_; }

 private:
  struct Beat;
  std::filesystem::path stem_;
  std::filesystem::path file_;
  int generation_;
  std::unique_ptr<Beat> beat_;
};

// The realtime clock, and a file's modification time on it (0 when the file is missing), in ns.
int64_t RealtimeNs();
int64_t ModifiedNs(const std::filesystem::path& file);

struct ClaimAttempt {
  std::unique_ptr<HeldClaim> held;  // the claim, or null: someone holds the job (`seen`)
  ClaimState seen;                  // the claim found before the attempt
  std::string taken_over_because;   // why `seen` was taken over; "" when the job was free
};

// Takes the job for `me` if it is free or its claim is stale or dead (WhyStale); exactly one of
// any number of processes racing for it succeeds. Throws std::runtime_error when the claim cannot
// be written (no directory, no permission), naming the file and the system's reason.
ClaimAttempt TryClaim(const std::filesystem::path& stem, const ClaimOwner& me,
                      const ClaimOptions& options);

}  // namespace rubcont
