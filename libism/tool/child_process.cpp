#include "tool/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace ism::tool {

namespace {

using Clock = std::chrono::steady_clock;

int open_output(const std::filesystem::path& path) {
  if (path.empty()) return -1;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error(path.string() + ": cannot write (" + std::strerror(errno) + ")");
  return fd;
}

void write_all(int fd, const std::string& text) {
  const char* p = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n <= 0) return;
    p += n;
    left -= std::size_t(n);
  }
}

// In the forked child: only async-signal-safe calls until exec.
[[noreturn]] void exec_child(const std::vector<char*>& args, const ChildOptions& options, int in_fd,
                             int out_fd, int err_fd, const std::string& exec_error) {
  ::setpgid(0, 0);
  for (int s : {SIGTERM, SIGINT, SIGHUP, SIGCHLD, SIGPIPE}) ::signal(s, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  ::dup2(in_fd, STDIN_FILENO);
  if (out_fd >= 0) ::dup2(out_fd, STDOUT_FILENO);
  if (err_fd >= 0) ::dup2(err_fd, STDERR_FILENO);
  if (!options.working_dir.empty() && ::chdir(options.working_dir.c_str()) != 0) {
    write_all(STDERR_FILENO, options.working_dir.string() + ": cannot enter the folder\n");
    ::_exit(127);
  }
  ::execv(args[0], args.data());
  write_all(STDERR_FILENO, exec_error);
  ::_exit(127);
}

}  // namespace

std::string signal_name(int signal) {
  switch (signal) {
    case SIGTERM:
      return "SIGTERM";
    case SIGKILL:
      return "SIGKILL";
    case SIGINT:
      return "SIGINT";
    case SIGHUP:
      return "SIGHUP";
    case SIGSEGV:
      return "SIGSEGV";
    case SIGABRT:
      return "SIGABRT";
    case SIGBUS:
      return "SIGBUS";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGPIPE:
      return "SIGPIPE";
    case SIGXCPU:
      return "SIGXCPU";
    default:
      return "signal " + std::to_string(signal);
  }
}

ChildResult run_child(const std::vector<std::string>& argv, const ChildOptions& options) {
  if (argv.empty()) throw std::invalid_argument("run_child: empty command");
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // Prepared before fork: the child only calls async-signal-safe functions.
  const std::string exec_error = argv[0] + ": cannot run the program\n";

  sigset_t watched, previous;
  sigemptyset(&watched);
  for (int s : {SIGCHLD, SIGTERM, SIGINT, SIGHUP}) sigaddset(&watched, s);
  // A SIGCHLD set to SIG_IGN would reap the child before we could.
  struct sigaction default_chld {
  }, previous_chld{};
  default_chld.sa_handler = SIG_DFL;
  ::sigaction(SIGCHLD, &default_chld, &previous_chld);
  ::sigprocmask(SIG_BLOCK, &watched, &previous);
  struct Restore {
    sigset_t mask;
    struct sigaction chld;
    ~Restore() {
      ::sigaction(SIGCHLD, &chld, nullptr);
      ::sigprocmask(SIG_SETMASK, &mask, nullptr);
    }
  } restore{previous, previous_chld};

  struct Fds {
    int in = -1, out = -1, err = -1;
    ~Fds() {
      for (int fd : {in, out, err})
        if (fd >= 0) ::close(fd);
    }
  } fds;
  fds.in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  fds.out = open_output(options.stdout_file);
  fds.err = open_output(options.stderr_file);

  const auto start = Clock::now();
  const pid_t pid = ::fork();
  if (pid < 0)
    throw std::runtime_error(std::string("cannot start a process: ") + std::strerror(errno));
  if (pid == 0) exec_child(args, options, fds.in, fds.out, fds.err, exec_error);
  ::setpgid(pid, pid);  // also here, so that the group exists before any kill

  ChildResult result;
  const bool limited = options.timeout_seconds > 0;
  auto deadline = start + std::chrono::duration_cast<Clock::duration>(
                              std::chrono::duration<double>(limited ? options.timeout_seconds : 0));
  bool ending = false;  // SIGTERM sent to the group; SIGKILL at the deadline
  int status = 0;
  for (;;) {
    // The child is left a zombie (WNOWAIT), so its process group id stays
    // reserved until the group has been killed below.
    siginfo_t info{};
    if (::waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid)
      break;
    const auto now = Clock::now();
    if ((limited || ending) && now >= deadline) {
      if (ending) break;
      result.timed_out = true;
      ::kill(-pid, SIGTERM);
      ending = true;
      deadline = now + std::chrono::duration_cast<Clock::duration>(
                           std::chrono::duration<double>(options.grace_seconds));
      continue;
    }
    // Wake on any watched signal, and at least every half second.
    double wait = 0.5;
    if (limited || ending)
      wait = std::min(wait, std::chrono::duration<double>(deadline - now).count());
    timespec ts{};
    ts.tv_sec = time_t(wait);
    ts.tv_nsec = long((wait - double(ts.tv_sec)) * 1e9);
    const int s = ::sigtimedwait(&watched, nullptr, &ts);
    if ((s == SIGTERM || s == SIGINT || s == SIGHUP) && !ending) {
      result.interrupted_by = s;
      ::kill(-pid, SIGTERM);
      ending = true;
      deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(options.grace_seconds));
    }
  }
  ::kill(-pid, SIGKILL);  // the group: a child past its grace, or what it left running
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) result.term_signal = WTERMSIG(status);
  return result;
}

}  // namespace ism::tool
