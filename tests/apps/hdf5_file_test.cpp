#include "apps/hdf5_file.h"
#include "apps/atomic_file.h"
#include "solvers/constants.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>
#include <csignal>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <unistd.h>

#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;

using testing::TempDir;

std::string Bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// An older result under `file`: /version = {1}.
void WriteOlderResult(const fs::path& file) {
  ResultWriter writer(file);
  writer.WriteInts("/version", {1});
  writer.Commit();
}

TEST_CASE("HDF5 round trip of every supported type", "[hdf5]") {
  TempDir dir;
  const fs::path file = dir.path / "round.h5";
  const double inf = kInfinity;
  Matrix matrix(2, 3);
  matrix << 1, 2, 3, 4, 5, 6;
  {
    ResultWriter writer(file);
    writer.WriteDoubles("/a/b/doubles", std::vector<double>{1.5, -2.0, inf, 1e-300});
    writer.WriteDoubles("/a/vector", Vector::LinSpaced(5, 0.0, 1.0));
    writer.WriteMatrix("/a/matrix", matrix);
    writer.WriteInts("/a/ints", {3, -1, 0});
    writer.WriteStrings("/a/strings", {"mu_crossing", "μ_req ≤ μ", ""});
    writer.WriteDoubles("/a/empty", std::vector<double>{});
    writer.WriteStrings("/a/no_strings", {});
    writer.CreateGroup("/c/d");
    writer.SetAttribute("/", "rubcont_version", "0.1.0");
    writer.SetAttribute("/a", "friction", 0.5);
    writer.SetAttribute("/a/matrix", "unit", "N");
    writer.SetAttribute("/a/matrix", "unit", "N·s/m");  // overwrite
    writer.SetAttribute("/a", "no_folds", std::vector<double>{});  // a list may be empty
    writer.SetAttribute("/a", "folds", std::vector<double>{49.2, -1e-300});
    writer.Commit();
  }
  const ResultReader reader(file);
  const auto doubles = reader.ReadDoubles("/a/b/doubles");
  REQUIRE(doubles.size() == 4);
  CHECK(doubles[0] == 1.5);
  CHECK(doubles[2] == inf);
  CHECK(doubles[3] == 1e-300);
  CHECK(reader.ReadDoubles("/a/vector")[4] == 1.0);
  const Matrix back = reader.ReadMatrix("/a/matrix");
  CHECK(back == matrix);
  CHECK(reader.ReadInts("/a/ints") == std::vector<int>{3, -1, 0});
  CHECK(reader.ReadStrings("/a/strings") == std::vector<std::string>{"mu_crossing", "μ_req ≤ μ", ""});
  CHECK(reader.ReadDoubles("/a/empty").empty());
  CHECK(reader.ReadStrings("/a/no_strings").empty());
  CHECK(reader.ReadStringAttribute("/", "rubcont_version") == "0.1.0");
  CHECK(reader.ReadDoubleAttribute("/a", "friction") == 0.5);
  CHECK(reader.ReadStringAttribute("/a/matrix", "unit") == "N·s/m");
  CHECK(reader.HasAttribute("/a", "friction"));
  CHECK_FALSE(reader.HasAttribute("/a", "nothing"));
  CHECK(reader.HasAttribute("/a", "no_folds"));
  CHECK(reader.ReadDoublesAttribute("/a", "no_folds").empty());
  CHECK(reader.ReadDoublesAttribute("/a", "folds") == std::vector<double>{49.2, -1e-300});
  CHECK(reader.ReadDoublesAttribute("/a", "friction") == std::vector<double>{0.5});
  CHECK(reader.Exists("/c/d"));
  CHECK_FALSE(reader.Exists("/c/e"));
  CHECK_FALSE(reader.Exists("/x/y/z"));
  CHECK(reader.Children("/a") == std::vector<std::string>{"b", "empty", "ints", "matrix", "no_strings", "strings", "vector"});
  CHECK_THROWS_AS(reader.ReadDoubles("/a/missing"), std::runtime_error);
  CHECK_THROWS_AS(reader.ReadDoubles("/a/matrix"), std::runtime_error);  // 2-D, not 1-D
}

