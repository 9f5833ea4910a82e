#include "rvor/spec_text.h"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace rvor {

namespace {

// `text` without one leading '+', which from_chars does not take (it takes '-'); nothing for a
// second sign ("+-1").
std::optional<std::string_view> without_plus(std::string_view text) {
  if (text.empty() || text.front() != '+') return text;
  text.remove_prefix(1);
  if (!text.empty() && text.front() == '-') return std::nullopt;
  return text;
}

}  // namespace

std::optional<long long> parse_integer(std::string_view signed_text) {
  const std::optional<std::string_view> text = without_plus(signed_text);
  if (!text || text->empty()) return std::nullopt;
  long long value = 0;
  const char* end = text->data() + text->size();
  const auto [stop, error] = std::from_chars(text->data(), end, value);
  if (error != std::errc() || stop != end) return std::nullopt;
  return value;
}

std::optional<double> parse_decimal(std::string_view signed_text) {
  const std::optional<std::string_view> unsigned_text = without_plus(signed_text);
  if (!unsigned_text) return std::nullopt;
  const std::string_view text = *unsigned_text;
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value, std::chars_format::general);
  if (text.empty() || error != std::errc() || stop != end || !std::isfinite(value))
    return std::nullopt;
  return value;
}

namespace {

template <typename Real>
std::string shortest_text(Real value) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

}  // namespace

std::string exact_text(double value) {
  return shortest_text(value);
}
std::string exact_text(float value) {
  return shortest_text(value);
}

std::string quoted_text(std::string_view text, std::size_t most) {
  std::string quoted = "'";
  for (const char c : text.substr(0, most)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7F) {
      quoted += c;
      continue;
    }
    char escaped[5];
    std::snprintf(escaped, sizeof escaped, "\\x%02X", byte);
    quoted += escaped;
  }
  return quoted + (text.size() > most ? "...'" : "'");
}

std::vector<std::string> split_at(std::string_view text, char separator) {
  std::vector<std::string> items;
  while (true) {
    const std::size_t at = text.find(separator);
    items.emplace_back(text.substr(0, at));
    if (at == std::string_view::npos) return items;
    text.remove_prefix(at + 1);
  }
}

std::vector<std::string> split_commas(std::string_view text) {
  return split_at(text, ',');
}

}  // namespace rvor
