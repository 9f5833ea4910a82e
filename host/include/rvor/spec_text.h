#pragma once
// How rvor reads numbers and lists in the text a user writes (domain and metric specs, seed and
// probe files, command-line values), and writes numbers back: one rule everywhere, independent of
// the C++ locale.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rvor {

// The whole text as a finite decimal number ("1", "-2.5", "+3e-4"): an optional sign, nothing
// before or after it (no blanks), no hexadecimal, inf or nan. A number beyond double's range
// gives nothing too.
std::optional<double> parse_decimal(std::string_view text);

// The whole text as a decimal integer ("12", "-3", "+4"), as parse_decimal reads a number: no
// blanks, no fraction, no exponent; nothing beyond long long's range.
std::optional<long long> parse_integer(std::string_view text);

// The shortest text that reads back as the same number (std::to_chars): what rvor writes in its
// text outputs (seeds.xyz, probe.csv, Medit files). inf and nan come out as "inf" and "nan".
std::string exact_text(double value);
std::string exact_text(float value);

// `text` quoted for an error message: cut after `most` bytes ("..." before the closing quote), its
// control bytes (a lone '\r' of old Mac line ends, NUL) and non-ASCII bytes written as \xNN, so
// that the terminal shows them instead of acting on them and the message stays valid UTF-8 (a
// binary file's bytes are not) and short (a damaged file's token can be megabytes).
std::string quoted_text(std::string_view text, std::size_t most = 80);

// `text` for a line on a terminal, whole: its control characters (C0, DEL, and C1 such as the
// 8-bit CSI) and the bytes that are not UTF-8 written as \xNN as quoted_text writes them, so that
// an escape sequence given on the command line is shown rather than obeyed; valid UTF-8 (a file
// name's accents) is kept.
std::string printable_text(std::string_view text);

// The items between separators, every one of them: with ',', "1,,2," gives "1", "", "2", "" so
// that callers can report empty items; "" gives one empty item.
std::vector<std::string> split_at(std::string_view text, char separator);

// split_at(text, ','): the lists of specs and options.
std::vector<std::string> split_commas(std::string_view text);

// `text` without the blanks (spaces, tabs) around it: specs take "rect: -1, -1, 1, 1" as they
// take "rect:-1,-1,1,1", in domains and metrics alike.
std::string trim_blanks(std::string_view text);

}  // namespace rvor
