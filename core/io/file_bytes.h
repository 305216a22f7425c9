// SPDX-License-Identifier: MIT
#pragma once

#include <string>

namespace volspline::io {

/// Reads a whole regular file into memory. Folders, devices, FIFOs and sockets are refused before
/// any byte is read (a device or FIFO would be read until memory runs out).
/// Throws volspline::Error naming the path if it is not a regular file or cannot be read.
std::string read_file_bytes(const std::string& path);

/// Throws volspline::Error "'PATH' is a folder, not a regular file" (or a device, FIFO, socket)
/// if path exists and is not a regular file (after symlinks). A missing path passes: its
/// reader reports it.
void refuse_special_file(const std::string& path);

/// True if path names a regular file (after symlinks).
bool is_regular_file(const std::string& path);

/// A new, empty file created beside a target: `fd` is open for writing, `path` its name.
struct TemporaryFile {
  int fd = -1;
  std::string path;
};

/// Creates `.NAME.tmp-volspline-XXXXXXXX` (random suffix) in the folder of `target` with
/// O_CREAT|O_EXCL|O_NOFOLLOW, so an existing file or symlink of that name is never followed or
/// reused. Its permissions are those of `target` if that is an existing regular file, else
/// 0666 less the umask. Throws volspline::Error naming `target` on failure.
TemporaryFile create_temporary_beside(const std::string& target);

/// Writes all bytes to fd (retrying short writes), flushes them to the file system and closes
/// fd. Throws volspline::Error naming `name` on failure (fd is closed either way).
void write_and_close(int fd, const std::string& bytes, const std::string& name);

/// The file that writing `path` should replace: `path` itself, or the file its symlink chain
/// ends at (so a symlinked output keeps its link). Unchanged if nothing exists there.
std::string write_target(const std::string& path);

/// Writes bytes to path: a temporary beside it (create_temporary_beside), then rename, so a
/// failure never leaves a half-written output. A target that is a character device
/// (/dev/null, /dev/full) is written directly, never renamed over; a folder, FIFO, socket or
/// block device is refused. Throws volspline::Error naming the path on failure.
void write_file_atomic(const std::string& path, const std::string& bytes);

/// Lower-case extension without the dot ("obj" for "a/b.OBJ"); empty if none.
std::string file_extension(const std::string& path);

}  // namespace volspline::io
