// SPDX-License-Identifier: Apache-2.0
// Reading attachment areas from a JSON landmark file (see attachment_areas.h).
#include "model/attachment_areas.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

namespace rbfmuscle {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw ModelError("attachment areas file " + path + ": " + what);
}

std::string inQuotes(const std::string& s) { return "\"" + s + "\""; }

/// A JSON value as short text for a message: its dump, cut at 40 characters.
std::string shortDump(const Json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

/// "an array", "a string", "null", ... for a message.
std::string kindOf(const Json& value) {
  const std::string type = value.type_name();
  if (type == "null") return type;
  return (type == "array" || type == "object" ? "an " : "a ") + type;
}

/// The whole file as text, after checking that it exists, is a regular file
/// and is not larger than kMaxAttachmentAreasFileBytes.
std::string readText(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) fail(path, "no such file");
  if (ec) fail(path, "cannot be examined: " + ec.message());
  if (!fs::is_regular_file(status))
    fail(path, std::string("not a regular file (") +
                   (fs::is_directory(status) ? "a directory" : "a special file") +
                   "); expected a JSON file");
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) fail(path, "cannot be examined: " + ec.message());
  if (bytes > static_cast<std::uintmax_t>(kMaxAttachmentAreasFileBytes))
    fail(path, "is " + std::to_string(bytes) + " bytes, more than the " +
                   std::to_string(kMaxAttachmentAreasFileBytes) +
                   " bytes (64 MiB) read for a landmark file; is it the right file?");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, std::string("cannot be opened: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) fail(path, "cannot be read");
  return text.str();
}

/// Parses `text`; a syntax error names line, column and byte. Names defined
/// twice in the top object or in "clouds" (JSON keeps only the last) fail too.
Json parseJson(const std::string& path, const std::string& text) {
  std::set<std::string> top_keys, cloud_keys;
  std::string top_key, duplicate;
  const Json::parser_callback_t watch = [&](int depth, Json::parse_event_t event, Json& parsed) {
    if (event != Json::parse_event_t::key || !duplicate.empty()) return true;
    const std::string key = parsed.get<std::string>();
    if (depth == 1) {
      top_key = key;
      if (!top_keys.insert(key).second) duplicate = "member " + inQuotes(key);
    } else if (depth == 2 && top_key == "clouds" && !cloud_keys.insert(key).second) {
      duplicate = "cloud " + inQuotes(key);
    }
    return true;
  };
  Json root;
  try {
    root = Json::parse(text, watch);
  } catch (const Json::parse_error& e) {
    // nlohmann: "[json.exception.parse_error.101] parse error at line L, column C: ..."
    std::string reason = e.what();
    const auto at = reason.find("parse error");
    if (at != std::string::npos) reason = reason.substr(at);
    const std::size_t from = e.byte > 12 ? e.byte - 12 : 0;
    const std::string near = text.substr(std::min(from, text.size()), 24);
    const bool literal = near.find("NaN") != std::string::npos ||
                         near.find("Infinity") != std::string::npos;
    const std::string hint =
        literal ? "; JSON has no NaN or Infinity: every coordinate must be a finite number" : "";
    fail(path, "not valid JSON: " + reason + " (byte " + std::to_string(e.byte) + ")" + hint);
  } catch (const Json::exception& e) {
    // Numbers beyond double (1e400) end here: "number overflow parsing '1e400'".
    std::string reason = e.what();
    const auto bracket = reason.find("] ");
    if (bracket != std::string::npos) reason = reason.substr(bracket + 2);
    const auto open = reason.find('\'');
    const auto close = open == std::string::npos ? open : reason.find('\'', open + 1);
    if (close != std::string::npos) {
      const auto at = text.find(reason.substr(open + 1, close - open - 1));
      if (at != std::string::npos) {
        const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n');
        reason += " at line " + std::to_string(line);
      }
    }
    const bool overflow = reason.find("overflow") != std::string::npos;
    fail(path, "not valid JSON: " + reason +
                   (overflow ? "; every coordinate must be a finite number" : ""));
  }
  if (!duplicate.empty())
    fail(path, duplicate + " is defined twice; JSON keeps only the last, so one would be lost");
  return root;
}

