#pragma once
// Progress of long work on stderr: stage, percent, elapsed time. Silent for
// the first second of a stage so quick runs stay quiet, and throttled so it
// costs nothing in tight loops.
#include <chrono>
#include <string>

namespace ism::tool {

class Progress {
 public:
  explicit Progress(std::string tool_name = "", bool quiet = true);

  void start(const std::string& stage);
  /// fraction in [0, 1]; cheap to call often.
  void update(double fraction);
  /// Ends the current progress line, if one was shown.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string tool_, stage_;
  bool quiet_;
  bool shown_ = false;
  bool tty_ = false;
  Clock::time_point stage_start_, last_print_;
};

}  // namespace ism::tool
