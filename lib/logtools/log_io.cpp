#include "logtools/log_io.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include "runtime/log.hpp"

namespace tiller::logtools {

namespace {
bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

std::string log_stem(const std::string& path) {
  std::string s = path;
  if (ends_with(s, ".gz")) s.resize(s.size() - 3);
  if (ends_with(s, ".lcmlog")) s.resize(s.size() - 7);
  return s;
}

std::vector<Event> read_any_log(const std::string& path, const std::string& channel_regex) {
  if (!ends_with(path, ".gz")) return read_log(path, channel_regex);
  if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": no such file");
  char tmpl[] = "/tmp/tiller-log-XXXXXX";
  const int fd = ::mkstemp(tmpl);
  if (fd < 0) throw std::runtime_error("cannot create a temporary file to decompress " + path);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fd, 1);
    ::execlp("gzip", "gzip", "-dc", path.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(fd);
  int st = 0;
  ::waitpid(pid, &st, 0);
  if (pid < 0 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) {
    ::unlink(tmpl);
    throw std::runtime_error(path + ": gzip could not decompress it");
  }
  try {
    auto events = read_log(tmpl, channel_regex);
    ::unlink(tmpl);
    return events;
  } catch (...) {
    ::unlink(tmpl);
    throw;
  }
}

}  // namespace tiller::logtools