std::string lowered(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Edit distance between two names, ignoring case.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      const std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

/// "no cloud X (did you mean Y?); the file's N clouds: ..." — every name,
/// sorted, for up to 20 clouds; otherwise the 10 closest to `name`.
[[noreturn]] void failNotFound(const std::string& path, const std::string& name,
                               const Json& clouds) {
  std::vector<std::pair<std::size_t, std::string>> by_distance;
  for (const auto& item : clouds.items())
    by_distance.emplace_back(editDistance(name, item.key()), item.key());
  std::sort(by_distance.begin(), by_distance.end());
  std::string message = "no cloud " + inQuotes(name);
  if (by_distance.empty()) fail(path, message + "; its \"clouds\" object is empty");
  // Suggest the closest name when it is a near miss, else the names containing `name`.
  std::vector<std::string> suggested;
  if (by_distance.front().first <= std::max<std::size_t>(2, name.size() / 3)) {
    suggested.push_back(by_distance.front().second);
  } else {
    for (const auto& entry : by_distance)
      if (lowered(entry.second).find(lowered(name)) != std::string::npos)
        suggested.push_back(entry.second);
    std::sort(suggested.begin(), suggested.end());
    if (suggested.size() > 3) suggested.clear();
  }
  for (std::size_t i = 0; i < suggested.size(); ++i)
    message += (i ? " or " : " (did you mean ") + inQuotes(suggested[i]) +
               (i + 1 == suggested.size() ? "?)" : "");
  const std::size_t total = by_distance.size();
  if (total > 20) by_distance.resize(10);
  std::vector<std::string> listed;
  for (const auto& entry : by_distance) listed.push_back(entry.second);
  std::sort(listed.begin(), listed.end());
  message += total > 20 ? "; the 10 closest of its " + std::to_string(total) + " clouds: "
                        : "; its " + std::to_string(total) + " clouds: ";
  for (std::size_t i = 0; i < listed.size(); ++i) message += (i ? ", " : "") + listed[i];
  fail(path, message);
}

/// The points of one cloud, checked one by one.
Eigen::Matrix3Xd readCloud(const std::string& path, const std::string& name, const Json& cloud) {
  const std::string where = "cloud " + inQuotes(name);
  if (!cloud.is_array())
    fail(path, where + " is " + kindOf(cloud) +
                   "; expected an array of points {\"name\": ..., \"mm\": [x, y, z]}");
  if (cloud.empty()) fail(path, where + " is empty; an attachment area needs at least one point");
  const std::size_t n = cloud.size();
  Eigen::Matrix3Xd points_mm(3, static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const Json& point = cloud[i];
    std::string at = where + ", point " + std::to_string(i + 1) + " of " + std::to_string(n);
    if (point.is_object() && point.contains("name") && point["name"].is_string())
      at += " (name " + inQuotes(point["name"].get<std::string>()) + ")";
    if (!point.is_object() || !point.contains("mm"))
      fail(path, at + ": expected an object with \"mm\": [x, y, z], found " + shortDump(point));
    const Json& mm = point["mm"];
    if (!mm.is_array() || mm.size() != 3)
      fail(path, at + ": \"mm\" is " + shortDump(mm) + "; expected 3 numbers [x, y, z]");
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string axis = std::string(1, "xyz"[k]);
      if (!mm[k].is_number())
        fail(path, at + ": coordinate " + axis + " is " + shortDump(mm[k]) + "; expected a number");
      const double value = mm[k].get<double>();
      if (!std::isfinite(value))
        fail(path, at + ": coordinate " + axis + " is not finite; expected a finite number");
      if (std::abs(value) > kMaxAttachmentCoordinateMm) {
        std::ostringstream m;
        m << at << ": coordinate " << axis << " = " << value
          << " mm is implausible (magnitude above " << kMaxAttachmentCoordinateMm << " mm)";
        fail(path, m.str());
      }
      points_mm(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = value;
    }
  }
  return points_mm;
}

}  // namespace

std::vector<AttachmentArea> readAttachmentAreas(const std::string& json_path,
                                                const std::vector<std::string>& cloud_names) {
  std::map<std::string, std::size_t> first_asked;
  for (std::size_t i = 0; i < cloud_names.size(); ++i) {
    const auto inserted = first_asked.emplace(cloud_names[i], i);
    if (!inserted.second)
      fail(json_path, "cloud " + inQuotes(cloud_names[i]) + " is asked twice (names " +
                          std::to_string(inserted.first->second + 1) + " and " +
                          std::to_string(i + 1) + " of the list)");
  }

  const Json root = parseJson(json_path, readText(json_path));
  if (!root.is_object())
    fail(json_path, "the top value is " + kindOf(root) +
                        "; expected an object with \"units\" and \"clouds\"");
  if (!root.contains("units"))
    fail(json_path, "no \"units\" member; expected \"units\": \"mm\"");
  if (root["units"] != "mm")
    fail(json_path, "\"units\" is " + shortDump(root["units"]) + "; only \"mm\" is read");
  if (!root.contains("clouds")) fail(json_path, "no \"clouds\" object");
  const Json& clouds = root["clouds"];
  if (!clouds.is_object())
    fail(json_path, "\"clouds\" is " + kindOf(clouds) +
                        "; expected an object of named clouds");

  std::vector<AttachmentArea> areas;
  areas.reserve(cloud_names.size());
  for (const std::string& name : cloud_names) {
    const auto found = clouds.find(name);
    if (found == clouds.end()) failNotFound(json_path, name, clouds);
    areas.push_back({name, readCloud(json_path, name, *found)});
  }
  return areas;
}

Eigen::Matrix3Xd joinAreas(const std::vector<AttachmentArea>& areas) {
  Eigen::Index count = 0;
  for (const AttachmentArea& area : areas) count += area.points_mm.cols();
  Eigen::Matrix3Xd points(3, count);
  Eigen::Index at = 0;
  for (const AttachmentArea& area : areas) {
    points.middleCols(at, area.points_mm.cols()) = area.points_mm;
    at += area.points_mm.cols();
  }
  return points;
}

}  // namespace rbfmuscle
