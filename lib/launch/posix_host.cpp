#include "launch/posix_host.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

extern char** environ;

namespace tiller::launch {

std::string self_dir() {
  std::error_code ec;
  auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : p.parent_path().string();
}

PosixHost::PosixHost(std::string root_dir, std::map<std::string, std::string> vars,
                     std::vector<std::string> search_dirs,
                     std::map<std::string, std::string> extra_env, std::FILE* out,
                     std::size_t name_width)
    : root_(std::move(root_dir)),
      vars_(std::move(vars)),
      search_dirs_(std::move(search_dirs)),
      extra_env_(std::move(extra_env)),
      out_(out),
      width_(name_width) {}

PosixHost::~PosixHost() {
  for (auto& [fd, p] : pipes_) ::close(fd);
  if (guard_fd_ >= 0) ::close(guard_fd_);
}

int PosixHost::start_guard(std::string& error) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    error = std::string("pipe: ") + std::strerror(errno);
    return -1;
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    error = std::string("fork: ") + std::strerror(errno);
    ::close(fds[0]);
    ::close(fds[1]);
    return -1;
  }
  if (pid == 0) {
    // The guard: its own process group (a Ctrl-C or a group kill aimed at the launcher does not
    // reach it), deaf to the stop signals; it ends when the launcher's end of the pipe closes.
    ::setpgid(0, 0);
    ::close(fds[1]);
    for (int s : {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGPIPE}) ::signal(s, SIG_IGN);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int devnull = ::open("/dev/null", O_RDWR);
    if (devnull >= 0) {
      ::dup2(devnull, 0);
      ::dup2(devnull, 1);
    }
    for (int fd = 3; fd < 1024; ++fd)
      if (fd != fds[0]) ::close(fd);
    std::vector<int> groups;
    std::int32_t g = 0;
    for (;;) {
      const ssize_t n = ::read(fds[0], &g, sizeof g);
      if (n == static_cast<ssize_t>(sizeof g)) {
        if (g > 0) groups.push_back(g);
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      break;  // EOF: the launcher exited or was killed
    }
    int left = 0;
    for (int grp : groups) left += ::kill(-grp, SIGKILL) == 0 ? 1 : 0;
    if (left > 0) {
      char msg[160];
      const int len = std::snprintf(msg, sizeof msg,
                                    "tiller-launch guard: the launcher is gone; SIGKILL to %d "
                                    "process group%s still alive\n",
                                    left, left > 1 ? "s" : "");
      (void)!::write(2, msg, static_cast<std::size_t>(len));
    }
    ::_exit(0);
  }
  ::close(fds[0]);
  guard_fd_ = fds[1];
  return pid;
}

namespace {
bool executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}
}  // namespace

std::string PosixHost::resolve(const std::string& command) const {
  if (command.find('/') != std::string::npos) {
    const std::string p = command[0] == '/' ? command : root_ + "/" + command;
    return executable(p) ? p : "";
  }
  std::vector<std::string> dirs = search_dirs_;
  if (const char* path = std::getenv("PATH")) {
    std::string s = path;
    std::size_t b = 0;
    while (b <= s.size()) {
      auto e = s.find(':', b);
      if (e == std::string::npos) e = s.size();
      if (e > b) dirs.push_back(s.substr(b, e - b));
      b = e + 1;
    }
  }
  for (const auto& d : dirs) {
    const std::string p = d + "/" + command;
    if (executable(p)) return p;
  }
  return "";
}

std::vector<std::string> PosixHost::argv_of(const ProcessSpec& p) const {
  std::vector<std::string> a{substitute(p.command, vars_)};
  for (const auto& s : p.args) a.push_back(substitute(s, vars_));
  return a;
}

