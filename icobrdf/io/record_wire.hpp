#pragma once
// A material record (icobrdf/io/spectrum_file.hpp MaterialRecord) as bytes, to move it between the processes
// of one job (icobrdf/cluster/distributed_bank.hpp), and back. Not a file format: nothing is ever written to
// disk in this form, and both ends are the same build.
//
// Exact: every field of the record travels, doubles as their 8 bytes, so the record read is the record
// written (the bank written from it is byte-identical; tests/io/test_record_wire.cpp checks this through
// bank_image for records with every part: channels, IBSSS, lobe, LUT, sample-fit record, figures, labels).
// A field added to MaterialRecord, Spectrum, SampleFitRecord or HalfAngleFactors must be added here too.
//
// Cost: a copy of the record's arrays. An order-6 record takes 4 us to make and read back, against 0.5 ms to
// make and 0.4 ms to read the same record as a one-material HDF5 image (bank_image; benchmarks/RESULTS.md).
//
// Layout: the tag "icobrdf-record-wire", a uint32 version (kRecordWireVersion), then the fields in a fixed
// order: integers as int64, flags as one byte, doubles as their IEEE bytes, strings and arrays with their
// lengths first; all in the host's byte order.
//
// read_record_wire checks the tag, the version, every length against the bytes left, and that nothing is
// left over; anything else is an InputError naming `name` and the byte offset. It does not validate the
// record's contents: the bank writer does that (write_material) wherever the record is written.
#include <cstdint>
#include <string>

#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf {

inline constexpr std::uint32_t kRecordWireVersion = 2;  // 2: lobes carry their precision and channel scales

std::string record_wire(const MaterialRecord& record);
MaterialRecord read_record_wire(const std::string& bytes, const std::string& name);

}  // namespace icobrdf
