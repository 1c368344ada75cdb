#pragma once
// The tool's progress line on stderr, for long work: what it is doing (loading, with the
// file's size; building the BVH, with Embree's fraction done) and, while frames render, frames done, a bar, and the time left — or the
// estimated error against --error-target. Drawn only on a terminal and without --quiet;
// a thread of its own redraws it in place every fifth of a second from the frame's tile
// count, so a single long frame shows its progress too.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "sciray/frame/render_frame.hpp"

namespace sciray_tool {

class ProgressLine {
public:
  /// Shows nothing unless `wanted` and stderr is a terminal (or `force`, for tests).
  explicit ProgressLine(bool wanted, bool force = false) : shown_(wanted && (force || isatty(fileno(stderr)))) {
    if (shown_) painter_ = std::thread([this] { paint_until_done(); });
  }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  ~ProgressLine() {
    if (!shown_) return;
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    painter_.join();
    std::fprintf(stderr, "\r\033[K");  // leave the terminal as it was
    std::fflush(stderr);
  }

  /// What the tool does now ("loading can.vtu", "building the BVH"), and how far it is
  /// in [0, 1] if it can tell (`fraction`, called from the painting thread).
  void stage(std::string what, std::function<double()> fraction = {}) {
    std::lock_guard lock(mutex_);
    stage_ = std::move(what);
    stage_fraction_ = std::move(fraction);
    stage_start_ = Clock::now();
  }
  /// Frames begin: up to `total` of them, or until the error estimate meets `error_target` (> 0).
  void start_frames(int total, float error_target) {
    std::lock_guard lock(mutex_);
    stage_.clear(), stage_fraction_ = {};
    total_frames_ = total, error_target_ = error_target, frames_done_ = 0;
    frames_start_ = Clock::now();
  }
  /// A frame finished, and the frame buffer's error estimate after it (NaN if none).
  void frame_done(float error) {
    std::lock_guard lock(mutex_);
    ++frames_done_;
    error_ = error;
    control_.tiles_done = 0;
  }
  /// What frames report their tiles to (and can be cancelled through).
  sciray::FrameControl* control() { return shown_ ? &control_ : nullptr; }

private:
  using Clock = std::chrono::steady_clock;

  void paint_until_done() {
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(200), [this] { return done_; })) {
      const std::string line = describe();
      if (line.empty()) continue;
      std::fprintf(stderr, "\r\033[K%s", line.c_str());
      std::fflush(stderr);
    }
  }

  static std::string seconds(double s) {
    char text[32];
    if (s < 60)
      std::snprintf(text, sizeof text, "%.1f s", s);
    else
      std::snprintf(text, sizeof text, "%d min %02d s", static_cast<int>(s / 60), static_cast<int>(s) % 60);
    return text;
  }

  /// The line as things stand (under the lock).
  std::string describe() const {
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    if (!stage_.empty()) {
      std::string line = stage_ + "… ";
      if (stage_fraction_) {
        char percent[16];
        std::snprintf(percent, sizeof percent, "%3.0f%% · ", 100. * std::clamp(stage_fraction_(), 0., 1.));
        line += percent;
      }
      return line + seconds(since(stage_start_));
    }
    if (total_frames_ == 0) return {};
    const double within = control_.progress();
    const double done = std::min<double>(frames_done_ + within, total_frames_);
    const double elapsed = since(frames_start_);
    std::string line = "frame " + std::to_string(std::min(frames_done_ + 1, total_frames_)) + '/' +
                       std::to_string(total_frames_) + ' ';
    constexpr int width = 24;
    const int filled = static_cast<int>(width * done / total_frames_);
    line += '[' + std::string(static_cast<std::size_t>(filled), '#') +
            std::string(static_cast<std::size_t>(width - filled), '.') + "] ";
    char percent[16];
    std::snprintf(percent, sizeof percent, "%3.0f%%", 100. * done / total_frames_);
    line += percent;
    if (error_target_ > 0.f) {
      char error[64];
      if (std::isfinite(error_))
        std::snprintf(error, sizeof error, " · error %.4g → %.4g", error_, error_target_);
      else
        std::snprintf(error, sizeof error, " · error target %.4g", error_target_);
      line += error;
    } else if (done > 0.) {
      line += " · " + seconds(elapsed * (total_frames_ - done) / done) + " left";
    }
    return line;
  }

  bool shown_;
  std::thread painter_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::string stage_;
  std::function<double()> stage_fraction_;
  Clock::time_point stage_start_, frames_start_;
  int total_frames_ = 0, frames_done_ = 0;
  float error_target_ = 0.f, error_ = std::numeric_limits<float>::quiet_NaN();
  sciray::FrameControl control_;
};

}  // namespace sciray_tool
