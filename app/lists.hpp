// The one parser for lists on command lines and in scene values: tokens separated by commas
// and/or whitespace ("1e-6, 15e-6 30e-6", "sigma1,damage"), numbers read whole by from_chars.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace brittle {

/// The tokens of `text` split at commas and whitespace; empty tokens are dropped.
std::vector<std::string> list_words(const std::string& text);

/// The tokens of several values (a repeated option), each split as above, in order.
std::vector<std::string> list_words(const std::vector<std::string>& values);

/// `token` as a finite number if all of it is one (std::from_chars), else nothing.
std::optional<double> parse_number(const std::string& token);

/// The numbers of a list; `bad` is the first token that is not a finite number (then
/// `values` holds the numbers before it).
struct NumberList {
  std::vector<double> values;
  std::optional<std::string> bad;
};
NumberList parse_number_list(const std::string& text);

/// Numbers joined with commas at full precision, so that parse_number_list gives them back.
std::string join_numbers(const std::vector<double>& values);

}  // namespace brittle
