#include "granular_core/dataset/object_names.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace granular {
namespace fs = std::filesystem;

namespace {

bool plainByte(unsigned char c, bool first) {
  return std::isalnum(c) || c == '_' || (c == '.' && !first);
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') {
    return c - '0';
  }
  if (c >= 'A' && c <= 'F') {
    return c - 'A' + 10;
  }
  return -1;  // lower case is not encodeLabel's, so not a name it gave
}

std::string checkedEncoding(const std::string& label) {
  if (label.empty()) {
    throw std::invalid_argument("an empty label cannot name a file");
  }
  std::string encoded = encodeLabel(label);
  if (encoded.size() > kMaxEncodedLabel) {
    throw std::invalid_argument("label '" + label + "' is too long for a file name (" +
                                std::to_string(encoded.size()) + " bytes encoded; at most " +
                                std::to_string(kMaxEncodedLabel) + ")");
  }
  return encoded;
}

}  // namespace

std::string encodeLabel(const std::string& label) {
  static const char* const kHex = "0123456789ABCDEF";
  std::string encoded;
  encoded.reserve(label.size());
  for (std::size_t i = 0; i < label.size(); ++i) {
    const auto c = static_cast<unsigned char>(label[i]);
    if (plainByte(c, i == 0)) {
      encoded += static_cast<char>(c);
    } else {
      encoded += '%';
      encoded += kHex[c >> 4];
      encoded += kHex[c & 0xF];
    }
  }
  return encoded;
}

std::optional<std::string> decodeLabel(const std::string& encoded) {
  if (encoded.empty()) {
    return std::nullopt;
  }
  std::string label;
  for (std::size_t i = 0; i < encoded.size(); ++i) {
    const auto c = static_cast<unsigned char>(encoded[i]);
    if (c != '%') {
      if (!plainByte(c, label.empty())) {
        return std::nullopt;
      }
      label += static_cast<char>(c);
      continue;
    }
    if (i + 2 >= encoded.size()) {
      return std::nullopt;
    }
    const int high = hexValue(encoded[i + 1]);
    const int low = hexValue(encoded[i + 2]);
    if (high < 0 || low < 0) {
      return std::nullopt;
    }
    const auto byte = static_cast<unsigned char>(high * 16 + low);
    if (plainByte(byte, label.empty())) {
      return std::nullopt;  // encodeLabel writes plain bytes as they are
    }
    label += static_cast<char>(byte);
    i += 2;
  }
  return label;
}

std::string objectFileName(const std::string& label, const std::string& stamp,
                           std::size_t label_index) {
  return checkedEncoding(label) + "-" + stamp + "-" + std::to_string(label_index) + ".pcd";
}

std::string objectClass(const fs::path& file) {
  const std::string name = file.filename().string();
  const std::size_t dash = name.find('-');
  if (dash == std::string::npos) {
    return "";
  }
  return decodeLabel(name.substr(0, dash)).value_or("");
}

std::string modelFileName(const std::string& label) { return checkedEncoding(label) + ".pcd"; }

std::string modelClass(const fs::path& file) {
  return decodeLabel(file.stem().string()).value_or("");
}

void requireObjectsFolder(const fs::path& folder) {
  if (!fs::is_directory(folder)) {
    throw std::runtime_error(folder.string() + ": no such objects folder");
  }
}

std::map<std::string, std::vector<fs::path>> listObjectFiles(const fs::path& folder,
                                                             std::vector<std::string>* unnamed) {
  requireObjectsFolder(folder);
  std::map<std::string, std::vector<fs::path>> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || entry.path().extension() != ".pcd" || name[0] == '.') {
      continue;
    }
    const std::string label = objectClass(entry.path());
    if (label.empty()) {
      if (unnamed != nullptr) {
        unnamed->push_back(name);
      }
      continue;
    }
    files[label].push_back(entry.path());
  }
  for (auto& [label, paths] : files) {
    std::sort(paths.begin(), paths.end());
  }
  if (unnamed != nullptr) {
    std::sort(unnamed->begin(), unnamed->end());
  }
  return files;
}

std::vector<fs::path> listAllObjectFiles(const fs::path& folder,
                                         std::map<std::string, std::vector<fs::path>>* by_class) {
  std::vector<std::string> unnamed;
  const std::map<std::string, std::vector<fs::path>> classes = listObjectFiles(folder, &unnamed);
  std::vector<fs::path> files;
  for (const auto& [label, paths] : classes) {
    files.insert(files.end(), paths.begin(), paths.end());
  }
  for (const std::string& name : unnamed) {
    files.push_back(folder / name);
  }
  if (files.empty()) {
    throw std::runtime_error(folder.string() +
                             ": no object PCDs (<Class>-<stamp>-<index>.pcd) in this folder");
  }
  std::sort(files.begin(), files.end());
  if (by_class != nullptr) {
    *by_class = classes;
  }
  return files;
}

}  // namespace granular
