#include "granular_core/io/atomic_output.h"

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace granular {
namespace fs = std::filesystem;

void writeThroughTemporary(const fs::path& file, const std::string& what,
                           const std::function<bool(const fs::path&)>& write) {
  const fs::path partial = file.parent_path() / ("." + file.filename().string() + ".partial");
  std::error_code error;
  if (!write(partial)) {
    fs::remove(partial, error);
    throw std::runtime_error(file.string() + ": cannot write " + what + " (through " +
                             partial.string() + ")");
  }
  fs::rename(partial, file, error);
  if (error) {
    const std::string reason = error.message();
    fs::remove(partial, error);
    throw std::runtime_error(file.string() + ": cannot write " + what + ": " + reason);
  }
}

void writeFileAtomically(const fs::path& file, const std::string& content,
                         const std::string& what) {
  writeThroughTemporary(file, what, [&](const fs::path& partial) {
    std::ofstream stream(partial, std::ios::binary | std::ios::trunc);
    stream.write(content.data(), static_cast<std::streamsize>(content.size()));
    stream.close();
    return static_cast<bool>(stream);
  });
}

StagingFolder::StagingFolder(fs::path path) : path_(std::move(path)) {
  fs::remove_all(path_);
  fs::create_directory(path_);
}

StagingFolder::~StagingFolder() {
  if (!released_) {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
}

void checkReplaceable(const fs::path& target, bool overwrite) {
  if (!fs::exists(target)) {
    return;
  }
  if (!fs::is_directory(target)) {
    throw std::runtime_error(target.string() + ": output exists and is not a folder");
  }
  if (!fs::is_empty(target) && !overwrite) {
    throw std::runtime_error(target.string() +
                             ": output folder exists and is not empty; refusing to replace it "
                             "unless overwrite is set");
  }
}

void replaceFolder(const fs::path& staging, const fs::path& target, const std::string& suffix) {
  if (fs::exists(target)) {
    const fs::path previous =
        target.parent_path() / ("." + target.filename().string() + ".previous-" + suffix);
    fs::rename(target, previous);
    fs::rename(staging, target);
    fs::remove_all(previous);
  } else {
    fs::rename(staging, target);
  }
}

}  // namespace granular
