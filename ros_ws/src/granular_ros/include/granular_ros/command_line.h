#pragma once

#include <charconv>
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace granular_ros {

/// Whether -h or --help is anywhere among the arguments (after the program's name): the help
/// is then what the user asked for, whatever else the line holds, as argparse's tools do.
inline bool asksForHelp(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view argument(argv[i]);
    if (argument == "--help" || argument == "-h") {
      return true;
    }
  }
  return false;
}

/// The items of a comma-separated list, trimmed; an empty item or list is an error naming
/// `option`.
std::vector<std::string> splitList(const std::string& option, const std::string& text);

/// `text` as a number of type T, all of it; otherwise an error naming `option`.
template <typename T>
T parseNumber(const std::string& option, const std::string& text) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) {
    throw std::invalid_argument(option + ": '" + text + "' is not a valid number");
  }
  return value;
}

/// Walks a tool's arguments, `--name VALUE`, `--name=VALUE` and `--flag`, one option at a time.
/// Every problem is a std::invalid_argument that names the option.
class OptionReader {
 public:
  OptionReader(int argc, char** argv);

  /// Moves to the next option; false after the last one.
  bool next();
  /// The current option, e.g. "--out".
  const std::string& name() const { return name_; }
  /// The current option's value: the text after '=', or else the next argument.
  std::string value();
  /// For an option that takes no value: true, or an error when it was given one.
  bool flag();
  /// Throws the error for an option the tool does not know.
  [[noreturn]] void unknown() const;

 private:
  std::vector<std::string> arguments_;
  std::size_t next_ = 0;
  std::string name_;
  std::string inline_value_;
  bool has_inline_value_ = false;
};

/// A tool's options, each declared once with where its value goes and its --help line, read in
/// one call:
///   OptionTable().help(options.help).required("--out", options.out, "FILE", "file to write")
///       .parse(argc, argv);
/// An option given twice keeps the last value; an unknown one is an error naming it. help()
/// lists the options in the order declared, as gflags does from its flag definitions.
class OptionTable {
 public:
  using Handler = std::function<void(OptionReader&)>;

  /// An option without a value.
  OptionTable& flag(const std::string& name, bool& field, const std::string& text);
  /// --help and -h: when given, parse() does not ask for the required options.
  OptionTable& help(bool& field);
  /// A value the tool cannot run without: parse() fails when any is missing (or empty),
  /// naming every required option ("--a, --b and --c are required"). `argument` names the value
  /// in --help (FILE, FOLDER, N).
  OptionTable& required(const std::string& name, std::string& field, const std::string& argument,
                        const std::string& text);
  OptionTable& value(const std::string& name, std::string& field, const std::string& argument,
                     const std::string& text);
  OptionTable& value(const std::string& name, std::optional<std::string>& field,
                     const std::string& argument, const std::string& text);
  /// A value parsed as a number of T (parseNumber).
  template <typename T>
  OptionTable& number(const std::string& name, T& field, const std::string& argument,
                      const std::string& text);
  template <typename T>
  OptionTable& number(const std::string& name, std::optional<T>& field,
                      const std::string& argument, const std::string& text);
  /// A comma-separated list (splitList).
  OptionTable& list(const std::string& name, std::vector<std::string>& field,
                    const std::string& argument, const std::string& text);
  /// A comma-separated list of numbers of T; exactly `count` of them unless it is 0.
  template <typename T>
  OptionTable& numbers(const std::string& name, std::vector<T>& field, const std::string& argument,
                       const std::string& text, std::size_t count = 0);
  /// KEY=VALUE items, the option repeated for several; `argument` (e.g. CLASS=FILE.pcd) names
  /// the form in --help and errors. A key given twice is an error.
  template <typename V>
  OptionTable& keyValues(const std::string& name, std::map<std::string, V>& field,
                         const std::string& argument, const std::string& text);
  /// A thread count: a whole number of at least 1 (the field's 0 means every core).
  OptionTable& threads(const std::string& name, int& field, const std::string& text);
  /// Any other handling of the current option (reader.value() for its value; an empty
  /// `argument` for an option without one).
  OptionTable& custom(const std::string& name, const std::string& argument,
                      const std::string& text, Handler handler);

  void parse(int argc, char** argv) const;

  /// The options' --help lines: each option and its argument, then its text wrapped into the
  /// column beside (a '\n' in the text starts a new line there).
  std::string help() const;

 private:
  struct Entry {
    std::string names;  ///< "--out FILE", "-h, --help"
    std::string text;
  };
  OptionTable& add(const std::string& name, const std::string& argument, const std::string& text,
                   Handler handler);

  std::map<std::string, Handler> handlers_;
  std::vector<Entry> entries_;  ///< in the order declared
  bool* help_ = nullptr;
  std::vector<std::pair<std::string, const std::string*>> required_;  ///< in the order given
};

template <typename T>
OptionTable& OptionTable::numbers(const std::string& name, std::vector<T>& field,
                                  const std::string& argument, const std::string& text,
                                  std::size_t count) {
  return add(name, argument, text, [&field, name, argument, count](OptionReader& reader) {
    const std::string given = reader.value();
    const std::vector<std::string> items = splitList(name, given);
    if (count != 0 && items.size() != count) {
      throw std::invalid_argument(name + ": expected " + argument + ", got '" + given + "'");
    }
    field.clear();
    for (const std::string& item : items) {
      field.push_back(parseNumber<T>(name, item));
    }
  });
}

template <typename V>
OptionTable& OptionTable::keyValues(const std::string& name, std::map<std::string, V>& field,
                                    const std::string& argument, const std::string& text) {
  return add(name, argument, text, [&field, name, argument](OptionReader& reader) {
    const std::string item = reader.value();
    const auto separator = item.find('=');
    if (separator == 0 || separator == std::string::npos || separator + 1 == item.size()) {
      throw std::invalid_argument(name + ": expected " + argument + ", got '" + item + "'");
    }
    const std::string key = item.substr(0, separator);
    if (!field.emplace(key, V(item.substr(separator + 1))).second) {
      throw std::invalid_argument(name + ": '" + key + "' given twice");
    }
  });
}


template <typename T>
OptionTable& OptionTable::number(const std::string& name, T& field, const std::string& argument,
                                 const std::string& text) {
  return add(name, argument, text, [&field, name](OptionReader& reader) {
    field = parseNumber<T>(name, reader.value());
  });
}

template <typename T>
OptionTable& OptionTable::number(const std::string& name, std::optional<T>& field,
                                 const std::string& argument, const std::string& text) {
  return add(name, argument, text, [&field, name](OptionReader& reader) {
    field = parseNumber<T>(name, reader.value());
  });
}

/// `value` as --help shows it, as a stream writes it (0.5, 30), e.g. a default.
template <typename T>
std::string shown(const T& value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

/// "a,b,c" of a container's numbers, as --help shows a default list.
template <typename Container>
std::string joinedNumbers(const Container& numbers) {
  std::string text;
  for (const auto number : numbers) {
    text += (text.empty() ? "" : ",") + shown(number);
  }
  return text;
}

/// Progress of long work on stderr, "WHAT: DONE/TOTAL UNIT (P%)": on a terminal one line
/// redrawn at most ten times a second; in a log a line each time another 1/`lines` is done.
class ProgressReport {
 public:
  explicit ProgressReport(std::size_t lines = 10);

  void operator()(const std::string& what, std::size_t done, std::size_t total,
                  const std::string& unit);

  /// True when stderr is a terminal (a failure message must then start on a new line).
  static bool terminal();

 private:
  std::size_t lines_;
  bool terminal_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace granular_ros
