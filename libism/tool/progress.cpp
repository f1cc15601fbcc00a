#include "tool/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace ism::tool {

Progress::Progress(std::string tool_name, bool quiet)
    : tool_(std::move(tool_name)), quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0) {}

void Progress::start(const std::string& stage) {
  finish();
  stage_ = stage;
  stage_start_ = last_print_ = Clock::now();
}

void Progress::update(double fraction) {
  if (quiet_) return;
  const auto now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  // Quiet for the first second; then at most twice a second on a terminal,
  // every five seconds in a log.
  const double interval = tty_ ? 0.5 : 5.0;
  if (elapsed < 1.0 || std::chrono::duration<double>(now - last_print_).count() < interval) return;
  last_print_ = now;
  const int percent = int(100.0 * std::clamp(fraction, 0.0, 1.0));
  std::fprintf(stderr, "%s%s: %s %3d%% (%.1f s)%s", tty_ ? "\r" : "", tool_.c_str(), stage_.c_str(),
               percent, elapsed, tty_ ? "\033[K" : "\n");
  std::fflush(stderr);
  shown_ = true;
}

void Progress::finish() {
  if (shown_ && tty_) std::fputc('\n', stderr);
  shown_ = false;
}

}  // namespace ism::tool
