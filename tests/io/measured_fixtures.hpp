#pragma once
// Paths of the measured fixtures (tests/data/measured/README.md: CURET and NIST PTFE, with provenance).
#include <string>

namespace icobrdf::test {

inline std::string measured_fixture(const std::string& name) { return std::string(ICOBRDF_SOURCE_DIR) + "/tests/data/measured/" + name; }

}  // namespace icobrdf::test
