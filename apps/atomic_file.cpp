#include "apps/atomic_file.h"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <random>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>

namespace rubcont {
namespace {

namespace fs = std::filesystem;

// `error` is errno as it was right after the failing call: anything called since (close, unlink,
// the std::filesystem functions) may have overwritten errno itself.
[[noreturn]] void Fail(const fs::path& file, int error) {
  throw std::runtime_error(fmt::format("cannot write {}: {}", file.string(), std::strerror(error)));
}

// Creates `temporary` for writing (it must not exist yet); returns the descriptor or throws.
int CreateTemporary(const fs::path& file, const fs::path& temporary) {
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) Fail(file, errno);
  return fd;
}

void Discard(int fd, const fs::path& temporary) {
  ::close(fd);
  ::unlink(temporary.c_str());
}

}  // namespace

fs::path UniqueTemporaryName(const fs::path& file) {
  static thread_local std::mt19937 random{std::random_device{}()};
  return fs::path(fmt::format("{}.tmp.{}.{:08x}", file.string(), ::getpid(),
                              static_cast<unsigned>(random())));
}

void CheckWritable(const fs::path& file) {
  std::error_code ignored;
  if (fs::is_directory(file, ignored)) Fail(file, EISDIR);
  const fs::path temporary = UniqueTemporaryName(file);
  Discard(CreateTemporary(file, temporary), temporary);
}

void PrepareToWrite(const fs::path& file) {
  std::error_code error;
  fs::create_directories(file.parent_path().empty() ? fs::path(".") : file.parent_path(), error);
  if (error) Fail(file, error.value());
  CheckWritable(file);
}

void WriteFileAtomically(const fs::path& file, std::string_view bytes) {
  const fs::path temporary = UniqueTemporaryName(file);
  const int fd = CreateTemporary(file, temporary);
  // Held until the rename: RemoveStaleTemporaries leaves a held temporary alone. A file system
  // without flock only loses that protection.
  ::flock(fd, LOCK_EX | LOCK_NB);
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      Discard(fd, temporary);
      Fail(file, error);
    }
    done += static_cast<std::size_t>(n);
  }
  // A full disk may show only here (delayed allocation, network file systems).
  if (::fsync(fd) != 0 || ::rename(temporary.c_str(), file.c_str()) != 0) {
    const int error = errno;
    Discard(fd, temporary);
    Fail(file, error);
  }
  ::close(fd);  // after fsync its outcome cannot change the file's bytes
}

std::vector<fs::path> RemoveStaleTemporaries(const fs::path& file, double min_age_s) {
  const fs::path directory = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  const std::string fixed = file.filename().string() + ".tmp";
  std::vector<fs::path> removed;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, ec)) {
    const std::string name = entry.path().filename().string();
    if (name != fixed && name.rfind(fixed + ".", 0) != 0) continue;
    const auto age = fs::file_time_type::clock::now() - entry.last_write_time(ec);
    if (ec || std::chrono::duration<double>(age).count() < min_age_s) continue;
    const int fd = ::open(entry.path().c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::unlink(entry.path().c_str()) == 0) {
      removed.push_back(entry.path());
    }
    ::close(fd);
  }
  return removed;
}

}  // namespace rubcont
