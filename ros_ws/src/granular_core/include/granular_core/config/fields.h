#pragma once

// One field list per config struct. (Over 400 lines: the templates that walk a field list to
// validate, compare, write, read and describe a config belong together, and are header-only.)
// Each config declares, next to its members,
//
//   template <class Self, class Visit>
//   static void fields(Self& self, Visit& visit) {
//     visit("cell_size", self.cell_size, positive("m"));   // a value and what it may be
//     visit("icp", self.icp);                               // a nested config
//   }
//
// and everything that used to be written once per field comes from that list: validation
// (validateFields), equality (the operator== below), JSON writing (toJson), strict reading
// (readJson: an unknown key is an error naming the known ones; the YAML files and the nodes'
// parameters go through it) and the defaults that --help prints (describeFields).
//
// Values: double, int, std::size_t, std::uint32_t, bool, std::string, std::optional<double>,
// Eigen::Vector3d (three numbers), enums with EnumNames, and std::vector of numbers, strings
// or enums. Nested: configs with fields, std::map<std::string, Config> (each entry read over
// the one already there) and Overrides<Config> (per-name changes to a shared config).

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace granular {
namespace config {

using Json = nlohmann::ordered_json;

/// What a value may be: its unit (for --help) and its range, checked by validateFields (and,
/// for whole numbers that cannot be negative, when read). Numbers must be finite unless
/// `finite` is false.
struct Spec {
  const char* unit = "";
  std::optional<double> min;
  bool min_open = false;  ///< min itself excluded
  std::optional<double> max;
  bool max_open = false;  ///< max itself excluded
  bool finite = true;
  /// What a text value is, for errors ("a label"); a text list's items must not be empty.
  const char* expected = "a name";
  /// A list must not be empty.
  bool non_empty = false;
  /// A text may be empty (it means "none"); otherwise an empty text is an error.
  bool empty_text = false;
  /// An optional number left unset means "worked out from the data": written and read as
  /// "auto" (null is read as auto too).
  bool automatic = false;
};

/// Values from `min` to `max` (each excluded when open), in `unit`.
inline Spec interval(double min, double max, const char* unit = "", bool min_open = false,
                     bool max_open = false) {
  Spec spec;
  spec.unit = unit;
  spec.min = min;
  spec.min_open = min_open;
  spec.max = max;
  spec.max_open = max_open;
  return spec;
}
inline Spec any(const char* unit = "") {
  Spec spec;
  spec.unit = unit;
  return spec;
}
inline Spec atLeast(double min, const char* unit = "") {
  Spec spec = any(unit);
  spec.min = min;
  return spec;
}
inline Spec nonNegative(const char* unit = "") { return atLeast(0.0, unit); }
inline Spec positive(const char* unit = "") {
  Spec spec = atLeast(0.0, unit);
  spec.min_open = true;
  return spec;
}
inline Spec fraction() { return interval(0.0, 1.0, "", false, true); }  ///< [0, 1)
inline Spec text(const char* expected) {
  Spec spec;
  spec.expected = expected;
  return spec;
}
/// A number, or "auto" (an unset std::optional<double>) for one worked out from the data.
inline Spec automatic(const char* unit = "") {
  Spec spec = any(unit);
  spec.automatic = true;
  return spec;
}

/// A text where "" means none.
inline Spec optionalText(const char* expected) {
  Spec spec = text(expected);
  spec.empty_text = true;
  return spec;
}
inline Spec nonEmpty(Spec spec) {
  spec.non_empty = true;
  return spec;
}

/// Names of an enum's values: specialise with `what` ("stage") and `values`, pairs of the
/// value and its name, in the order --help lists them.
template <typename E>
struct EnumNames;

template <typename E>
const char* enumName(E value) {
  for (const auto& [candidate, name] : EnumNames<E>::values) {
    if (candidate == value) {
      return name;
    }
  }
  return "unknown";
}

template <typename E>
std::optional<E> enumFromName(const std::string& name) {
  for (const auto& [value, candidate] : EnumNames<E>::values) {
    if (name == candidate) {
      return value;
    }
  }
  return std::nullopt;
}

/// "a, b or c": the names of every value of E.
template <typename E>
std::string enumChoices() {
  std::string text;
  const auto& values = EnumNames<E>::values;
  for (std::size_t i = 0; i < values.size(); ++i) {
    text += (i == 0 ? "" : (i + 1 == values.size() ? " or " : ", ")) +
            std::string(values[i].second);
  }
  return text;
}

/// Per-name changes to a shared config (the per-class filter chains): each entry holds only
/// the keys it changes, in the config's own layout, and resolve() lays them over the shared
/// config. Read entries merge into what is there.
template <typename Config>
struct Overrides {
  using value_type = Config;
  std::map<std::string, Json> by_name;

  Json& operator[](const std::string& name) { return by_name[name]; }
  bool operator==(const Overrides& other) const {
    // Whatever order the keys were set in.
    return nlohmann::json::parse(Json(by_name).dump()) ==
           nlohmann::json::parse(Json(other.by_name).dump());
  }
};

/// Throws std::invalid_argument(what) unless `condition`: the checks between fields that a
/// field list cannot state (min_z below max_z, a stage listed once).
inline void require(bool condition, const std::string& what) {
  if (!condition) {
    throw std::invalid_argument(what);
  }
}

/// A config error found while reading: the dotted key and what is wrong with it.
class FieldError : public std::runtime_error {
 public:
  FieldError(std::string key, const std::string& what)
      : std::runtime_error((key.empty() ? std::string() : key + ": ") + what),
        key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

namespace detail {

template <typename T, typename = void>
struct HasFields : std::false_type {};
struct NoVisit {
  template <typename... A>
  void operator()(A&&...) {}
};
template <typename T>
struct HasFields<T, std::void_t<decltype(T::fields(std::declval<T&>(), std::declval<NoVisit&>()))>>
    : std::true_type {};

template <typename T>
struct IsVector : std::false_type {};
template <typename T>
struct IsVector<std::vector<T>> : std::true_type {};
template <typename T>
struct IsMap : std::false_type {};
template <typename T>
struct IsMap<std::map<std::string, T>> : std::true_type {};
template <typename T>
struct IsOverrides : std::false_type {};
template <typename T>
struct IsOverrides<Overrides<T>> : std::true_type {};

inline std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

inline std::string number(double value) {
  if (!std::isfinite(value)) {  // JSON would write null
    return std::isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf");
  }
  Json json = value;
  return json.dump();
}

// The text of a scalar for "got '...'".
inline std::string shown(const Json& node) {
  return node.is_string() ? node.get<std::string>() : node.dump();
}

// Numbers come as JSON numbers, or as text from YAML (which knows no types): parsed whole.
inline std::optional<double> parseNumber(const Json& node) {
  if (node.is_number()) {
    return node.get<double>();
  }
  if (!node.is_string()) {
    return std::nullopt;
  }
  const std::string text = node.get<std::string>();
  if (text == ".inf" || text == "+.inf" || text == ".Inf") {
    return HUGE_VAL;
  }
  if (text == "-.inf" || text == "-.Inf") {
    return -HUGE_VAL;
  }
  if (text == ".nan" || text == ".NaN") {
    return NAN;
  }
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) {
      return value;
    }
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

inline std::optional<long long> parseInteger(const Json& node) {
  if (node.is_number_integer()) {
    return node.get<long long>();
  }
  if (!node.is_string()) {
    return std::nullopt;
  }
  const std::string text = node.get<std::string>();
  try {
    std::size_t used = 0;
    const long long value = std::stoll(text, &used);
    if (used == text.size()) {
      return value;
    }
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// ---- writing -----------------------------------------------------------------------------

template <typename T>
Json write(const T& value);

struct Writer {
  Json& out;
  template <typename T>
  void operator()(const char* name, const T& value, const Spec& spec = {}) {
    if constexpr (std::is_same_v<T, std::optional<double>>) {
      if (!value && spec.automatic) {
        out[name] = "auto";
        return;
      }
    }
    out[name] = write(value);
  }
};

template <typename T>
Json write(const T& value) {
  if constexpr (HasFields<T>::value) {
    Json out = Json::object();
    Writer writer{out};
    T::fields(value, writer);
    return out;
  } else if constexpr (IsMap<T>::value) {
    Json out = Json::object();
    for (const auto& [name, entry] : value) {
      out[name] = write(entry);
    }
    return out;
  } else if constexpr (IsOverrides<T>::value) {
    Json out = Json::object();
    for (const auto& [name, entry] : value.by_name) {
      out[name] = entry;
    }
    return out;
  } else if constexpr (IsVector<T>::value) {
    Json out = Json::array();
    for (const auto& item : value) {
      out.push_back(write(item));
    }
    return out;
  } else if constexpr (std::is_enum_v<T>) {
    return enumName(value);
  } else if constexpr (std::is_same_v<T, std::optional<double>>) {
    return value ? Json(*value) : Json(nullptr);
  } else if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
    return Json::array({value.x(), value.y(), value.z()});
  } else {
    return Json(value);
  }
}

// ---- reading -----------------------------------------------------------------------------

template <typename T>
void read(const Json& node, T& value, const std::string& key, const Spec& spec);

struct Reader {
  const Json& node;
  const std::string& path;
  std::vector<std::string> known;
  template <typename T>
  void operator()(const char* name, T& value, const Spec& spec = {}) {
    known.push_back(name);
    const auto found = node.find(name);
    if (found != node.end()) {
      read(*found, value, join(path, name), spec);
    }
  }
};

// The keys of `node` that `known` lacks: an error naming the first and the known ones.
inline void rejectUnknown(const Json& node, const std::vector<std::string>& known,
                          const std::string& path) {
  for (const auto& entry : node.items()) {
    bool found = false;
    for (const std::string& name : known) {
      found = found || name == entry.key();
    }
    if (!found) {
      std::string names;
      for (const std::string& name : known) {
        names += (names.empty() ? "" : ", ") + name;
      }
      throw FieldError(join(path, entry.key()), "unknown key (known: " + names + ")");
    }
  }
}

inline void requireMapping(const Json& node, const std::string& key, const char* of) {
  if (!node.is_object()) {
    throw FieldError(key, std::string("expected a mapping of ") + of);
  }
}

// The parts of `typed` at the keys of `shape` (recursively into mappings).
inline Json project(const Json& typed, const Json& shape) {
  if (!shape.is_object() || !typed.is_object()) {
    return typed;
  }
  Json out = Json::object();
  for (const auto& entry : shape.items()) {
    out[entry.key()] = project(typed.at(entry.key()), entry.value());
  }
  return out;
}

// `item`: an item of a list, where a value below the minimum is named as such at once (a
// scalar's range is validateFields' job; reading only refuses a negative count).
template <typename T>
T readScalar(const Json& node, const std::string& key, const Spec& spec, bool item = false) {
  if constexpr (std::is_same_v<T, bool>) {
    if (node.is_boolean()) {
      return node.get<bool>();
    }
    if (node.is_string() && (node == "true" || node == "false")) {
      return node == "true";
    }
    throw FieldError(key, "expected true or false" +
                              (node.is_primitive() ? ", got '" + shown(node) + "'" : ""));
  } else if constexpr (std::is_enum_v<T>) {
    const std::string name = node.is_string() ? node.get<std::string>() : shown(node);
    const std::optional<T> value = enumFromName<T>(name);
    if (!node.is_string() || !value) {
      throw FieldError(key, "expected " + enumChoices<T>() + ", got '" + name + "'");
    }
    return *value;
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!node.is_string() || (node.get<std::string>().empty() && !spec.empty_text)) {
      throw FieldError(key, std::string("expected ") + spec.expected);
    }
    return node.get<std::string>();
  } else if constexpr (std::is_integral_v<T>) {
    const std::optional<long long> value = parseInteger(node);
    if (!node.is_primitive() || !value) {
      throw FieldError(key, "expected an integer" +
                                (node.is_primitive() ? ", got '" + shown(node) + "'" : ""));
    }
    const double least = item ? std::max(0.0, spec.min.value_or(0.0)) : 0.0;
    if (std::is_unsigned_v<T> && *value < least) {
      throw FieldError(key, least > 0.0 ? "must be at least " + number(least) + ", got " +
                                              std::to_string(*value)
                                        : "must not be negative, got " + std::to_string(*value));
    }
    if (*value < static_cast<long long>(std::numeric_limits<T>::min()) ||
        static_cast<unsigned long long>(*value) >
            static_cast<unsigned long long>(std::numeric_limits<T>::max())) {
      throw FieldError(key, "integer out of range");
    }
    return static_cast<T>(*value);
  } else {
    static_assert(std::is_floating_point_v<T>, "unsupported config value");
    const std::optional<double> value = parseNumber(node);
    if (!node.is_primitive() || !value) {
      throw FieldError(key, "expected a number" +
                                (node.is_primitive() ? ", got '" + shown(node) + "'" : ""));
    }
    return static_cast<T>(*value);
  }
}

template <typename T>
void read(const Json& node, T& value, const std::string& key, const Spec& spec) {
  if constexpr (HasFields<T>::value) {
    if (node.is_null()) {
      return;  // an empty section changes nothing
    }
    requireMapping(node, key, "keys to values");
    Reader reader{node, key, {}};
    T::fields(value, reader);
    rejectUnknown(node, reader.known, key);
  } else if constexpr (IsMap<T>::value) {
    if (node.is_null()) {
      return;
    }
    requireMapping(node, key, "names to settings");
    for (const auto& entry : node.items()) {
      // operator[]: a new name starts from the defaults, a known one is changed.
      read(entry.value(), value[entry.key()], join(key, entry.key()), spec);
    }
  } else if constexpr (IsOverrides<T>::value) {
    if (node.is_null()) {
      return;
    }
    requireMapping(node, key, "names to settings");
    for (const auto& entry : node.items()) {
      // Read into a scratch config first, so that a misspelt key is named now, and keep the
      // changed keys with their values as read (typed: "0.2" from YAML is the number 0.2).
      typename T::value_type scratch;
      read(entry.value(), scratch, join(key, entry.key()), spec);
      value.by_name[entry.key()].merge_patch(project(write(scratch), entry.value()));
    }
  } else if constexpr (IsVector<T>::value) {
    using Item = typename T::value_type;
    if (!node.is_array()) {
      throw FieldError(key, "expected a list, e.g. [1, 2]");
    }
    if (spec.non_empty && node.empty()) {
      throw FieldError(key, "expected at least one value");
    }
    T items;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string item_key = key + "[" + std::to_string(i) + "]";
      if constexpr (std::is_enum_v<Item>) {
        const std::string name = node[i].is_string() ? node[i].get<std::string>() : shown(node[i]);
        const std::optional<Item> item = enumFromName<Item>(name);
        if (!item) {
          throw FieldError(item_key, std::string("unknown ") + EnumNames<Item>::what + " '" +
                                         name + "' (known: " + enumChoices<Item>() + ")");
        }
        items.push_back(*item);
      } else {
        items.push_back(readScalar<Item>(node[i], item_key, spec, true));
      }
    }
    value = std::move(items);
  } else if constexpr (std::is_same_v<T, std::optional<double>>) {
    if (node.is_null() || (spec.automatic && node.is_string() && node == "auto")) {
      value.reset();
    } else {
      value = readScalar<double>(node, key, spec);
    }
  } else if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
    if (!node.is_array() || node.size() != 3) {
      throw FieldError(key, "expected three values [x, y, z]");
    }
    for (Eigen::Index axis = 0; axis < 3; ++axis) {
      value[axis] = readScalar<double>(node[static_cast<std::size_t>(axis)],
                                       key + "[" + std::to_string(axis) + "]", spec);
    }
  } else {
    value = readScalar<T>(node, key, spec);
  }
}

// ---- validation ----------------------------------------------------------------------------

inline void checkNumber(double value, const std::string& key, const Spec& spec) {
  const bool below = spec.min && (spec.min_open ? !(value > *spec.min) : !(value >= *spec.min));
  const bool above = spec.max && (spec.max_open ? !(value < *spec.max) : !(value <= *spec.max));
  if ((spec.finite && !std::isfinite(value)) || below || above) {
    std::string range;
    if (spec.min && spec.max) {
      range = std::string("in ") + (spec.min_open ? "(" : "[") + number(*spec.min) + ", " +
              number(*spec.max) + (spec.max_open ? ")" : "]");
    } else if (spec.min && *spec.min == 0.0) {
      range = spec.min_open ? "a positive number" : "a number >= 0";
    } else if (spec.min) {
      range = std::string("at least ") + number(*spec.min);
    } else {
      range = "a finite number";
    }
    throw std::invalid_argument(key + " must be " + range + ", got " + number(value));
  }
}

template <typename T>
void check(const T& value, const std::string& key, const Spec& spec);

struct Checker {
  const std::string& path;
  template <typename T>
  void operator()(const char* name, const T& value, const Spec& spec = {}) {
    check(value, join(path, name), spec);
  }
};

template <typename T>
void check(const T& value, const std::string& key, const Spec& spec) {
  if constexpr (HasFields<T>::value) {
    Checker checker{key};
    T::fields(value, checker);
  } else if constexpr (IsMap<T>::value) {
    for (const auto& [name, entry] : value) {
      check(entry, join(key, name), spec);
    }
  } else if constexpr (IsOverrides<T>::value) {
    // Checked by the owner, which knows the shared config they change.
  } else if constexpr (IsVector<T>::value) {
    if (spec.non_empty && value.empty()) {
      throw std::invalid_argument(key + " must hold at least one value");
    }
    for (std::size_t i = 0; i < value.size(); ++i) {
      check(value[i], key + "[" + std::to_string(i) + "]", spec);
    }
  } else if constexpr (std::is_same_v<T, std::optional<double>>) {
    if (value) {
      checkNumber(*value, key, spec);
    }
  } else if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
    for (Eigen::Index axis = 0; axis < 3; ++axis) {
      checkNumber(value[axis], key + "[" + std::to_string(axis) + "]", spec);
    }
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (value.empty() && !spec.empty_text) {
      throw std::invalid_argument(key + " must not be empty");
    }
  } else if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
    checkNumber(static_cast<double>(value), key, spec);
  }
}

