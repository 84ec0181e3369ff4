#pragma once
// Output paths: what a command may write, checked before it does any work, so that a bad -o fails at once
// (not after the work) and nothing that exists is destroyed. docs/reliability.md lists the tests.
//
// check_output_target(path): what atomic_write (icobrdf/io/atomic_write.hpp) itself refuses, before and again just
// before its rename. IoError (one line naming `path`, what it is and what was expected) when
//   - `path` is empty or names a folder ("", "x/", ".", "..");
//   - `path` exists and is not a regular file: a folder, a FIFO, a character or block device (/dev/null),
//     a socket. The rename would replace the node (as root, -o /dev/null would replace the system's) or
//     writers would block on a FIFO;
//   - `path` is a symbolic link, whatever it points to (named in the message): the rename would replace
//     the link, not the file it names. This refuses -o /dev/stdout, /dev/fd/N and /proc/self/fd/N too,
//     even when the descriptor is a regular file (rename would replace /dev/stdout itself). Name the file
//     the link points to instead;
//   - the folder of `path` is missing or not a folder.
// A dangling symbolic link is a link too: refused.
//
// check_output_path(path, inputs): check_output_target, then
//   - IoError when no file can be created in the folder of `path` (tried with a uniquely named empty file,
//     created with O_EXCL and removed at once: permission bits, read-only or special file systems);
//   - ArgumentError when `path` is the same file (device and inode: hard links and links to it count) as
//     one of the command's inputs. Refused, not forced: write elsewhere and rename. An input is given as on
//     the command line: a file, FILE.h5#MATERIAL, or any SOURCE; every file the text can name is compared
//     (the text itself, without a "kind:" prefix, without its "#..." suffix). Models name no file.
// Both only look: nothing is created at `path`, nothing existing is opened or changed.
#include <string>
#include <vector>

namespace icobrdf {

void check_output_target(const std::string& path);

void check_output_path(const std::string& path, const std::vector<std::string>& inputs = {});

}  // namespace icobrdf
