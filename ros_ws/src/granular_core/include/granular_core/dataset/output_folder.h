#pragma once

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace granular {

/// The marker at the root of every folder a granular tool writes: a small JSON object naming the
/// tool and the version. Only a folder that holds one may ever be replaced.
inline constexpr const char* kManifestName = ".granular.json";

/// The version of granular written into manifests (package.xml's).
const char* granularVersion();

/// How a tool may treat an output folder that exists.
struct OutputPolicy {
  /// Replace a folder that a granular tool wrote (it holds kManifestName). A folder of other
  /// files is never replaced, whatever this says.
  bool overwrite = false;
  /// How the user asks for `overwrite`, for the error that tells them: "--overwrite" for a
  /// tool, "overwrite:=true" when they came through roslaunch.
  std::string overwrite_hint = "--overwrite";
};

/// Throws std::runtime_error naming `target` when a tool may not write it under `policy`: it is
/// not a folder, holds files without a manifest, or holds a granular tool's results without
/// policy.overwrite. An absent or empty folder may always be written.
void checkOutputFolder(const std::filesystem::path& target, const OutputPolicy& policy);

/// Throws std::runtime_error naming both when the output folder `target` is, or holds, one of
/// `inputs` (files or folders a run reads; symbolic links resolved): replacing it would lose
/// the input, with --overwrite or without.
void checkOutputApart(const std::filesystem::path& target,
                      const std::vector<std::filesystem::path>& inputs);

/// A folder a tool builds as a whole. The constructor
///   - takes an exclusive lock (flock on lockFileOf(target), holding the pid and tool) so that a
///     second run into the same folder is refused with a message naming the first;
///   - clears what dead runs left: staging folders and temporary files of processes that no
///     longer exist, and puts back a previous result that a run killed mid-swap had set aside;
///   - checks the target (checkOutputApart from `inputs`, the run's input files and folders;
///     checkOutputFolder) and creates an empty staging folder beside it,
///     ".<name>.partial-<pid>", registered for removal on a signal (removePendingOutputs).
/// The tool writes into staging(); commit() adds the manifest, flushes the staging folder to
/// disk and renames it into place (the old result, if any, removed). Destroyed without commit()
/// (an error, an exception), the staging folder is removed and the target is left as it was.
class OutputFolder {
 public:
  OutputFolder(const std::filesystem::path& target, std::string tool,
               const OutputPolicy& policy = {},
               const std::vector<std::filesystem::path>& inputs = {});
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// Absolute, without a trailing separator.
  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& staging() const { return staging_; }
  /// What the constructor cleared (or put back) of dead runs, one line each.
  const std::vector<std::string>& cleared() const { return cleared_; }

  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  std::string tool_;
  int lock_fd_ = -1;
  bool committed_ = false;
  std::vector<std::string> cleared_;
};

/// The lock file of an output folder: "$XDG_RUNTIME_DIR/granular-locks/<hash>.lock" (or under
/// /tmp), the hash (FNV-1a) of the folder's canonical path, so that no lock file is left among
/// the user's folders and two spellings of one folder share a lock.
std::filesystem::path lockFileOf(const std::filesystem::path& target);

/// The absolute form of `path` without a trailing separator, so that it has a file name.
std::filesystem::path absoluteOutputPath(const std::filesystem::path& path);

/// Removes the temporary siblings of `path` (".<name>.partial-<pid>", ".<name>.previous-<pid>")
/// that processes no longer running left; a set-aside previous result is renamed back to
/// `path` when `path` is missing. Returns one line per thing done.
std::vector<std::string> clearDeadSiblings(const std::filesystem::path& path);

/// Registers a staging folder or temporary file that must not survive an interruption.
void registerPendingOutput(const std::filesystem::path& path);
void unregisterPendingOutput(const std::filesystem::path& path);

/// Removes every registered path; returns them. For a tool's signal handling thread, just
/// before the process exits: each path is renamed first, so that the writers' later writes into
/// it fail instead of recreating it. Waits for a commit in progress (see holdPendingOutputs).
std::vector<std::filesystem::path> removePendingOutputs();

/// Held while a commit renames folders, so that an interruption cannot fall between them.
std::unique_lock<std::mutex> holdPendingOutputs();

}  // namespace granular
