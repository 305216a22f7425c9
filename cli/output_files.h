// SPDX-License-Identifier: MIT
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace volspline::cli {

/// Writing an output failed after the job ran (disk full, /dev/full, folder removed): exit 1.
class WriteError : public std::runtime_error {
 public:
  explicit WriteError(const std::string& message) : std::runtime_error(message) {}
};

/// The files a command reads and writes, checked before the work starts and written together
/// at its end. Every command uses it the same way:
///   OutputFiles files;  files.input(path);  files.output("--vtk", vtk_path);   // checks, exit 2
///   ... run the job ...
///   files.stage(vtk_path, bytes);  ...  files.commit();                        // exit 1 on failure
/// - an output resolving to an input or to another output (same file after following links
///   and "..", or a hard link of it) is refused: UsageError;
/// - an output's folder must exist and be writable, and the output must not be a folder, FIFO,
///   socket or block device: volspline::Error naming the flag, before any work;
/// - stage() writes the bytes to a fresh temporary beside the target (O_EXCL|O_NOFOLLOW, the
///   target's permissions); commit() renames all of them over their targets, one after another
///   with nothing left to compute in between; character devices (/dev/null) are written then,
///   directly, never renamed over;
/// - temporaries not committed are removed by the destructor (every error path) and by the
///   SIGINT/SIGTERM handler this class installs.
class OutputFiles {
 public:
  OutputFiles();
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  /// An input file of the command (for the collision check). Missing files are fine here: the
  /// reader reports them.
  void input(const std::string& path);
  /// An output named by `flag` ("-o", "--vtk"). Throws as described above.
  void output(const std::string& flag, const std::string& path);
  /// Writes the bytes of a registered output to its temporary. Throws WriteError.
  void stage(const std::string& path, const std::string& bytes);
  /// Moves every staged output into place. Throws WriteError.
  void commit();

 private:
  struct Output {
    std::string flag, path, target, temporary;
    std::string bytes;  // held for a character-device target, written at commit
    bool device = false, staged = false;
  };
  void forget_temporaries();
  std::vector<std::string> inputs_;
  std::vector<Output> outputs_;
};

}  // namespace volspline::cli
