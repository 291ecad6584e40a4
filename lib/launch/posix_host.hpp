// The real ProcessHost of tiller-launch: fork/exec on POSIX. Each child runs in its own process
// group (signals reach its own children too, and a terminal's Ctrl-C reaches only the
// launcher), dies with the launcher (PR_SET_PDEATHSIG = SIGKILL), has stdin from /dev/null, and
// writes stdout and stderr into one pipe that the host prints line by line, each line
// prefixed with the process name. A grandchild is not covered by PR_SET_PDEATHSIG; so that
// nothing is left behind even when the launcher is SIGKILLed, start_guard() forks a small guard
// process that learns every child's process group and, when the launcher is gone (its pipe
// closes), SIGKILLs each group still alive. Only a process that leaves its group (setsid,
// setpgid: a daemon) escapes it. Commands without a '/' are looked up in `search_dirs`, then
// on PATH; ${NAME} in command, args and env values is replaced from `vars` or the environment.
#pragma once

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "launch/supervisor.hpp"

namespace tiller::launch {

class PosixHost : public ProcessHost {
 public:
  PosixHost(std::string root_dir, std::map<std::string, std::string> vars,
            std::vector<std::string> search_dirs, std::map<std::string, std::string> extra_env,
            std::FILE* out, std::size_t name_width);
  ~PosixHost() override;

  int spawn(const ProcessSpec& p, std::string& error) override;
  // Forks the guard (call before the first spawn, so it holds none of the children's pipes).
  // Returns its pid, or -1 (then only direct children are covered) with `error` set.
  int start_guard(std::string& error);
  void signal(int pid, int sig) override;
  bool file_has_data(const std::string& path, TimeUs since) override;

  // Resolves a command to an executable path ("" if none is found).
  std::string resolve(const std::string& command) const;
  // Substitutes vars in a process's command and args (throws std::invalid_argument).
  std::vector<std::string> argv_of(const ProcessSpec& p) const;

  // Output pipes still open, and what to do when one is readable.
  std::vector<int> output_fds() const;
  void on_readable(int fd);
  // Prints a line from the launcher itself, prefixed like the processes' lines.
  void print(const std::string& who, const std::string& line);

 private:
  struct Pipe {
    std::string name;
    std::string partial;
  };
  std::string root_;
  std::map<std::string, std::string> vars_;
  std::vector<std::string> search_dirs_;
  std::map<std::string, std::string> extra_env_;
  std::FILE* out_;
  std::size_t width_;
  std::map<int, Pipe> pipes_;
  int guard_fd_ = -1;  // write end of the guard's pipe
};

// A private scratch directory for one run, ${RUN_DIR} in a launch file: mode 0700, made under
// $TMPDIR (else /tmp) as tiller-<launch name>-XXXXXX, removed with everything in it when this
// object goes (the end of the run). For what processes of one run share that is not LCM: a
// pseudo-terminal's link, a daemon's control socket (config/launch/sim_usv_sensors.yaml).
class RunDir {
 public:
  explicit RunDir(const std::string& launch_name);  // throws std::runtime_error
  ~RunDir();
  RunDir(const RunDir&) = delete;
  RunDir& operator=(const RunDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Directory of the running executable (for finding sibling tiller-* programs).
std::string self_dir();

}  // namespace tiller::launch
