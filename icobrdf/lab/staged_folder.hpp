#pragma once
// A report assembled in a staging folder and moved into its destination folder only when complete, so that
// a failed run leaves the destination as it was. Error messages start with `label` (the caller's name for
// the destination).
#include <filesystem>
#include <string>

namespace icobrdf::lab {

// Refuses (IoError, before anything is replaced) a destination where a staged file's name is taken by
// anything but a regular file: a folder, FIFO, device, socket or symbolic link (icobrdf/io/output_path.hpp).
void check_staged_commit(const std::filesystem::path& stage, const std::filesystem::path& dir, const std::string& label);

// Moves the staged files into `dir`: a rename of the whole folder when `dir` does not exist, else file by
// file with report.md last (then the emptied stage is removed). Files of `dir` not staged are left alone.
void commit_staged(const std::filesystem::path& stage, const std::filesystem::path& dir, const std::string& label);

}  // namespace icobrdf::lab
