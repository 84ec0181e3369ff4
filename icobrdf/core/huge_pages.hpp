#pragma once
// A hint for large, freshly allocated buffers: back them by transparent huge pages (2 MiB) where the system
// allows it, so that the first write of a buffer of tens of megabytes costs a few dozen page faults instead
// of one per 4 KiB page (writing a fresh 46 MB buffer: 25 ms single-threaded with 4 KiB pages, 4.5 ms with
// huge pages, measured on the 2-core reference machine, Linux with THP in "madvise" mode).
//
// On Linux this is madvise(MADV_HUGEPAGE) on the 2 MiB-aligned part of [data, data + bytes); elsewhere, for
// buffers below 4 MiB, or when the kernel refuses, it does nothing. Contents and validity are unaffected;
// call it before the buffer is first written (pages already present are not converted).
#include <cstddef>

namespace icobrdf {

void advise_huge_pages(void* data, std::size_t bytes);

}  // namespace icobrdf