// ---- description --------------------------------------------------------------------------

struct Describer {
  const std::string& path;
  std::vector<std::string>& lines;
  template <typename T>
  void operator()(const char* name, const T& value, const Spec& spec = {}) {
    const std::string key = join(path, name);
    if constexpr (HasFields<T>::value) {
      Describer nested{key, lines};
      T::fields(value, nested);
    } else {
      Json shown_value;
      Writer writer{shown_value};
      writer("value", value, spec);
      std::string line = key + ": " + shown_value["value"].dump();
      if (*spec.unit != '\0') {
        line += std::string(" ") + spec.unit;
      }
      lines.push_back(line);
    }
  }
};

}  // namespace detail

/// The config as JSON, keys in field-list order.
template <typename Config>
Json toJson(const Config& config) {
  return detail::write(config);
}

/// Lays the keys of `node` over `config`, strictly: an unknown key, a value of the wrong type
/// or a list of the wrong length is a FieldError naming the dotted key (`path` first). Keys
/// left out keep their values. Ranges are validateFields' job.
template <typename Config>
void readJson(const Json& node, Config& config, const std::string& path = "") {
  detail::read(node, config, path, Spec{});
}

/// Throws std::invalid_argument naming the dotted key (after `path`) of the first value out
/// of its Spec's range.
template <typename Config>
void validateFields(const Config& config, const std::string& path = "") {
  detail::check(config, path, Spec{});
}

