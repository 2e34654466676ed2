// Claims on jobs (apps/claims.h): owners, heartbeats, what is taken over and what is not, and
// racing takers. The batch command's use of them: tests/apps/batch_command_test.cpp.
#include "apps/claims.h"

#include <atomic>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using testing::TempDir;

// A claim file as another process would have left it, its heartbeat `age_s` seconds old.
void WriteClaim(const fs::path& file, const ClaimOwner& owner, double age_s) {
  std::ofstream(file) << "host = \"" << owner.host << "\"\nboot_id = \"" << owner.boot_id
                      << "\"\npid = " << owner.pid << "\nstart_ticks = " << owner.start_ticks
                      << "\nallocation = \"" << owner.allocation << "\"\nrank = 0\n"
                      << "heartbeat_seconds = " << owner.heartbeat_s << "\n";
  const int64_t at = RealtimeNs() - static_cast<int64_t>(age_s * 1e9);
  const timespec times[2] = {{at / 1000000000, at % 1000000000}, {at / 1000000000, at % 1000000000}};
  REQUIRE(::utimensat(AT_FDCWD, file.c_str(), times, 0) == 0);
}

// A pid that no process has now: a child's, after it was reaped.
int64_t GonePid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

ClaimOptions ClaimsStaleAfter(double seconds) {
  ClaimOptions options;
  options.stale_after_s = seconds;
  return options;
}

TEST_CASE("claims: a claim names its owner, beats, keeps others out and is let go", "[claims]") {
  TempDir dir;
  const fs::path stem = dir.path / "job.claim";
  const ClaimOptions options = ClaimsStaleAfter(0.5);  // heartbeat every 0.05 s
  const ClaimOwner me = ThisProcess(3, options.HeartbeatSeconds());
  {
    const ClaimAttempt mine = TryClaim(stem, me, options);
    REQUIRE(mine.held);
    CHECK(mine.taken_over_because.empty());
    CHECK(mine.held->file() == dir.path / "job.claim.0");
    const ClaimState seen = LookAtClaim(stem);
    REQUIRE(seen.owner_known);
    CHECK(seen.owner.pid == getpid());
    CHECK(seen.owner.host == me.host);
    CHECK(seen.owner.start_ticks > 0);
    CHECK(seen.owner.rank == 3);
    CHECK(LifeOf(seen.owner) == OwnerLife::kAlive);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const ClaimState later = LookAtClaim(stem);
    CHECK(later.heartbeat_ns > seen.heartbeat_ns);  // it beats
    CHECK(later.heartbeat_age_s < 0.2);
    const ClaimAttempt other = TryClaim(stem, me, options);  // live: not taken over
    CHECK_FALSE(other.held);
    CHECK(other.seen.generation == 0);
  }
  CHECK(LookAtClaim(stem).generation == -1);  // let go: no file left
  CHECK(fs::is_empty(dir.path));
}

TEST_CASE("claims: only a stale claim or a dead owner's is taken over", "[claims]") {
  TempDir dir;
  const fs::path stem = dir.path / "job.claim";
  const ClaimOwner me = ThisProcess(0, 0.1);
  ClaimOwner elsewhere = me;  // a live-looking owner on another host: only its heartbeat tells
  elsewhere.host = "node-elsewhere";
  elsewhere.heartbeat_s = 0.1;
  WriteClaim(dir.path / "job.claim.0", elsewhere, 5.0);
  CHECK_FALSE(TryClaim(stem, me, ClaimsStaleAfter(60.0)).held);  // 5 s old: live under 60 s
  ClaimOwner slow = elsewhere;  // beats every 30 s: stale only after 3 beats, whatever we ask
  slow.heartbeat_s = 30.0;
  WriteClaim(dir.path / "job.claim.0", slow, 5.0);
  CHECK_FALSE(TryClaim(stem, me, ClaimsStaleAfter(1.0)).held);
  WriteClaim(dir.path / "job.claim.0", elsewhere, 5.0);
  {
    const ClaimAttempt stale = TryClaim(stem, me, ClaimsStaleAfter(1.0));
    REQUIRE(stale.held);
    CHECK_THAT(stale.taken_over_because, Contains("its heartbeat is 5 s old (stale after 1 s)"));
    CHECK_THAT(stale.taken_over_because, Contains("on node-elsewhere"));
    CHECK(stale.held->file() == dir.path / "job.claim.1");
    CHECK(fs::exists(dir.path / "job.claim.0"));  // the old generation stays until let go
  }
  CHECK(fs::is_empty(dir.path));

  // This host: a pid that is gone, or one reused by a process started at another time, is dead at
  // once, with a fresh heartbeat; this process itself is alive.
  ClaimOwner gone = me;
  gone.pid = GonePid();
  CHECK(LifeOf(gone) == OwnerLife::kDead);
  ClaimOwner reused = me;
  reused.start_ticks += 1;
  CHECK(LifeOf(reused) == OwnerLife::kDead);
  ClaimOwner rebooted = me;
  rebooted.boot_id = "another-boot";
  CHECK(LifeOf(rebooted) == OwnerLife::kDead);
  CHECK(LifeOf(me) == OwnerLife::kAlive);
  CHECK(LifeOf(elsewhere) == OwnerLife::kUnknown);
  WriteClaim(dir.path / "job.claim.0", reused, 0.0);
  const ClaimAttempt dead = TryClaim(stem, me, ClaimsStaleAfter(300.0));
  REQUIRE(dead.held);
  CHECK_THAT(dead.taken_over_because, Contains("is gone"));
}

TEST_CASE("claims: of takers racing for one stale claim exactly one wins", "[claims]") {
  // Eight threads (their own link calls, as processes make them) find the same stale claim and
  // take it over at the same moment, 30 times; the winners keep their claims until all have tried.
  TempDir dir;
  const ClaimOwner me = ThisProcess(0, 0.1);
  ClaimOwner elsewhere = me;
  elsewhere.host = "node-elsewhere";
  constexpr int kTakers = 8;
  int rounds_with_one_winner = 0;
  for (int round = 0; round < 30; ++round) {
    const fs::path stem = dir.path / ("job" + std::to_string(round) + ".claim");
    WriteClaim(fs::path(stem.string() + ".0"), elsewhere, 10.0);
    std::atomic<int> ready{0};
    std::vector<ClaimAttempt> attempts(kTakers);
    std::vector<std::thread> takers;
    for (int t = 0; t < kTakers; ++t) {
      takers.emplace_back([&, t] {
        ++ready;
        while (ready < kTakers) std::this_thread::yield();
        attempts[t] = TryClaim(stem, me, ClaimsStaleAfter(1.0));
      });
    }
    for (std::thread& t : takers) t.join();
    int winners = 0;
    for (const ClaimAttempt& a : attempts) winners += a.held ? 1 : 0;
    INFO("round " << round << ": " << winners << " winners");
    CHECK(winners == 1);
    rounds_with_one_winner += winners == 1 ? 1 : 0;
  }
  CHECK(rounds_with_one_winner == 30);
}

TEST_CASE("claims: --stale-after must be a positive number of seconds", "[claims]") {
  CHECK_THROWS_WITH(ClaimsStaleAfter(0.0).Validate(), Contains("--stale-after 0: must be a number of seconds"));
  CHECK_THROWS_WITH(ClaimsStaleAfter(-5.0).Validate(), Contains("--stale-after -5"));
  CHECK_NOTHROW(ClaimsStaleAfter(300.0).Validate());
}

}  // namespace
}  // namespace rubcont
