// SPDX-License-Identifier: MIT
#include "cli/output_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "cli/args.h"
#include "core/common/error.h"
#include "core/io/file_bytes.h"

namespace volspline::cli {

namespace {

// The temporaries alive in this process, for the signal handler: fixed slots of plain chars,
// since a handler may only call async-signal-safe functions (unlink) on memory it can read
// without locks. A slot is published by setting its flag after the name is complete.
constexpr int kSlots = 32;
char g_temporary[kSlots][PATH_MAX];
std::atomic<bool> g_used[kSlots];

void remove_temporaries_and_die(int signal) {
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load()) ::unlink(g_temporary[i]);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

// Installed by every OutputFiles, not once per process: whatever replaced the handlers since
// (a test harness, a library) would otherwise leave the temporaries of this one behind.
void install_handlers() {
  struct sigaction action {};
  action.sa_handler = remove_temporaries_and_die;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
  ::sigaction(SIGHUP, &action, nullptr);
}

void publish(const std::string& path) {
  for (int i = 0; i < kSlots; ++i) {
    if (g_used[i].load() || path.size() >= PATH_MAX) continue;
    std::memcpy(g_temporary[i], path.c_str(), path.size() + 1);
    g_used[i].store(true);
    return;
  }
}

void retract(const std::string& path) {
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load() && path == g_temporary[i]) g_used[i].store(false);
}

std::string folder_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// The absolute path a name refers to: realpath of the file if it exists, else of its folder
// joined with the file name.
std::string resolved(const std::string& path) {
  char buffer[PATH_MAX];
  if (::realpath(path.c_str(), buffer)) return buffer;
  const std::string folder = folder_of(path);
  const auto slash = path.find_last_of('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (::realpath(folder.c_str(), buffer)) return std::string(buffer) + "/" + name;
  return path;
}

bool same_file(const std::string& a, const std::string& b) {
  if (resolved(a) == resolved(b)) return true;
  struct stat sa {}, sb {};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

}  // namespace

OutputFiles::OutputFiles() { install_handlers(); }

OutputFiles::~OutputFiles() { forget_temporaries(); }

void OutputFiles::forget_temporaries() {
  for (Output& out : outputs_) {
    if (out.temporary.empty()) continue;
    ::unlink(out.temporary.c_str());
    retract(out.temporary);
    out.temporary.clear();
  }
}

void OutputFiles::input(const std::string& path) { inputs_.push_back(path); }

void OutputFiles::output(const std::string& flag, const std::string& path) {
  if (path.empty()) throw UsageError(flag + " needs a file name");
  for (const std::string& in : inputs_)
    if (same_file(path, in)) throw UsageError(flag + " '" + path + "' is the input '" + in + "'; choose another file");
  for (const Output& out : outputs_)
    if (same_file(path, out.path))
      throw UsageError(flag + " '" + path + "' is also the " + out.flag + " output; choose another file");
  Output out;
  out.flag = flag;
  out.path = path;
  out.target = io::write_target(path);
  struct stat st {};
  if (::stat(out.target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw Error(flag + " '" + path + "' is a folder, not a file");
    if (!S_ISCHR(st.st_mode)) throw Error(flag + " '" + path + "' is not a regular file or character device");
    if (::access(out.target.c_str(), W_OK) != 0) throw Error(flag + " '" + path + "' is not writable");
    out.device = true;
  } else {
    const std::string folder = folder_of(out.target);
    struct stat fs {};
    if (::stat(folder.c_str(), &fs) != 0 || !S_ISDIR(fs.st_mode))
      throw Error(flag + " '" + path + "': the folder '" + folder + "' does not exist");
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
      throw Error(flag + " '" + path + "': the folder '" + folder + "' is not writable");
  }
  outputs_.push_back(std::move(out));
}

void OutputFiles::stage(const std::string& path, const std::string& bytes) {
  for (Output& out : outputs_) {
    if (out.path != path) continue;
    if (out.device) {
      out.bytes = bytes;
      out.staged = true;
      return;
    }
    try {
      const io::TemporaryFile tmp = io::create_temporary_beside(out.target);
      out.temporary = tmp.path;
      publish(tmp.path);
      io::write_and_close(tmp.fd, bytes, path);
    } catch (const Error& e) {
      throw WriteError(e.what());
    }
    out.staged = true;
    return;
  }
  throw std::logic_error("OutputFiles::stage: '" + path + "' was not registered");
}

void OutputFiles::commit() {
  // Devices first: a device that refuses its bytes (/dev/full) then leaves every file as it was.
  for (Output& out : outputs_) {
    if (!out.staged || !out.device) continue;
    try {
      io::write_file_atomic(out.target, out.bytes);
    } catch (const Error& e) {
      throw WriteError(e.what());
    }
  }
  for (Output& out : outputs_) {
    if (!out.staged || out.device) continue;
    if (std::rename(out.temporary.c_str(), out.target.c_str()) != 0)
      throw WriteError("cannot write '" + out.path + "': " + std::strerror(errno));
    retract(out.temporary);
    out.temporary.clear();
  }
}

}  // namespace volspline::cli
