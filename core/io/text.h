// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Text helpers the readers share, header-only like format_number.h.
#include <sstream>
#include <string>
#include <vector>

namespace rbfmuscle::io {

/// `s` without its leading and trailing spaces, tabs, CRs and LFs.
inline std::string trimWhitespace(const std::string& s) {
  const char* space = " \t\r\n";
  const auto begin = s.find_first_not_of(space);
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(space) - begin + 1);
}

/// The parts of `s` between `separator`s, each trimmed; a trailing separator gives an empty
/// last part, and an empty `s` no part.
inline std::vector<std::string> splitTrimmed(const std::string& s, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(trimWhitespace(part));
  if (!s.empty() && s.back() == separator) parts.push_back("");
  return parts;
}

/// The words of `s`, split at any white space.
inline std::vector<std::string> splitWords(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

}  // namespace rbfmuscle::io
