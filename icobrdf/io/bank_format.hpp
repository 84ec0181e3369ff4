#pragma once
// Name and version of the icobrdf HDF5 bank schema (docs/file-format.md).
//
// Versioning: MAJOR.MINOR. A minor bump only adds optional objects or attributes, so a reader accepts any
// minor of the majors it knows; a reader refuses a file of a newer major.
//   1.0  modes: spectra, IBSSS, LUTs, grid, operators.
//   2.0  adds materials with a half-angle lobe (/materials/<name>/half_angle and the attribute
//        representation). A 1.x reader would read such a material as its modes alone, silently wrong, so
//        these files carry major 2; the writer writes 1.0 when no material has a lobe (those files are
//        unchanged, and 1.x readers still read them).
//   3.0  lobes gain the quantity mean-cosine, the attribute corners ("valid": corner node pairs below the
//        horizon are dropped from the interpolation) and the stretch of anisotropic h grids (h_axis,
//        h_scale_1, h_scale_2). A 2.x reader would evaluate such lobes on the wrong interpolation, so files
//        with lobes carry major 3; 2.x files are still read (their lobes: corners "all", no stretch).
//   1.1 / 3.1  add the optional group /materials/<name>/sample_fit (the record of a fit of scattered samples:
//        standard errors, CV error, rank, condition, residual RMS); written only when a material has one,
//        and ignored by 1.0 / 3.0 readers, which lose nothing else.
//   4.0  lobes may store their factors as float32, int16 or int8 (attribute precision; integers with
//        per-column scales u_scale, v_scale) and share one factor set across channels with per-channel term
//        scales (attribute factor_sets = "shared", dataset channel_scales). A 3.x reader cannot read these
//        (element types and shapes differ), so files with such a lobe carry major 4 (4.1 with a sample_fit);
//        files whose lobes are float64 per channel are still written as 3.0 / 3.1.
namespace icobrdf::bank_format {

inline constexpr const char* kName = "icobrdf-bank";
inline constexpr int kMajor = 4;            // newest major this reader reads
inline constexpr int kOldestMajor = 1;      // oldest major this reader reads
inline constexpr const char* kVersion = "3.0";          // files with a half-angle lobe
inline constexpr const char* kVersionModesOnly = "1.0";  // files without
inline constexpr const char* kVersionSampleFit = "3.1";          // lobes, and a sample_fit record
inline constexpr const char* kVersionModesOnlySampleFit = "1.1";  // no lobe, a sample_fit record
inline constexpr const char* kVersionCompactLobes = "4.0";         // a lobe of float32 / integer / shared factors
inline constexpr const char* kVersionCompactLobesSampleFit = "4.1";  // the same, and a sample_fit record

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
