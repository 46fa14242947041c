#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace granular {

/// Writes `content` to `file` (created or truncated) and checks every write and the close:
/// on any failure (a full disk, a read-only folder) the file is removed and std::runtime_error
/// names it, `what` ("PCD", "JSON", ...) and the system's reason. For files inside a folder that
/// an OutputFolder stages: the folder as a whole is put in place at the end.
void writeFile(const std::filesystem::path& file, const std::string& content,
               const std::string& what);

/// Writes `file` through a temporary name in the same folder (".<name>.partial-<pid>"), flushed
/// to disk (fsync) and then renamed to `file`, so that no reader ever sees a half-written file,
/// even after a crash. `write` writes the temporary file and returns false if it failed. Throws
/// std::runtime_error naming the file and `what` on failure, leaving no temporary file behind.
/// The temporary file is removed by a signal's cleanup too (see registerForCleanup).
void writeThroughTemporary(const std::filesystem::path& file, const std::string& what,
                           const std::function<bool(const std::filesystem::path&)>& write);

/// writeThroughTemporary with the file's whole content given (written as by writeFile).
void writeFileAtomically(const std::filesystem::path& file, const std::string& content,
                         const std::string& what);

/// Throws std::runtime_error naming `file` and `what` unless `file` could be written: its
/// folder exists and is a folder, and `file` is not a folder. For tools that write one file at
/// the end of long work, to refuse a wrong --out before the work.
void checkCanWrite(const std::filesystem::path& file, const std::string& what);

/// The name a temporary sibling of `path` gets in this process: ".<name>.<kind>-<pid>", so that a
/// later run can tell a dead process's leftovers by their pid.
std::filesystem::path temporarySibling(const std::filesystem::path& path, const std::string& kind);

}  // namespace granular
