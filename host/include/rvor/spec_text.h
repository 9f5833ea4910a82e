#pragma once
// How rvor reads numbers and lists in the text a user writes (domain and metric specs, seed and
// probe files, command-line values): one rule everywhere, independent of the C++ locale.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rvor {

// The whole text as a finite decimal number ("1", "-2.5", "+3e-4"): an optional sign, nothing
// before or after it (no blanks), no hexadecimal, inf or nan. A number beyond double's range
// gives nothing too.
std::optional<double> parse_decimal(std::string_view text);

// The items between commas, every one of them: "1,,2," gives "1", "", "2", "" so that callers
// can report empty items; "" gives one empty item.
std::vector<std::string> split_commas(std::string_view text);

}  // namespace rvor