int PosixHost::spawn(const ProcessSpec& p, std::string& error) {
  std::vector<std::string> args;
  std::map<std::string, std::string> env;
  try {
    args = argv_of(p);
    for (char** e = environ; *e; ++e) {
      const std::string kv = *e;
      const auto eq = kv.find('=');
      if (eq != std::string::npos) env[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
    for (const auto& [k, v] : extra_env_) env[k] = v;
    for (const auto& [k, v] : p.env) env[k] = substitute(v, vars_);
  } catch (const std::exception& e) {
    error = e.what();
    return -1;
  }
  const std::string exe = resolve(args[0]);
  if (exe.empty()) {
    error = "no program \"" + args[0] + "\" (looked next to tiller-launch and on PATH)";
    return -1;
  }
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_strings;
  for (const auto& [k, v] : env) env_strings.push_back(k + "=" + v);
  std::vector<char*> envp;
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);

  int out[2], err[2];
  if (::pipe2(out, O_CLOEXEC) != 0) {
    error = std::string("pipe: ") + std::strerror(errno);
    return -1;
  }
  if (::pipe2(err, O_CLOEXEC) != 0) {
    ::close(out[0]);
    ::close(out[1]);
    error = std::string("pipe: ") + std::strerror(errno);
    return -1;
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    error = std::string("fork: ") + std::strerror(errno);
    for (int fd : {out[0], out[1], err[0], err[1]}) ::close(fd);
    return -1;
  }
  if (pid == 0) {
    // Child: only async-signal-safe calls from here to exec.
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the launcher died before prctl
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    for (int s : {SIGINT, SIGTERM, SIGCHLD, SIGPIPE, SIGHUP, SIGUSR1}) ::signal(s, SIG_DFL);
    const int devnull = ::open("/dev/null", O_RDONLY);
    if (devnull >= 0) ::dup2(devnull, 0);
    ::dup2(out[1], 1);
    ::dup2(out[1], 2);
    if (::chdir(root_.c_str()) != 0) {
      const int e = errno;
      (void)!::write(err[1], &e, sizeof e);
      ::_exit(127);
    }
    ::execve(exe.c_str(), argv.data(), envp.data());
    const int e = errno;
    (void)!::write(err[1], &e, sizeof e);
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here, so signals sent right away reach the group
  if (guard_fd_ >= 0) {
    const std::int32_t g = pid;
    (void)!::write(guard_fd_, &g, sizeof g);
  }
  ::close(out[1]);
  ::close(err[1]);
  int child_errno = 0;
  ssize_t n;
  do {
    n = ::read(err[0], &child_errno, sizeof child_errno);
  } while (n < 0 && errno == EINTR);
  ::close(err[0]);
  if (n == static_cast<ssize_t>(sizeof child_errno)) {
    ::waitpid(pid, nullptr, 0);
    ::close(out[0]);
    error = "cannot run " + exe + ": " + std::strerror(child_errno);
    return -1;
  }
  ::fcntl(out[0], F_SETFL, ::fcntl(out[0], F_GETFL) | O_NONBLOCK);
  pipes_[out[0]] = Pipe{p.name, {}};
  return pid;
}

bool PosixHost::file_has_data(const std::string& path, TimeUs since) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || st.st_size == 0) return false;
  const TimeUs mtime = static_cast<TimeUs>(st.st_mtim.tv_sec) * kUsPerSecond +
                       static_cast<TimeUs>(st.st_mtim.tv_nsec / 1000);
  return mtime >= since;
}

void PosixHost::signal(int pid, int sig) {
  if (pid <= 0) return;
  if (::kill(-pid, sig) != 0) ::kill(pid, sig);
}

std::vector<int> PosixHost::output_fds() const {
  std::vector<int> v;
  for (const auto& [fd, p] : pipes_) v.push_back(fd);
  return v;
}

void PosixHost::print(const std::string& who, const std::string& line) {
  std::string name = who;
  if (name.size() < width_) name.resize(width_, ' ');
  std::fprintf(out_, "%s | %s\n", name.c_str(), line.c_str());
  std::fflush(out_);
}

void PosixHost::on_readable(int fd) {
  auto it = pipes_.find(fd);
  if (it == pipes_.end()) return;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n > 0) {
      it->second.partial.append(buf, static_cast<std::size_t>(n));
      std::size_t nl;
      while ((nl = it->second.partial.find('\n')) != std::string::npos) {
        print(it->second.name, it->second.partial.substr(0, nl));
        it->second.partial.erase(0, nl + 1);
      }
      if (it->second.partial.size() > 65536) {  // a very long line without newline
        print(it->second.name, it->second.partial);
        it->second.partial.clear();
      }
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    // EOF or error: the process (and everything that shared the pipe) is gone.
    if (!it->second.partial.empty()) print(it->second.name, it->second.partial);
    ::close(fd);
    pipes_.erase(it);
    return;
  }
}

RunDir::RunDir(const std::string& launch_name) {
  const char* t = std::getenv("TMPDIR");
  std::string name = launch_name;
  for (char& c : name)
    if (c == '/' || c == ' ') c = '_';
  std::string tmpl = std::string(t && *t ? t : "/tmp") + "/tiller-" + name + "-XXXXXX";
  if (::mkdtemp(tmpl.data()) == nullptr)
    throw std::runtime_error("cannot make the run directory " + tmpl + ": " + std::strerror(errno));
  path_ = tmpl;
}

RunDir::~RunDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

}  // namespace tiller::launch
