#pragma once
// A hint for large, freshly allocated buffers: back them by transparent huge pages (2 MiB) where the system
// allows it, so that the first write of a buffer of tens of megabytes costs a few dozen page faults instead
// of one per 4 KiB page (writing a fresh 46 MB buffer: 25 ms single-threaded with 4 KiB pages, 4.5 ms with
// huge pages, measured on the 2-core reference machine, Linux with THP in "madvise" mode). A cells x cells
// LUT that project_lut streams is read page after page, each 4 KiB page once: with huge pages the level-5
// projection at order 8 ran 2-3% faster (Zen 4, 2 threads, 3 alternated pairs, 2026-11-28: 0.0986-0.0999 s
// against 0.1007-0.1028 s), so the LUTs the library allocates (build_lut, the LUT reader) are advised too.
//
// On Linux this is madvise(MADV_HUGEPAGE) on the 2 MiB-aligned part of [data, data + bytes); elsewhere, for
// buffers below 4 MiB, or when the kernel refuses, it does nothing. Contents and validity are unaffected;
// call it before the buffer is first written (pages already present are not converted).
#include <Eigen/Core>
#include <cstddef>

namespace icobrdf {

constexpr std::size_t kHugePageBytes = std::size_t{1} << 21;  // 2 MiB: x86-64's transparent huge page

void advise_huge_pages(void* data, std::size_t bytes);

// A rows x cols matrix, uninitialized, its storage advised as above before anything is written to it.
Eigen::MatrixXd huge_page_matrix(Eigen::Index rows, Eigen::Index cols);

// Bytes of [data, data + bytes) that huge pages back now: the sum of AnonHugePages over the mappings of
// /proc/self/smaps that the range overlaps, at most `bytes` (the advised interior of a buffer is a mapping
// of its own; one mapping that also holds other memory could count that memory too). 0 off Linux, or when
// smaps cannot be read. Whether the kernel found the huge pages depends on how fragmented memory is, so a
// benchmark reports it (bench project: `lut_huge_page_fraction`).
std::size_t huge_page_bytes(const void* data, std::size_t bytes);

}  // namespace icobrdf
