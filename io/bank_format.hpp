#pragma once
// Name and version of the icobrdf HDF5 bank schema (docs/file-format.md).
//
// Versioning: MAJOR.MINOR. A minor bump only adds optional objects or attributes, so a reader accepts any
// minor of its own major; a reader refuses a file of a newer major. Older majors are refused too until a
// reader for them exists (there is none: 1 is the first).
namespace icobrdf::bank_format {

inline constexpr const char* kName = "icobrdf-bank";
inline constexpr int kMajor = 1;
inline constexpr int kMinor = 0;
inline constexpr const char* kVersion = "1.0";

// Root attribute text describing conventions, written verbatim to every file.
inline constexpr const char* kConventions =
    "surface normal +z; directions are unit vectors with z >= 0, incident and remitted both pointing away "
    "from the surface (Nicodemus); hemisphere basis K_n^l = sqrt((n+1)/pi) R_n^|l|(rho) az_l(phi), "
    "rho = sqrt(2) sin(theta/2), orthonormal over the hemisphere with d(omega); single index "
    "j = (n(n+2)+l)/2 (ANSI); C_ab = integral integral f(w_i, w_r) K_a(w_i) K_b(w_r) dw_i dw_r "
    "(f in 1/sr, or g = f cos(theta_i) when cosine = 1); LUT[c, i, r] = cell average of f over incident "
    "cell i and remitted cell r";
inline constexpr const char* kAxisOrder = "row-major, logical shapes as documented";

// Object names.
inline constexpr const char* kGridGroup = "grid";
inline constexpr const char* kMaterialsGroup = "materials";
inline constexpr const char* kBasisGroup = "basis";

}  // namespace icobrdf::bank_format
