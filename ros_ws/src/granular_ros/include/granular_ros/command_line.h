#pragma once

#include <charconv>
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
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

/// A tool's options, each with where its value goes, read in one call:
///   OptionTable().flag("--help", options.help).value("--out", options.out).parse(argc, argv);
/// An option given twice keeps the last value; an unknown one is an error naming it.
class OptionTable {
 public:
  using Handler = std::function<void(OptionReader&)>;

  /// An option without a value; also under `alias` (e.g. "-h") when given.
  OptionTable& flag(const std::string& name, bool& field, const std::string& alias = "");
  /// --help and -h: when given, parse() does not ask for the required options.
  OptionTable& help(bool& field);
  /// A value the tool cannot run without: parse() fails when any is missing (or empty),
  /// naming every required option ("--a, --b and --c are required").
  OptionTable& required(const std::string& name, std::string& field);
  OptionTable& value(const std::string& name, std::string& field);
  OptionTable& value(const std::string& name, std::optional<std::string>& field);
  /// A value parsed as a number of T (parseNumber).
  template <typename T>
  OptionTable& number(const std::string& name, T& field);
  /// A thread count: a whole number of at least 1 (the field's 0 means every core).
  OptionTable& threads(const std::string& name, int& field);
  /// Any other handling of the current option (reader.value() for its value).
  OptionTable& custom(const std::string& name, Handler handler);

  void parse(int argc, char** argv) const;

 private:
  std::map<std::string, Handler> handlers_;
  bool* help_ = nullptr;
  std::vector<std::pair<std::string, const std::string*>> required_;  ///< in the order given
};

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

template <typename T>
OptionTable& OptionTable::number(const std::string& name, T& field) {
  return custom(name, [&field, name](OptionReader& reader) {
    field = parseNumber<T>(name, reader.value());
  });
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