/// One line per value, "key.path: default unit", for --help.
template <typename Config>
std::vector<std::string> describeFields(const Config& config) {
  std::vector<std::string> lines;
  const std::string path;
  detail::Describer describer{path, lines};
  Config::fields(config, describer);
  return lines;
}

/// `base` with the changes of `overrides` for `name` (none: `base`). Throws FieldError naming
/// `path.name.key` for a change that does not fit Config's layout.
template <typename Config>
Config resolve(const Overrides<Config>& overrides, const std::string& name, const Config& base,
               const std::string& path = "") {
  Config config = base;
  const auto found = overrides.by_name.find(name);
  if (found != overrides.by_name.end()) {
    readJson(found->second, config, detail::join(path, name));
  }
  return config;
}

}  // namespace config

/// Equality of any two configs with a field list: every field equal.
template <typename Config, typename = std::enable_if_t<config::detail::HasFields<Config>::value>>
bool operator==(const Config& a, const Config& b) {
  // Compared as unordered JSON: the keys of per-name overrides may come in any order.
  return nlohmann::json::parse(config::toJson(a).dump()) ==
         nlohmann::json::parse(config::toJson(b).dump());
}

template <typename Config, typename = std::enable_if_t<config::detail::HasFields<Config>::value>>
bool operator!=(const Config& a, const Config& b) {
  return !(a == b);
}

}  // namespace granular
