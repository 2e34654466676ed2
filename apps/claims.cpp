#include "apps/claims.h"

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "apps/atomic_file.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;

std::string FirstLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// The start of process `pid` in clock ticks after boot (field 22 of /proc/PID/stat, counted after
// the command name's closing parenthesis, as the name may hold spaces); 0 when there is none.
uint64_t StartTicks(int64_t pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  const std::string stat((std::istreambuf_iterator<char>(in)), {});
  const size_t name_end = stat.rfind(')');
  if (name_end == std::string::npos) return 0;
  std::istringstream fields(stat.substr(name_end + 1));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
    if (i == 22) return std::strtoull(field.c_str(), nullptr, 10);
  }
  return 0;
}

// UTC time of a start in ticks after boot (btime of /proc/stat); "" when unknown.
std::string StartedUtc(uint64_t start_ticks) {
  std::ifstream in("/proc/stat");
  std::time_t boot = 0;
  for (std::string key; in >> key;) {
    if (key == "btime") {
      in >> boot;
      break;
    }
  }
  if (boot == 0 || start_ticks == 0) return "";
  const std::time_t started =
      boot + static_cast<std::time_t>(start_ticks / static_cast<uint64_t>(::sysconf(_SC_CLK_TCK)));
  char text[32];
  std::tm utc{};
  ::gmtime_r(&started, &utc);
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

std::string HostName() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

std::string Environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

fs::path Generation(const fs::path& stem, int g) { return fs::path(stem.string() + "." + std::to_string(g)); }

bool Exists(const fs::path& file) {
  struct stat s;
  return ::stat(file.c_str(), &s) == 0;
}

std::string OwnerRecord(const ClaimOwner& o) {
  return fmt::format("host = \"{}\"\nboot_id = \"{}\"\npid = {}\nstart_ticks = {}\nstarted = \"{}\"\n"
                     "allocation = \"{}\"\nrank = {}\nheartbeat_seconds = {}\n",
                     o.host, o.boot_id, o.pid, o.start_ticks, o.started, o.allocation, o.rank,
                     o.heartbeat_s);
}

bool ReadOwner(const fs::path& file, ClaimOwner& o) {
  try {
    const toml::table t = toml::parse_file(file.string());
    o.host = t["host"].value_or(std::string());
    o.boot_id = t["boot_id"].value_or(std::string());
    o.pid = t["pid"].value_or(int64_t{0});
    o.start_ticks = static_cast<uint64_t>(t["start_ticks"].value_or(int64_t{0}));
    o.started = t["started"].value_or(std::string());
    o.allocation = t["allocation"].value_or(std::string());
    o.rank = static_cast<int>(t["rank"].value_or(int64_t{0}));
    o.heartbeat_s = t["heartbeat_seconds"].value_or(0.0);
    return !o.host.empty() && o.pid > 0;
  } catch (const toml::parse_error&) {
    return false;
  }
}

[[noreturn]] void FailClaim(const fs::path& file, int error) {
  throw std::runtime_error(fmt::format("cannot claim {}: {}", file.string(), std::strerror(error)));
}

// Creates `file` holding `record`, exclusively: false when it exists. The record goes to a
// temporary first and is hard-linked to the name, so that the claim appears whole. On NFS a link
// whose reply was lost may report an error although it was made; the temporary's link count then
// says so (the recipe of open(2), O_EXCL). Returns the open descriptor of the claim, for its
// heartbeat, in `fd`.
bool CreateExclusively(const fs::path& file, const std::string& record, int& fd) {
  const fs::path temporary = UniqueTemporaryName(file);
  fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) FailClaim(file, errno);
  if (::write(fd, record.data(), record.size()) != static_cast<ssize_t>(record.size())) {
    const int error = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    FailClaim(file, error);
  }
  bool linked = ::link(temporary.c_str(), file.c_str()) == 0;
  const int error = errno;
  if (!linked && error != EEXIST) {
    struct stat s;
    linked = ::fstat(fd, &s) == 0 && s.st_nlink == 2;
    if (!linked) {
      ::close(fd);
      ::unlink(temporary.c_str());
      FailClaim(file, error);
    }
  }
  ::unlink(temporary.c_str());
  if (!linked) ::close(fd);
  return linked;
}

}  // namespace

int64_t RealtimeNs() {
  timespec now;
  ::clock_gettime(CLOCK_REALTIME, &now);
  return int64_t{now.tv_sec} * 1000000000 + now.tv_nsec;
}

int64_t ModifiedNs(const fs::path& file) {
  struct stat s;
  if (::stat(file.c_str(), &s) != 0) return 0;
  return int64_t{s.st_mtim.tv_sec} * 1000000000 + s.st_mtim.tv_nsec;
}

void ClaimOptions::Validate() const {
  if (!(stale_after_s > 0.0) || stale_after_s > 1e7) {
    throw std::invalid_argument(fmt::format(
        "--stale-after {}: must be a number of seconds in (0, 1e7] (default 300)", stale_after_s));
  }
}

std::string ClaimOwner::Describe() const {
  std::string text = fmt::format("pid {} on {} (", pid, host.empty() ? "an unknown host" : host);
  if (!allocation.empty()) text += fmt::format("Slurm job {}, ", allocation);
  text += fmt::format("rank {}", rank);
  if (!started.empty()) text += fmt::format(", started {}", started);
  return text + ")";
}

