#pragma once
// Running another program as a child process in its own process group, with
// a wall-clock limit. POSIX (Linux) only.
#include <filesystem>
#include <string>
#include <vector>

namespace ism::tool {

struct ChildOptions {
  std::filesystem::path working_dir;  // empty: the caller's
  std::filesystem::path stdout_file;  // empty: inherited
  std::filesystem::path stderr_file;  // empty: inherited
  double timeout_seconds = 0;         // <= 0: no limit
  double grace_seconds = 2;           // between SIGTERM and SIGKILL
};

struct ChildResult {
  int exit_code = -1;   // the child's exit status; -1 when it did not exit
  int term_signal = 0;  // the signal that ended the child, 0 if it exited
  bool timed_out = false;
  int interrupted_by = 0;  // SIGTERM, SIGINT or SIGHUP sent to this process
  double seconds = 0;      // wall time
};

/// Runs argv[0] (a path, not looked up on PATH) with arguments argv[1..] in a
/// new process group, its standard input from /dev/null and its outputs in the
/// given files (created or truncated). Returns when the child has ended:
/// - normally: exit_code (127 when argv[0] could not be executed; the reason
///   is then the last line of stderr_file);
/// - after `timeout_seconds`: the whole group gets SIGTERM, then SIGKILL
///   after `grace_seconds`; timed_out is set;
/// - when this process receives SIGTERM, SIGINT or SIGHUP meanwhile: the group
///   is ended the same way and interrupted_by names the signal; the caller
///   should clean up and exit.
/// Those three signals and SIGCHLD are blocked during the call and restored
/// after it. Throws std::runtime_error when no process can be started or an
/// output file cannot be opened. Not thread-safe (signal mask of the process).
ChildResult run_child(const std::vector<std::string>& argv, const ChildOptions& options);

/// A signal's name ("SIGKILL"), or "signal N".
std::string signal_name(int signal);

}  // namespace ism::tool
