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

namespace {

void append_escaped(std::string& out, unsigned char byte) {
  char escaped[5];
  std::snprintf(escaped, sizeof escaped, "\\x%02X", byte);
  out += escaped;
}

// The length of the UTF-8 sequence at the start of `text` that encodes a printable code point
// (not C1, not a surrogate, no overlong form), or 0.
std::size_t printable_utf8_length(std::string_view text) {
  const auto lead = static_cast<unsigned char>(text[0]);
  std::size_t length = 0;
  char32_t code = 0;
  if (lead >= 0xC2 && lead <= 0xDF)
    length = 2, code = lead & 0x1F;
  else if (lead >= 0xE0 && lead <= 0xEF)
    length = 3, code = lead & 0x0F;
  else if (lead >= 0xF0 && lead <= 0xF4)
    length = 4, code = lead & 0x07;
  else
    return 0;
  if (text.size() < length) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    const auto next = static_cast<unsigned char>(text[i]);
    if ((next & 0xC0) != 0x80) return 0;
    code = (code << 6) | (next & 0x3F);
  }
  const char32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < least[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF) || code < 0xA0)
    return 0;
  return length;
}

}  // namespace

std::string quoted_text(std::string_view text, std::size_t most) {
  std::string quoted = "'";
  for (const char c : text.substr(0, most)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7F)
      quoted += c;
    else
      append_escaped(quoted, byte);
  }
  return quoted + (text.size() > most ? "...'" : "'");
}

std::string printable_text(std::string_view text) {
  std::string printable;
  printable.reserve(text.size());
  while (!text.empty()) {
    const auto byte = static_cast<unsigned char>(text[0]);
    std::size_t length = byte >= 0x20 && byte < 0x7F ? 1 : printable_utf8_length(text);
    if (length == 0) {
      append_escaped(printable, byte);
      length = 1;
    } else {
      printable.append(text.substr(0, length));
    }
    text.remove_prefix(length);
  }
  return printable;
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

std::string trim_blanks(std::string_view text) {
  const char* blanks = " \t";
  const std::size_t first = text.find_first_not_of(blanks);
  if (first == std::string_view::npos) return "";
  return std::string(text.substr(first, text.find_last_not_of(blanks) - first + 1));
}

}  // namespace rvor