ClaimOwner ThisProcess(int rank, double heartbeat_s) {
  ClaimOwner o;
  o.host = HostName();
  o.boot_id = FirstLine("/proc/sys/kernel/random/boot_id");
  o.pid = ::getpid();
  o.start_ticks = StartTicks(o.pid);
  o.started = StartedUtc(o.start_ticks);
  const std::string array_job = Environment("SLURM_ARRAY_JOB_ID");
  o.allocation = array_job.empty() ? Environment("SLURM_JOB_ID")
                                   : array_job + "_" + Environment("SLURM_ARRAY_TASK_ID");
  o.rank = rank;
  o.heartbeat_s = heartbeat_s;
  return o;
}

// Only a process of this host and boot can be proven gone. Two hosts of one name (containers of
// one machine in separate pid namespaces, given the same host name) would defeat the test; their
// claims still go stale.
OwnerLife LifeOf(const ClaimOwner& owner) {
  static const ClaimOwner here = ThisProcess(0, 0.0);
  if (owner.host != here.host || owner.host.empty() || owner.pid <= 0) return OwnerLife::kUnknown;
  if (!owner.boot_id.empty() && !here.boot_id.empty() && owner.boot_id != here.boot_id) {
    return OwnerLife::kDead;
  }
  // kill(pid, 0) rather than /proc: a /proc mounted with hidepid hides other users' processes.
  if (::kill(static_cast<pid_t>(owner.pid), 0) != 0 && errno == ESRCH) return OwnerLife::kDead;
  const uint64_t now_ticks = StartTicks(owner.pid);  // 0: not readable here
  if (now_ticks == 0 || owner.start_ticks == 0) return OwnerLife::kUnknown;
  return now_ticks == owner.start_ticks ? OwnerLife::kAlive : OwnerLife::kDead;
}

// The newest generation: one missing generation is stepped over (an owner that lets go removes
// its files from the newest down, and one taking over meanwhile may leave generation 0 missing).
ClaimState LookAtClaim(const fs::path& stem) {
  ClaimState state;
  for (int g = 0;; ++g) {
    if (Exists(Generation(stem, g))) {
      state.generation = g;
    } else if (!Exists(Generation(stem, g + 1))) {
      break;
    }
  }
  if (state.generation < 0) return state;
  state.file = Generation(stem, state.generation);
  state.heartbeat_ns = ModifiedNs(state.file);
  if (state.heartbeat_ns == 0) {  // let go of since: the job is free
    state.generation = -1;
    return state;
  }
  state.heartbeat_age_s = std::max(0.0, 1e-9 * static_cast<double>(RealtimeNs() - state.heartbeat_ns));
  state.owner_known = ReadOwner(state.file, state.owner);
  return state;
}

std::string WhyStale(const ClaimState& state, const ClaimOptions& options) {
  if (state.generation < 0) return "";
  if (state.owner_known && LifeOf(state.owner) == OwnerLife::kDead) {
    return fmt::format("its owner, {}, is gone", state.owner.Describe());
  }
  const double limit = std::max(options.stale_after_s, 3.0 * state.owner.heartbeat_s);
  if (state.heartbeat_age_s > limit) {
    return fmt::format("its heartbeat is {:.0f} s old (stale after {:.0f} s){}", state.heartbeat_age_s,
                       limit, state.owner_known ? "; owner " + state.owner.Describe() : "");
  }
  return "";
}

struct HeldClaim::Beat {
  int fd;
  std::mutex mutex;
  std::condition_variable wake;
  bool stop = false;
  std::thread thread;
};

HeldClaim::HeldClaim(fs::path stem, int generation, int fd, double heartbeat_s)
    : stem_(std::move(stem)), file_(Generation(stem_, generation)), generation_(generation),
      beat_(std::make_unique<Beat>()) {
  beat_->fd = fd;
  // A failed touch is not reported: the claim then goes stale and may be run twice, which the
  // atomic writes of every result make harmless.
  beat_->thread = std::thread([beat = beat_.get(), heartbeat_s] {
    std::unique_lock<std::mutex> lock(beat->mutex);
    const auto interval = std::chrono::duration<double>(std::max(heartbeat_s, 0.01));
    while (!beat->wake.wait_for(lock, interval, [beat] { return beat->stop; })) {
      ::futimens(beat->fd, nullptr);
    }
  });
}

// Lets go: the newest generation's owner removes the job's claim files, newest first; an owner
// that was taken over from leaves them to the new owner.
HeldClaim::~HeldClaim() {
  {
    const std::lock_guard<std::mutex> lock(beat_->mutex);
    beat_->stop = true;
  }
  beat_->wake.notify_one();
  beat_->thread.join();
  ::close(beat_->fd);
  if (Exists(Generation(stem_, generation_ + 1))) return;
  for (int g = generation_; g >= 0; --g) ::unlink(Generation(stem_, g).c_str());
}

ClaimAttempt TryClaim(const fs::path& stem, const ClaimOwner& me, const ClaimOptions& options) {
  ClaimAttempt attempt;
  attempt.seen = LookAtClaim(stem);
  if (attempt.seen.generation >= 0) {
    attempt.taken_over_because = WhyStale(attempt.seen, options);
    if (attempt.taken_over_because.empty()) return attempt;
  }
  const int generation = attempt.seen.generation + 1;
  int fd = -1;
  if (!CreateExclusively(Generation(stem, generation), OwnerRecord(me), fd)) {
    attempt.taken_over_because.clear();
    return attempt;
  }
  attempt.held = std::make_unique<HeldClaim>(stem, generation, fd, me.heartbeat_s);
  return attempt;
}

}  // namespace rubcont
