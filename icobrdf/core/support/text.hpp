#pragma once
// Small text helpers of the parsers (model specs, CSV files, HDF5 attribute paths and lists): bytes, not
// characters; white space is what std::isspace reports for a byte in the "C" locale (space, \t, \n, \v, \f, \r).
#include <string>
#include <vector>

namespace icobrdf {

// s without its leading and trailing white space ("" when it is all white space).
std::string trim(const std::string& s);

// The parts of s between the separator bytes, in order and untrimmed: n separators give n + 1 parts, empty parts
// kept ("" -> {""}, "a,,b," -> {"a", "", "b", ""}).
std::vector<std::string> split_at(const std::string& s, char separator);

}  // namespace icobrdf
