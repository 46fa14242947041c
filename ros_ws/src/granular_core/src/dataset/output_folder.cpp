#include "granular_core/dataset/output_folder.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/atomic_file.h"

namespace granular {
namespace fs = std::filesystem;

namespace {

std::mutex& pendingMutex() {
  static std::mutex mutex;
  return mutex;
}

std::set<fs::path>& pendingPaths() {
  static std::set<fs::path> paths;
  return paths;
}

bool processRunning(long pid) {
  return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

constexpr const char* kRemovingSuffix = ".removing";

// The pid at the end of ".<name>.<kind>-<pid>" (or of one being removed), or -1 when `entry` is
// not such a sibling.
long siblingPid(const std::string& entry, const std::string& prefix) {
  if (entry.rfind(prefix, 0) != 0) {
    return -1;
  }
  std::string digits = entry.substr(prefix.size());
  const std::string removing = kRemovingSuffix;
  if (digits.size() > removing.size() &&
      digits.compare(digits.size() - removing.size(), removing.size(), removing) == 0) {
    digits.resize(digits.size() - removing.size());
  }
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
      digits.size() > 9) {
    return -1;
  }
  return std::stol(digits);
}

// The manifest's tool, or an empty string when `folder` has no valid manifest.
std::string manifestTool(const fs::path& folder) {
  std::ifstream stream(folder / kManifestName);
  if (!stream) {
    return "";
  }
  const nlohmann::json manifest = nlohmann::json::parse(stream, nullptr, false);
  if (!manifest.is_object() || !manifest.contains("tool") || !manifest["tool"].is_string()) {
    return "";
  }
  return manifest["tool"].get<std::string>();
}

std::string utcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// FNV-1a, 64 bits: the lock file's name for a folder (output.py computes the same).
std::string pathHash(const std::string& text) {
  std::uint64_t hash = 14695981039346656037ULL;
  for (const unsigned char c : text) {
    hash = (hash ^ c) * 1099511628211ULL;
  }
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(hash));
  return hex;
}

// Takes the lock of `target` or throws naming the run that holds it.
int lockOutput(const fs::path& target, const std::string& tool) {
  const fs::path lock_file = lockFileOf(target);
  std::error_code error;
  if (fs::create_directory(lock_file.parent_path(), error)) {
    // Shared by every user of the machine, like /tmp itself.
    fs::permissions(lock_file.parent_path(), fs::perms::all | fs::perms::sticky_bit, error);
  }
  const int fd = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error(target.string() + ": cannot create the lock file " +
                             lock_file.string() + ": " + std::strerror(errno));
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int lock_error = errno;
    std::string holder;
    std::ifstream holder_note(lock_file);
    std::getline(holder_note, holder);
    ::close(fd);
    if (lock_error == EWOULDBLOCK) {
      throw std::runtime_error(target.string() + ": another granular run is writing this folder" +
                               (holder.empty() ? "" : " (" + holder + ")") +
                               "; wait for it to finish or choose another output folder");
    }
    throw std::runtime_error(target.string() + ": cannot lock " + lock_file.string() + ": " +
                             std::strerror(lock_error));
  }
  const std::string holder = "process " + std::to_string(::getpid()) + ", " + tool + "\n";
  if (::ftruncate(fd, 0) != 0 || ::write(fd, holder.data(), holder.size()) < 0) {
    // The lock holds without the note; the note only makes the refusal clearer.
  }
  return fd;
}

}  // namespace

const char* granularVersion() { return GRANULAR_VERSION; }

fs::path lockFileOf(const fs::path& target) {
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  const fs::path base = runtime != nullptr && *runtime ? fs::path(runtime) : fs::path("/tmp");
  return base / "granular-locks" / (pathHash(fs::weakly_canonical(target).string()) + ".lock");
}

fs::path absoluteOutputPath(const fs::path& path) {
  fs::path absolute = fs::absolute(path).lexically_normal();
  return absolute.has_filename() ? absolute : absolute.parent_path();
}

void checkOutputApart(const fs::path& target, const std::vector<fs::path>& inputs) {
  const auto resolved = [](const fs::path& path) {
    std::error_code error;
    const fs::path canonical = fs::weakly_canonical(fs::absolute(path), error);
    return absoluteOutputPath(error ? fs::absolute(path) : canonical);
  };
  const fs::path folder = resolved(target);
  for (const fs::path& input : inputs) {
    const fs::path relative = resolved(input).lexically_relative(folder);
    if (!relative.empty() && *relative.begin() != "..") {
      throw std::runtime_error(target.string() + ": the output folder is or holds the input " +
                               input.string() + "; refusing to replace it: choose another "
                               "folder");
    }
  }
}

void checkOutputFolder(const fs::path& target, const OutputPolicy& policy) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(target, error);
  if (!fs::exists(status)) {
    return;
  }
  if (!fs::is_directory(fs::status(target, error))) {
    throw std::runtime_error(target.string() + ": output exists and is not a folder");
  }
  if (fs::is_empty(target, error)) {
    return;
  }
  const std::string tool = manifestTool(target);
  if (tool.empty()) {
    throw std::runtime_error(
        target.string() + ": output folder holds files that no granular tool wrote (it has no " +
        kManifestName + "); refusing to replace it, even with " + policy.overwrite_hint +
        ": choose another folder, or remove it yourself");
  }
  if (!policy.overwrite) {
    throw std::runtime_error(target.string() + ": output folder holds results of " + tool +
                             "; pass " + policy.overwrite_hint + " to replace them");
  }
}

