// SPDX-License-Identifier: MIT
#include "cli/output_files.h"

#include <dirent.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <doctest/doctest.h>

using namespace volspline;

namespace {

// A fresh empty folder under /tmp, removed with its files at the end of the test.
struct Folder {
  std::string path;
  Folder() {
    char name[] = "/tmp/output_files_test.XXXXXX";
    REQUIRE(::mkdtemp(name) != nullptr);
    path = name;
  }
  ~Folder() {
    for (const std::string& f : files()) ::unlink((path + "/" + f).c_str());
    ::rmdir(path.c_str());
  }
  std::set<std::string> files() const {
    std::set<std::string> names;
    if (DIR* dir = ::opendir(path.c_str())) {
      while (const dirent* e = ::readdir(dir))
        if (std::string(e->d_name) != "." && std::string(e->d_name) != "..") names.insert(e->d_name);
      ::closedir(dir);
    }
    return names;
  }
};

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST_CASE("OutputFiles: staged outputs appear only at commit, all together") {
  Folder folder;
  const std::string a = folder.path + "/a.json", b = folder.path + "/b.vtu";
  write_text(a, "old a");
  {
    cli::OutputFiles files;
    files.output("-o", a);
    files.output("--vtk", b);
    files.stage(a, "new a");
    files.stage(b, "new b");
    CHECK(text_of(a) == "old a");  // staged beside the target, not over it
    CHECK(folder.files().size() == 3);  // a.json and the two temporaries
    files.commit();
  }
  CHECK(text_of(a) == "new a");
  CHECK(text_of(b) == "new b");
  CHECK(folder.files() == std::set<std::string>{"a.json", "b.vtu"});
}

TEST_CASE("OutputFiles: an error before commit removes the temporaries and keeps the old outputs") {
  Folder folder;
  const std::string a = folder.path + "/a.json";
  write_text(a, "old a");
  try {
    cli::OutputFiles files;
    files.output("-o", a);
    files.stage(a, "new a");
    throw std::runtime_error("the job failed after staging");
  } catch (const std::runtime_error&) {
  }
  CHECK(text_of(a) == "old a");
  CHECK(folder.files() == std::set<std::string>{"a.json"});
}

TEST_CASE("OutputFiles: SIGTERM or SIGINT between staging and commit removes the temporaries") {
  for (const int signal : {SIGTERM, SIGINT, SIGHUP}) {
    CAPTURE(signal);
    Folder folder;
    const std::string a = folder.path + "/a.json", b = folder.path + "/b.vtu";
    write_text(a, "old a");
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      cli::OutputFiles files;
      files.output("-o", a);
      files.output("--vtk", b);
      files.stage(a, "new a");
      files.stage(b, "new b");
      std::raise(signal);
      std::_Exit(0);  // not reached: the handler removes the temporaries and dies of the signal
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal);
    CHECK(text_of(a) == "old a");
    CHECK(folder.files() == std::set<std::string>{"a.json"});
  }
}
