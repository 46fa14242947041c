#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace granular {

/// Writes `file` through a temporary name in the same folder (".<name>.partial") that is
/// renamed to `file` at the end, so that no reader ever sees a half-written file. `write` writes
/// the temporary file and returns false if it failed. Throws std::runtime_error naming the file
/// and `what` ("PCD", "JSON", ...) on failure, leaving no temporary file behind.
void writeThroughTemporary(const std::filesystem::path& file, const std::string& what,
                           const std::function<bool(const std::filesystem::path&)>& write);

/// writeThroughTemporary with the file's whole content given.
void writeFileAtomically(const std::filesystem::path& file, const std::string& content,
                         const std::string& what);

/// A folder created empty (replacing what was there) and removed again on scope exit, unless
/// release() was called: where a tool builds its output before putting it in place.
class StagingFolder {
 public:
  explicit StagingFolder(std::filesystem::path path);
  ~StagingFolder();
  StagingFolder(const StagingFolder&) = delete;
  StagingFolder& operator=(const StagingFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  void release() { released_ = true; }

 private:
  std::filesystem::path path_;
  bool released_ = false;
};

/// Throws std::runtime_error naming `target` when it exists and is not a folder, or is a folder
/// that is not empty and `overwrite` is false: the check before a tool replaces its output.
void checkReplaceable(const std::filesystem::path& target, bool overwrite);

/// Puts the folder `staging` in place of `target`, which may exist; `target` is missing only
/// between two renames (the old one goes to ".<target>.previous-<suffix>", then is removed).
void replaceFolder(const std::filesystem::path& staging, const std::filesystem::path& target,
                   const std::string& suffix);

}  // namespace granular
