#pragma once
// Lists of integers as a measurement's levels and orders are given: "a..b" (inclusive) or "a,b,c".
#include <string>
#include <vector>

namespace icobrdf::lab {

// The integers of `text` ("a..b" with a <= b, or a comma list), sorted and without repeats; ArgumentError
// naming `what` (the caller's name for the list) unless every value is an integer in [lo, hi].
std::vector<int> parse_int_list(const std::string& text, int lo, int hi, const std::string& what);

}  // namespace icobrdf::lab
