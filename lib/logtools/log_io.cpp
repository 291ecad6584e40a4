#include "logtools/log_io.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
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
  // A part of a split or rotated log (run.lcmlog.00, run.lcmlog.0): the run's stem.
  const auto dot = s.rfind('.');
  if (dot != std::string::npos && dot + 1 < s.size() &&
      s.find_first_not_of("0123456789", dot + 1) == std::string::npos &&
      ends_with(s.substr(0, dot), ".lcmlog"))
    s.resize(dot);
  if (ends_with(s, ".lcmlog")) s.resize(s.size() - 7);
  return s;
}

// lcm::LogFile reads anything as a log of zero events: say what the file is instead.
void check_lcm_log(const std::string& path, const std::string& shown) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error(shown + ": cannot open it (" + std::strerror(errno) + ")");
  unsigned char m[4] = {0, 0, 0, 0};
  const std::size_t n = std::fread(m, 1, 4, f);
  std::fclose(f);
  if (n == 0) throw std::runtime_error(shown + ": the file is empty (0 bytes), not an LCM log");
  if (n < 4 || m[0] != 0xED || m[1] != 0xA1 || m[2] != 0xDA || m[3] != 0x01)
    throw std::runtime_error(shown +
                             ": not an LCM log (it does not start with the LCM event magic "
                             "0xEDA1DA01)");
}

std::vector<Event> read_any_log(const std::string& path, const std::string& channel_regex) {
  if (!ends_with(path, ".gz")) {
    check_lcm_log(path, path);
    return read_log(path, channel_regex);
  }
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
    check_lcm_log(tmpl, path + " (decompressed)");
    auto events = read_log(tmpl, channel_regex);
    ::unlink(tmpl);
    return events;
  } catch (...) {
    ::unlink(tmpl);
    throw;
  }
}

}  // namespace tiller::logtools
