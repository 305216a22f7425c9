// SPDX-License-Identifier: MIT
#include "core/io/file_bytes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>

#include "core/common/error.h"

namespace volspline::io {

namespace {

std::string folder_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISCHR(mode)) return "a character device";
  return "not a regular file";
}

}  // namespace

void refuse_special_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw Error("'" + path + "' is " + kind_of(st.st_mode) + ", not a regular file");
}

bool is_regular_file(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string read_file_bytes(const std::string& path) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; fstat then refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    throw Error("cannot read '" + path + "': " + reason);
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    throw Error("'" + path + "' is " + kind_of(st.st_mode) + ", not a regular file");
  }
  std::string bytes(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t got = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const std::string reason = std::strerror(errno);
      ::close(fd);
      throw Error("cannot read '" + path + "': " + reason);
    }
    if (got == 0) break;  // the file shrank while being read
    done += static_cast<std::size_t>(got);
  }
  ::close(fd);
  bytes.resize(done);
  return bytes;
}

TemporaryFile create_temporary_beside(const std::string& target) {
  struct stat st {};
  const bool keep_mode = ::stat(target.c_str(), &st) == 0 && S_ISREG(st.st_mode);
  const std::string prefix = folder_of(target) + "/." + base_name(target) + ".tmp-volspline-";
  std::random_device entropy;
  for (int attempt = 0; attempt < 100; ++attempt) {
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "%08x", static_cast<unsigned>(entropy()));
    TemporaryFile tmp;
    tmp.path = prefix + suffix;
    tmp.fd = ::open(tmp.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (tmp.fd < 0 && errno == EEXIST) continue;
    if (tmp.fd < 0) throw Error("cannot write '" + target + "': " + std::strerror(errno));
    if (keep_mode && ::fchmod(tmp.fd, st.st_mode & 0777) != 0) {
      const std::string reason = std::strerror(errno);
      ::close(tmp.fd);
      ::unlink(tmp.path.c_str());
      throw Error("cannot write '" + target + "': " + reason);
    }
    return tmp;
  }
  throw Error("cannot write '" + target + "': no free temporary name beside it");
}

void write_and_close(int fd, const std::string& bytes, const std::string& name) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t put = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) {
      const std::string reason = put < 0 ? std::strerror(errno) : "nothing written";
      ::close(fd);
      throw Error("cannot write '" + name + "': " + reason);
    }
    done += static_cast<std::size_t>(put);
  }
  // A character device has nothing to flush (and /dev/null refuses fsync).
  struct stat st {};
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  if (regular && ::fsync(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    throw Error("cannot write '" + name + "': " + reason);
  }
  if (::close(fd) != 0) throw Error("cannot write '" + name + "': " + std::strerror(errno));
}

std::string write_target(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return path;
  char resolved[PATH_MAX];
  if (!::realpath(path.c_str(), resolved)) return path;  // dangling link: replaced by the file
  return resolved;
}

void write_file_atomic(const std::string& path, const std::string& bytes) {
  const std::string target = write_target(path);
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (!S_ISCHR(st.st_mode)) throw Error("cannot write '" + path + "': it is " + kind_of(st.st_mode));
    const int fd = ::open(target.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) throw Error("cannot write '" + path + "': " + std::strerror(errno));
    write_and_close(fd, bytes, path);
    return;
  }
  const TemporaryFile tmp = create_temporary_beside(target);
  try {
    write_and_close(tmp.fd, bytes, path);
  } catch (const Error&) {
    ::unlink(tmp.path.c_str());
    throw;
  }
  if (std::rename(tmp.path.c_str(), target.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.path.c_str());
    throw Error("cannot write '" + path + "': " + reason);
  }
}

std::string file_extension(const std::string& path) {
  const auto slash = path.find_last_of("/\\");
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace volspline::io
