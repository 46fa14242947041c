#include "granular_core/dataset/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include "granular_core/dataset/output_folder.h"

namespace granular {
namespace fs = std::filesystem;

namespace {

std::runtime_error writeError(const fs::path& file, const std::string& what, int error) {
  return std::runtime_error(file.string() + ": cannot write " + what + ": " +
                            std::strerror(error));
}

// Writes all of `content` to the open descriptor; false with errno set on failure.
bool writeAll(int fd, const std::string& content) {
  const char* at = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, at, left);
    if (written < 0) {
      if (errno == EINTR) {
        continue;
      }
      return false;
    }
    at += written;
    left -= static_cast<std::size_t>(written);
  }
  return true;
}

// Flushes `partial` to disk; a failure (a full disk found only now) is reported under `file`.
void syncFile(const fs::path& partial, const fs::path& file, const std::string& what) {
  const int fd = ::open(partial.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int error = errno;
    if (fd >= 0) {
      ::close(fd);
    }
    throw writeError(file, what, error);
  }
  ::close(fd);
}

// Creates or truncates `file` and writes `content`; 0, or the errno of the first failure (the
// file is then removed).
int writeContent(const fs::path& file, const std::string& content) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    return errno;
  }
  const bool written = writeAll(fd, content);
  const int write_error = errno;
  const bool closed = ::close(fd) == 0;
  if (written && closed) {
    return 0;
  }
  const int error = !written ? write_error : errno;
  std::error_code ignored;
  fs::remove(file, ignored);
  return error;
}

}  // namespace

fs::path temporarySibling(const fs::path& path, const std::string& kind) {
  const fs::path absolute = absoluteOutputPath(path);
  return absolute.parent_path() /
         ("." + absolute.filename().string() + "." + kind + "-" + std::to_string(::getpid()));
}

void writeFile(const fs::path& file, const std::string& content, const std::string& what) {
  if (const int error = writeContent(file, content)) {
    throw writeError(file, what, error);
  }
}

void writeThroughTemporary(const fs::path& file, const std::string& what,
                           const std::function<bool(const fs::path&)>& write) {
  clearDeadSiblings(file);
  const fs::path partial = temporarySibling(file, "partial");
  registerPendingOutput(partial);
  std::error_code error;
  try {
    if (!write(partial)) {
      throw std::runtime_error(file.string() + ": cannot write " + what + " (through " +
                               partial.string() + ")");
    }
    syncFile(partial, file, what);
  } catch (...) {
    fs::remove(partial, error);
    unregisterPendingOutput(partial);
    throw;
  }
  fs::rename(partial, file, error);
  unregisterPendingOutput(partial);
  if (error) {
    const std::string reason = error.message();
    fs::remove(partial, error);
    throw std::runtime_error(file.string() + ": cannot write " + what + ": " + reason);
  }
  // The rename itself reaches the disk with the folder's entry.
  const fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

void checkCanWrite(const fs::path& file, const std::string& what) {
  const auto refuse = [&](const std::string& reason) {
    throw std::runtime_error(file.string() + ": cannot write " + what + ": " + reason);
  };
  std::error_code error;
  if (fs::is_directory(file, error)) {
    refuse("it is a folder");
  }
  // The nearest existing folder above it must be a folder all the way.
  const fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  for (fs::path above = folder; !above.empty(); above = above.parent_path()) {
    if (fs::exists(above, error)) {
      if (!fs::is_directory(above, error)) {
        refuse(above.string() + " is not a folder");
      }
      if (above != folder) {
        refuse("its folder " + folder.string() + " does not exist");
      }
      return;
    }
    if (above == above.parent_path()) {
      break;
    }
  }
  refuse("its folder " + folder.string() + " does not exist");
}

void writeFileAtomically(const fs::path& file, const std::string& content,
                         const std::string& what) {
  int error = 0;
  try {
    writeThroughTemporary(file, what, [&](const fs::path& partial) {
      error = writeContent(partial, content);
      return error == 0;
    });
  } catch (const std::runtime_error&) {
    if (error != 0) {
      throw writeError(file, what, error);  // the reason, not the temporary name
    }
    throw;
  }
}

}  // namespace granular
