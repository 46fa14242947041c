#include "granular_ros/command_line.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace granular_ros {

OptionReader::OptionReader(int argc, char** argv) : arguments_(argv + 1, argv + argc) {}

bool OptionReader::next() {
  if (next_ >= arguments_.size()) {
    return false;
  }
  name_ = arguments_[next_++];
  has_inline_value_ = false;
  const auto equals = name_.find('=');
  if (name_.rfind("--", 0) == 0 && equals != std::string::npos) {
    inline_value_ = name_.substr(equals + 1);
    has_inline_value_ = true;
    name_.resize(equals);
  }
  return true;
}

std::string OptionReader::value() {
  if (has_inline_value_) {
    return inline_value_;
  }
  if (next_ >= arguments_.size()) {
    throw std::invalid_argument(name_ + " needs a value");
  }
  return arguments_[next_++];
}

bool OptionReader::flag() {
  if (has_inline_value_) {
    throw std::invalid_argument(name_ + " takes no value");
  }
  return true;
}

void OptionReader::unknown() const {
  throw std::invalid_argument("unknown option '" + name_ + "'");
}

OptionTable& OptionTable::add(const std::string& name, const std::string& argument,
                              const std::string& text, Handler handler) {
  handlers_[name] = std::move(handler);
  entries_.push_back({argument.empty() ? name : name + " " + argument, text});
  return *this;
}

OptionTable& OptionTable::flag(const std::string& name, bool& field, const std::string& text) {
  return add(name, "", text, [&field](OptionReader& reader) { field = reader.flag(); });
}

OptionTable& OptionTable::help(bool& field) {
  help_ = &field;
  handlers_["--help"] = handlers_["-h"] = [&field](OptionReader& reader) {
    field = reader.flag();
  };
  return *this;
}

OptionTable& OptionTable::required(const std::string& name, std::string& field,
                                   const std::string& argument, const std::string& text) {
  required_.emplace_back(name, &field);
  return value(name, field, argument, text);
}

OptionTable& OptionTable::value(const std::string& name, std::string& field,
                                const std::string& argument, const std::string& text) {
  return add(name, argument, text, [&field](OptionReader& reader) { field = reader.value(); });
}

OptionTable& OptionTable::value(const std::string& name, std::optional<std::string>& field,
                                const std::string& argument, const std::string& text) {
  return add(name, argument, text, [&field](OptionReader& reader) { field = reader.value(); });
}

OptionTable& OptionTable::list(const std::string& name, std::vector<std::string>& field,
                               const std::string& argument, const std::string& text) {
  return add(name, argument, text,
             [&field, name](OptionReader& reader) { field = splitList(name, reader.value()); });
}

OptionTable& OptionTable::threads(const std::string& name, int& field, const std::string& text) {
  return add(name, "N", text, [&field, name](OptionReader& reader) {
    field = parseNumber<int>(name, reader.value());
    // Far more threads than any machine has cores only fail in OpenMP (or crash in it).
    constexpr int kMaxThreads = 1024;
    if (field < 1 || field > kMaxThreads) {
      throw std::invalid_argument(name + ": expected 1 to " + std::to_string(kMaxThreads) +
                                  " threads, got " + std::to_string(field));
    }
  });
}

OptionTable& OptionTable::custom(const std::string& name, const std::string& argument,
                                 const std::string& text, Handler handler) {
  return add(name, argument, text, std::move(handler));
}

std::string OptionTable::help() const {
  // The options in the first kColumn columns, their text beside them up to kWidth.
  constexpr std::size_t kColumn = 25;
  constexpr std::size_t kWidth = 90;
  std::vector<Entry> entries = entries_;
  if (help_ != nullptr) {
    entries.push_back({"-h, --help", "print this help and exit"});  // last, as the tools had it
  }
  std::string lines;
  for (const Entry& entry : entries) {
    std::string line = "  " + entry.names;
    const auto endLine = [&] {
      lines += line.substr(0, line.find_last_not_of(' ') + 1) + "\n";
      line = std::string(kColumn, ' ');
    };
    if (line.size() + 1 >= kColumn) {
      endLine();
    }
    line.resize(kColumn, ' ');
    std::istringstream paragraphs(entry.text);
    bool first_paragraph = true;
    for (std::string paragraph; std::getline(paragraphs, paragraph);) {
      if (!first_paragraph) {
        endLine();
      }
      first_paragraph = false;
      std::istringstream words(paragraph);
      for (std::string word; words >> word;) {
        if (line.size() > kColumn && line.size() + 1 + word.size() > kWidth) {
          endLine();
        }
        line += (line.size() > kColumn ? " " : "") + word;
      }
    }
    endLine();
  }
  return lines;
}

void OptionTable::parse(int argc, char** argv) const {
  if (help_ != nullptr && asksForHelp(argc, argv)) {
    *help_ = true;
    return;
  }
  OptionReader reader(argc, argv);
  while (reader.next()) {
    const auto handler = handlers_.find(reader.name());
    if (handler == handlers_.end()) {
      reader.unknown();
    }
    handler->second(reader);
  }
  if (help_ != nullptr && *help_) {
    return;
  }
  const bool missing = std::any_of(required_.begin(), required_.end(),
                                   [](const auto& option) { return option.second->empty(); });
  if (missing) {
    std::string names;
    for (std::size_t i = 0; i < required_.size(); ++i) {
      names += (i == 0 ? "" : i + 1 == required_.size() ? " and " : ", ") + required_[i].first;
    }
    throw std::invalid_argument(names + (required_.size() == 1 ? " is" : " are") + " required");
  }
}

std::vector<std::string> splitList(const std::string& option, const std::string& text) {
  std::vector<std::string> items;
  std::istringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty()) {
      throw std::invalid_argument(option + ": empty item in '" + text + "'");
    }
    items.push_back(item);
  }
  if (items.empty()) {
    throw std::invalid_argument(option + ": expected a comma-separated list");
  }
  return items;
}

ProgressReport::ProgressReport(std::size_t lines)
    : lines_(lines > 0 ? lines : 1), terminal_(terminal()) {}

bool ProgressReport::terminal() { return ::isatty(STDERR_FILENO) != 0; }

void ProgressReport::operator()(const std::string& what, std::size_t done, std::size_t total,
                                const std::string& unit) {
  if (total == 0) {
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (terminal_) {
    if (done == total || now - last_ >= std::chrono::milliseconds(100)) {
      std::fprintf(stderr, "\r%s: %zu/%zu %s (%zu%%)%s", what.c_str(), done, total,
                   unit.c_str(), done * 100 / total, done == total ? "\n" : "");
      last_ = now;
    }
  } else if (done == total || done * lines_ / total != (done - 1) * lines_ / total) {
    std::fprintf(stderr, "%s: %zu/%zu %s (%zu%%)\n", what.c_str(), done, total, unit.c_str(),
                 done * 100 / total);
  }
}

}  // namespace granular_ros
