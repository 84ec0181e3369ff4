#pragma once
// Each test file keeps its file-scope helpers in `namespace ICOBRDF_UNITY_ID { ... }`. The tests of a folder are
// one program, compiled in batches of files (unity builds, tests/CMakeLists.txt): there CMake defines
// ICOBRDF_UNITY_ID to a name unique to the file, so that equal names in two files of a batch do not meet.
// Compiled one file at a time (ICOBRDF_UNITY=OFF) it is empty and the namespace is anonymous.
#ifndef ICOBRDF_UNITY_ID
#define ICOBRDF_UNITY_ID
#endif
