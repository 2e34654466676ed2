// Writing a file so that a reader finds the earlier content or the new, whole, never a mix.
//
// The bytes go to a temporary name unique to this process and call, `<file>.tmp.<pid>.<random>`,
// in the file's directory; they are flushed to the disk (fsync) and the temporary is renamed onto
// the file (atomic on one file system). Two processes writing the same file each write their own
// temporary: the last rename wins, whole. While it writes, a process holds an exclusive flock on its
// temporary, so that a temporary nobody holds can be told for what a killed run left behind.
//
// Every failure (no directory, no permission, a read-only or full file system, a file-size limit,
// a directory where the file should be) throws std::runtime_error with one line naming the file
// and the system's reason ("cannot write out/a.h5: No space left on device"); the temporary is
// removed and the file is left as it was.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace rubcont {

// `<file>.tmp.<pid>.<8 hex digits>`, a name no other writer of `file` uses.
std::filesystem::path UniqueTemporaryName(const std::filesystem::path& file);

// Throws (as WriteFileAtomically does) unless `file` could be written now: its directory exists
// and takes a new file, and `file` is not a directory. Lets a long run fail before its work.
void CheckWritable(const std::filesystem::path& file);

void WriteFileAtomically(const std::filesystem::path& file, std::string_view bytes);

// Makes the directories `file` goes into and checks that it can be written there (CheckWritable),
// so that a command finds an unwritable output before its work; throws as WriteFileAtomically does
// ("cannot write out/new/a.h5: Read-only file system").
void PrepareToWrite(const std::filesystem::path& file);

// Removes the temporaries of `file` (`<file>.tmp`, `<file>.tmp.*`) that no process holds and that
// are older than `min_age_s` seconds (a writer holds its temporary from a moment after creating it),
// and returns their names; temporaries still held by a writer are left alone.
std::vector<std::filesystem::path> RemoveStaleTemporaries(const std::filesystem::path& file,
                                                          double min_age_s = 10.0);

}  // namespace rubcont