// The names in `dir`, sorted.
std::vector<std::string> Names(const fs::path& dir) {
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

// The message of what `write` throws as std::runtime_error ("" when it does not throw).
template <class Function>
std::string Failure(Function&& write) {
  try {
    write();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("The target appears only at Commit, whole, and no temporary stays", "[hdf5]") {
  TempDir dir;
  const fs::path file = dir.path / "result.h5";
  ResultWriter writer(file);
  writer.WriteInts("/x", {1});
  CHECK(fs::is_empty(dir.path));  // built in memory
  writer.Commit();
  CHECK(Names(dir.path) == std::vector<std::string>{"result.h5"});
  CHECK_THROWS_AS(writer.Commit(), std::logic_error);
}

TEST_CASE("A failure mid-write leaves no file and no temporary", "[hdf5]") {
  TempDir dir;
  const fs::path file = dir.path / "result.h5";
  CHECK_THROWS_WITH(
      [&] {
        ResultWriter writer(file);
        writer.WriteDoubles("/analytic/mode1/precession_hz", std::vector<double>(1000, 1.0));
        throw std::runtime_error("numerical failure halfway");
      }(),
      "numerical failure halfway");
  CHECK_FALSE(fs::exists(file));
  CHECK_FALSE(fs::exists(dir.path / "result.h5.tmp"));
  CHECK(fs::is_empty(dir.path));
}

TEST_CASE("A failed write leaves an existing target untouched", "[hdf5]") {
  TempDir dir;
  const fs::path file = dir.path / "result.h5";
  WriteOlderResult(file);
  const std::string before = Bytes(file);
  try {
    ResultWriter writer(file);
    writer.WriteInts("/version", {2});
    writer.WriteInts("/version", {3});  // HDF5 refuses a second dataset of that name
    FAIL("expected an exception");
  } catch (const std::runtime_error& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains("/version already exists"));
  }
  CHECK(Bytes(file) == before);
  CHECK(ResultReader(file).ReadInts("/version") == std::vector<int>{1});
  CHECK_FALSE(fs::exists(dir.path / "result.h5.tmp"));
}

TEST_CASE("Relative HDF5 paths are caller mistakes", "[hdf5]") {
  TempDir dir;
  ResultWriter writer(dir.path / "x.h5");
  CHECK_THROWS_AS(writer.WriteInts("relative", {1}), std::invalid_argument);
  CHECK_THROWS_AS(writer.CreateGroup("/trailing/"), std::invalid_argument);
}

TEST_CASE("Equal content gives equal bytes (no timestamps)", "[hdf5]") {
  TempDir dir;
  for (const char* name : {"one.h5", "two.h5"}) {
    if (std::string(name) == "two.h5") sleep(1);  // a recorded modification time would differ
    ResultWriter writer(dir.path / name);
    writer.WriteDoubles("/g/x", std::vector<double>{1.0, 2.0});
    writer.SetAttribute("/g", "a", "text");
    writer.Commit();
  }
  CHECK(Bytes(dir.path / "one.h5") == Bytes(dir.path / "two.h5"));
}

TEST_CASE("An unwritable target is reported with the system's reason before any work", "[hdf5]") {
  TempDir dir;
  CHECK(Failure([&] { ResultWriter writer(dir.path / "missing" / "x.h5"); }) ==
        "cannot write " + (dir.path / "missing" / "x.h5").string() + ": No such file or directory");
  fs::create_directory(dir.path / "x.h5");  // a directory where the file should be
  CHECK(Failure([&] { ResultWriter writer(dir.path / "x.h5"); }) ==
        "cannot write " + (dir.path / "x.h5").string() + ": Is a directory");
  CHECK(Names(dir.path) == std::vector<std::string>{"x.h5"});
  CHECK(fs::is_empty(dir.path / "x.h5"));
}

TEST_CASE("A file-size limit at Commit: the reason, the older file intact, no temporary", "[hdf5]") {
  // A full disk as a process meets it: the write fails partway (EFBIG here, ENOSPC on a full file
  // system; tests/apps/check_io_failure.sh fills a real one). It used to fail inside H5Fclose and
  // crash when the writer closed the half-closed file again.
  TempDir dir;
  const fs::path file = dir.path / "result.h5";
  WriteOlderResult(file);
  const std::string before = Bytes(file);
  ResultWriter writer(file);
  writer.WriteDoubles("/big", std::vector<double>(100000, 1.0));  // 800 kB
  rlimit saved{};
  REQUIRE(getrlimit(RLIMIT_FSIZE, &saved) == 0);
  rlimit limited = saved;
  limited.rlim_cur = 64 * 1024;
  auto* const handler = std::signal(SIGXFSZ, SIG_IGN);
  REQUIRE(setrlimit(RLIMIT_FSIZE, &limited) == 0);
  const std::string message = Failure([&] { writer.Commit(); });
  setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, handler);
  CHECK(message == "cannot write " + file.string() + ": File too large");
  CHECK(Bytes(file) == before);
  CHECK(Names(dir.path) == std::vector<std::string>{"result.h5"});
}

TEST_CASE("A rename onto a directory names the system's reason, not \"Success\"", "[hdf5]") {
  TempDir dir;
  const fs::path file = dir.path / "result.h5";
  ResultWriter writer(file);
  writer.WriteInts("/x", {1});
  fs::create_directories(file / "inside");  // appears while the writer works
  const std::string message = Failure([&] { writer.Commit(); });
  CHECK(message == "cannot write " + file.string() + ": Is a directory");
  CHECK(Names(dir.path) == std::vector<std::string>{"result.h5"});
}

TEST_CASE("Two writers of one target at once: each its own temporary, the last commit wins whole",
          "[hdf5]") {
  TempDir dir;
  const fs::path file = dir.path / "result.h5";
  ResultWriter first(file);
  ResultWriter second(file);
  first.WriteInts("/writer", {1});
  second.WriteInts("/writer", {2});
  second.WriteDoubles("/only_second", std::vector<double>{2.0});
  second.Commit();
  first.Commit();
  const ResultReader reader(file);
  CHECK(reader.ReadInts("/writer") == std::vector<int>{1});
  CHECK_FALSE(reader.Exists("/only_second"));
  CHECK(Names(dir.path) == std::vector<std::string>{"result.h5"});
}

TEST_CASE("Temporaries: unique per writer, a killed run's removed, a held one kept", "[hdf5]") {
  TempDir dir;
  const fs::path file = dir.path / "result.h5";
  const fs::path a = UniqueTemporaryName(file), b = UniqueTemporaryName(file);
  CHECK(a != b);
  CHECK_THAT(a.filename().string(),
             Catch::Matchers::StartsWith("result.h5.tmp." + std::to_string(getpid()) + "."));
  std::ofstream(dir.path / "result.h5.tmp") << "left by an older version";
  std::ofstream(a) << "left by a killed run";
  std::ofstream(b) << "being written";
  std::ofstream(dir.path / "result.h5.tmpfile") << "not a temporary of result.h5";
  const auto old = fs::file_time_type::clock::now() - std::chrono::minutes(1);
  for (const fs::path& p : {dir.path / "result.h5.tmp", a, b}) fs::last_write_time(p, old);
  const int held = open(b.c_str(), O_RDONLY);
  REQUIRE(flock(held, LOCK_EX) == 0);
  std::vector<fs::path> removed = RemoveStaleTemporaries(file);
  close(held);
  std::sort(removed.begin(), removed.end());
  CHECK(removed == std::vector<fs::path>{dir.path / "result.h5.tmp", a});
  CHECK(Names(dir.path) == std::vector<std::string>{b.filename().string(), "result.h5.tmpfile"});
  const fs::path recent = dir.path / "result.h5.tmp.1.00000000";
  std::ofstream(recent) << "recent: may be a writer's, not yet held";
  CHECK(RemoveStaleTemporaries(file) == std::vector<fs::path>{b});  // released now
  CHECK(fs::exists(recent));
}

}  // namespace
}  // namespace rubcont
