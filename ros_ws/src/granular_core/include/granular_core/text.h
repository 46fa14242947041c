#pragma once

// Small text helpers for the messages of every layer.

#include <sstream>
#include <string>
#include <vector>

namespace granular {

/// "a, b, c".
inline std::string joined(const std::vector<std::string>& items,
                          const std::string& separator = ", ") {
  std::string text;
  for (const std::string& item : items) {
    text += (text.empty() ? "" : separator) + item;
  }
  return text;
}

/// "12%": a share as a whole percentage.
inline std::string percent(double fraction) {
  std::ostringstream text;
  text.precision(0);
  text << std::fixed << fraction * 100.0 << "%";
  return text.str();
}

}  // namespace granular
