#include "granular_core/dataset/objects_index.h"

#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace granular {
namespace {

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) {
    return text;
  }
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  }
  return quoted + '"';
}

// The fields of one CSV record starting at `line`; a quoted field may span lines, which are
// read from `stream`.
std::vector<std::string> csvFields(std::string line, std::istream& stream) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0;; ++i) {
    if (i == line.size()) {
      std::string next;
      if (!quoted || !std::getline(stream, next)) {
        break;
      }
      fields.back() += '\n';
      line = next;
      i = static_cast<std::size_t>(-1);
      continue;
    }
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

}  // namespace

const char* objectIndexHeader() {
  return "file,label,detection_id,stamp,points,range_m,length_m,width_m,height_m,yaw_rad\n";
}

std::string objectIndexLine(const ObjectIndexRow& row) {
  std::ostringstream line;
  line << csvField(row.file) << ',' << csvField(row.label) << ',' << row.detection_id << ','
       << csvField(row.stamp) << ',' << row.points << ',' << std::fixed << std::setprecision(4)
       << row.range << ',' << row.length << ',' << row.width << ',' << row.height << ','
       << std::setprecision(6) << row.yaw << '\n';
  return line.str();
}

std::vector<ObjectIndexRow> readObjectIndex(const std::filesystem::path& folder) {
  const std::filesystem::path file = folder / "index.csv";
  std::vector<ObjectIndexRow> rows;
  std::ifstream stream(file);
  if (!stream) {
    return rows;
  }
  std::string line;
  std::getline(stream, line);  // the header
  std::size_t number = 1;
  while (std::getline(stream, line)) {
    ++number;
    if (line.empty()) {
      continue;
    }
    const std::vector<std::string> fields = csvFields(line, stream);
    try {
      if (fields.size() != 10) {
        throw std::invalid_argument("10 fields expected");
      }
      ObjectIndexRow row;
      row.file = fields[0];
      row.label = fields[1];
      row.detection_id = fields[2];
      row.stamp = fields[3];
      row.points = std::stoul(fields[4]);
      row.range = std::stod(fields[5]);
      row.length = std::stod(fields[6]);
      row.width = std::stod(fields[7]);
      row.height = std::stod(fields[8]);
      row.yaw = std::stod(fields[9]);
      rows.push_back(row);
    } catch (const std::exception&) {
      throw std::runtime_error(file.string() + ": line " + std::to_string(number) +
                               " is not a row of an objects index (" + objectIndexHeader() +
                               ")");
    }
  }
  return rows;
}

}  // namespace granular
