// The one list parser of the command line and the scene files.
#include "lists.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace brittle {

std::vector<std::string> list_words(const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  for (char c : text) {
    if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
      if (!word.empty()) words.push_back(std::move(word));
      word.clear();
    } else {
      word += c;
    }
  }
  if (!word.empty()) words.push_back(std::move(word));
  return words;
}

std::vector<std::string> list_words(const std::vector<std::string>& values) {
  std::vector<std::string> words;
  for (const std::string& v : values)
    for (std::string& w : list_words(v)) words.push_back(std::move(w));
  return words;
}

std::optional<double> parse_number(const std::string& token) {
  double v = 0;
  const char* last = token.data() + token.size();
  const auto [end, ec] = std::from_chars(token.data(), last, v);
  if (token.empty() || ec != std::errc() || end != last || !std::isfinite(v)) return std::nullopt;
  return v;
}

NumberList parse_number_list(const std::string& text) {
  NumberList list;
  for (const std::string& w : list_words(text)) {
    const auto v = parse_number(w);
    if (!v) {
      list.bad = w;
      break;
    }
    list.values.push_back(*v);
  }
  return list;
}

std::string join_numbers(const std::vector<double>& values) {
  std::ostringstream s;
  s << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (std::size_t i = 0; i < values.size(); ++i) s << (i ? "," : "") << values[i];
  return s.str();
}

}  // namespace brittle