std::vector<std::string> clearDeadSiblings(const fs::path& path) {
  const fs::path absolute = absoluteOutputPath(path);
  const fs::path parent = absolute.parent_path();
  const std::string name = absolute.filename().string();
  const std::string partial = "." + name + ".partial-";
  const std::string previous = "." + name + ".previous-";
  std::vector<std::string> done;
  std::error_code error;
  if (!fs::is_directory(parent, error)) {
    return done;
  }
  std::vector<fs::path> set_aside;
  for (const fs::directory_entry& entry : fs::directory_iterator(parent, error)) {
    const std::string entry_name = entry.path().filename().string();
    const long partial_pid = siblingPid(entry_name, partial);
    const long previous_pid = siblingPid(entry_name, previous);
    const long pid = std::max(partial_pid, previous_pid);
    if (pid < 0 || pid == ::getpid() || processRunning(pid)) {
      continue;
    }
    if (previous_pid >= 0) {
      set_aside.push_back(entry.path());
      continue;
    }
    fs::remove_all(entry.path(), error);
    done.push_back("removed " + entry.path().string() + ", left by process " +
                   std::to_string(pid) + ", which is no longer running");
  }
  for (const fs::path& old : set_aside) {
    if (!fs::exists(absolute, error)) {
      fs::rename(old, absolute, error);
      done.push_back("put back " + absolute.string() + " from " + old.string() +
                     ", set aside by a run that was killed while replacing it");
    } else {
      fs::remove_all(old, error);
      done.push_back("removed " + old.string() + ", an old result a killed run had replaced");
    }
  }
  return done;
}

OutputFolder::OutputFolder(const fs::path& target, std::string tool, const OutputPolicy& policy,
                           const std::vector<fs::path>& inputs)
    : target_(absoluteOutputPath(target)), tool_(std::move(tool)) {
  checkOutputApart(target_, inputs);
  std::error_code error;
  fs::create_directories(target_.parent_path(), error);
  if (error) {
    throw std::runtime_error(target_.string() + ": cannot create the folder " +
                             target_.parent_path().string() + ": " + error.message());
  }
  lock_fd_ = lockOutput(target_, tool_);
  try {
    cleared_ = clearDeadSiblings(target_);
    checkOutputFolder(target_, policy);
    staging_ = temporarySibling(target_, "partial");
    registerPendingOutput(staging_);
    fs::remove_all(staging_);
    fs::create_directory(staging_);
  } catch (const fs::filesystem_error& failure) {
    ::close(lock_fd_);
    throw std::runtime_error(target_.string() + ": cannot create the staging folder " +
                             staging_.string() + ": " + failure.code().message());
  } catch (...) {
    ::close(lock_fd_);
    throw;
  }
}

OutputFolder::~OutputFolder() {
  if (!committed_ && !staging_.empty()) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
    unregisterPendingOutput(staging_);
  }
  ::close(lock_fd_);
}

void OutputFolder::commit() {
  const nlohmann::json manifest = {
      {"tool", tool_}, {"version", granularVersion()}, {"written", utcNow()}};
  writeFile(staging_ / kManifestName, manifest.dump(1) + "\n", "manifest");

  // Everything written into the staging folder reaches the disk before it takes the final name.
  const int staging_fd = ::open(staging_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (staging_fd < 0 || ::syncfs(staging_fd) != 0) {
    const int sync_error = errno;
    if (staging_fd >= 0) {
      ::close(staging_fd);
    }
    throw std::runtime_error(target_.string() + ": cannot flush the results to disk: " +
                             std::strerror(sync_error));
  }
  ::close(staging_fd);

  const fs::path previous = temporarySibling(target_, "previous");
  bool had_previous = false;
  {
    const std::unique_lock<std::mutex> hold = holdPendingOutputs();
    std::error_code error;
    if (fs::exists(target_)) {
      fs::rename(target_, previous, error);
      if (error) {
        throw std::runtime_error(target_.string() + ": cannot replace it: " + error.message());
      }
      had_previous = true;
    }
    fs::rename(staging_, target_, error);
    if (error) {
      if (had_previous) {
        std::error_code ignored;
        fs::rename(previous, target_, ignored);
      }
      throw std::runtime_error(target_.string() + ": cannot put the results in place: " +
                               error.message());
    }
    pendingPaths().erase(staging_);
    if (had_previous) {
      pendingPaths().insert(previous);
    }
  }
  committed_ = true;
  const int parent_fd = ::open(target_.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (parent_fd >= 0) {
    ::fsync(parent_fd);
    ::close(parent_fd);
  }
  if (had_previous) {
    std::error_code ignored;
    fs::remove_all(previous, ignored);
    unregisterPendingOutput(previous);
  }
}

void registerPendingOutput(const fs::path& path) {
  const std::lock_guard<std::mutex> lock(pendingMutex());
  pendingPaths().insert(path);
}

void unregisterPendingOutput(const fs::path& path) {
  const std::lock_guard<std::mutex> lock(pendingMutex());
  pendingPaths().erase(path);
}

std::unique_lock<std::mutex> holdPendingOutputs() {
  return std::unique_lock<std::mutex>(pendingMutex());
}

std::vector<fs::path> removePendingOutputs() {
  const std::lock_guard<std::mutex> lock(pendingMutex());
  std::vector<fs::path> removed;
  for (const fs::path& path : pendingPaths()) {
    std::error_code error;
    if (!fs::exists(fs::symlink_status(path, error))) {
      continue;
    }
    // Renamed first: a writer's next file into `path` then fails instead of recreating it.
    const fs::path doomed = path.string() + kRemovingSuffix;
    fs::rename(path, doomed, error);
    const fs::path& target = error ? path : doomed;
    // A file created while the folder is walked makes remove_all fail; try again.
    for (int attempt = 0; attempt < 10; ++attempt) {
      fs::remove_all(target, error);
      if (!error) {
        break;
      }
    }
    removed.push_back(path);
  }
  pendingPaths().clear();
  return removed;
}

}  // namespace granular
