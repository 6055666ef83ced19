#include "harness/evaluation/background_lane.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "harness/results/stage_times.h"

namespace aoeval {

namespace {
thread_local BackgroundLane* t_lane = nullptr;  // the lane whose thread this is
}  // namespace

BackgroundLane::BackgroundLane(size_t max_queued)
    : max_queued_(std::max<size_t>(1, max_queued)), thread_([this] { work(); }) {}

BackgroundLane::~BackgroundLane() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    paused_ = false;
    wake_.notify_one();
    changed_.wait(lock, [&] { return jobs_.empty() && !busy_; });
    stopping_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void BackgroundLane::rethrow_locked(std::unique_lock<std::mutex>& lock) {
  if (!error_) return;
  std::exception_ptr error = std::exchange(error_, nullptr);
  lock.unlock();
  std::rethrow_exception(error);
}

void BackgroundLane::post(std::function<void()> job) {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (paused_ && jobs_.size() >= max_queued_)
      throw std::logic_error("BackgroundLane::post: the queue is full and the lane is paused");
    changed_.wait(lock, [&] { return error_ || jobs_.size() < max_queued_; });
    rethrow_locked(lock);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void BackgroundLane::drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  paused_ = false;
  wake_.notify_one();
  changed_.wait(lock, [&] { return jobs_.empty() && !busy_; });
  rethrow_locked(lock);
}

void BackgroundLane::pause() {
  std::unique_lock<std::mutex> lock(mutex_);
  paused_ = true;
  changed_.wait(lock, [&] { return !busy_; });
}

void BackgroundLane::resume() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    paused_ = false;
  }
  wake_.notify_one();
}

void BackgroundLane::checkpoint() {
  if (!t_lane) return;
  std::unique_lock<std::mutex> lock(t_lane->mutex_);
  t_lane->wait_while_paused(lock);
}

bool BackgroundLane::on_lane_thread() {
  return t_lane != nullptr;
}

void BackgroundLane::wait_while_paused(std::unique_lock<std::mutex>& lock) {
  if (!paused_) return;
  busy_ = false;
  changed_.notify_all();
  wake_.wait(lock, [&] { return !paused_; });
  busy_ = true;
}

void BackgroundLane::work() {
  t_lane = this;
  StageTimes::mark_this_thread_overlapped();
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stopping_ || (!paused_ && !jobs_.empty()); });
    if (stopping_ && jobs_.empty()) return;
    if (paused_ || jobs_.empty()) continue;
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    busy_ = true;
    lock.unlock();
    std::exception_ptr error;
    try {
      job();
    } catch (...) {
      error = std::current_exception();
    }
    job = nullptr;  // what the job holds (a frame's estimate) is freed before the next starts
    lock.lock();
    busy_ = false;
    if (error) {
      if (!error_) error_ = error;
      jobs_.clear();  // the run ends at the first failed point
    }
    changed_.notify_all();
  }
}

}  // namespace aoeval
