// The background lane's promises (background_lane.h): jobs run one at a time in the order posted;
// nothing runs between pause() and resume(), and a running job stops at its next checkpoint; the
// first error reaches the poster; the destructor finishes the queued work.
#include "harness/evaluation/background_lane.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "harness/results/stage_times.h"

namespace aoeval {
namespace {

using namespace std::chrono_literals;

TEST(BackgroundLane, JobsRunInTheOrderPosted) {
  std::vector<int> order;  // only the lane's thread writes it
  {
    BackgroundLane lane(4);  // a small queue: post() waits for room
    for (int i = 0; i < 50; ++i) lane.post([&order, i] { order.push_back(i); });
    lane.drain();
    ASSERT_EQ(order.size(), 50u);
    for (int i = 0; i < 50; ++i) EXPECT_EQ(order[i], i);
  }
}

TEST(BackgroundLane, NothingRunsWhilePausedAndARunningJobStopsAtItsCheckpoint) {
  BackgroundLane lane;
  // The job steps until told to stop, so however late the pause comes (a loaded machine may hold
  // this thread back for longer than any fixed number of steps takes) it finds the job running.
  std::atomic<int> steps{0}, later{0};
  std::atomic<bool> started{false}, stop{false};
  lane.post([&] {
    started = true;
    while (!stop) {
      std::this_thread::sleep_for(2ms);
      ++steps;
      BackgroundLane::checkpoint();
    }
  });
  while (!started) std::this_thread::yield();
  lane.pause();  // returns once the job waits at a checkpoint
  const int at_pause = steps.load();
  lane.post([&] { ++later; });
  std::this_thread::sleep_for(60ms);  // 30 steps' time: none may happen
  EXPECT_EQ(steps.load(), at_pause);
  EXPECT_EQ(later.load(), 0) << "a job posted while paused ran";
  stop = true;
  lane.resume();
  lane.drain();
  // The job left its checkpoint, saw the stop and ended without another step; the later job ran.
  EXPECT_EQ(steps.load(), at_pause);
  EXPECT_EQ(later.load(), 1);
}

TEST(BackgroundLane, TheFirstErrorReachesThePosterAndDropsTheJobsBehindIt) {
  BackgroundLane lane;
  std::atomic<int> ran{0};
  lane.pause();
  lane.post([] { throw std::runtime_error("scoring failed"); });
  lane.post([&] { ++ran; });
  lane.resume();
  try {
    lane.drain();
    FAIL() << "drain() did not rethrow";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "scoring failed");
  }
  EXPECT_EQ(ran.load(), 0);
  lane.post([&] { ++ran; });  // the error was reported once; the lane works again
  lane.drain();
  EXPECT_EQ(ran.load(), 1);
}

TEST(BackgroundLane, TheDestructorFinishesQueuedWorkEvenWhenPaused) {
  std::atomic<int> ran{0};
  {
    BackgroundLane lane;
    lane.pause();
    for (int i = 0; i < 5; ++i) lane.post([&] { ++ran; });
  }
  EXPECT_EQ(ran.load(), 5);
}

TEST(BackgroundLane, StagesTimedOnTheLaneAreOverlappedAndLeaveTheWallTotal) {
  StageTimes stages;
  stages.add("estimator timed frames", 10.0);
  {
    BackgroundLane lane;
    lane.post([&] { stages.add("scoring", 4.0); });
    lane.drain();
  }
  EXPECT_EQ(stages.ms("scoring"), 0.0);
  EXPECT_EQ(stages.ms(std::string("scoring") + StageTimes::kOverlapped), 4.0);
  EXPECT_EQ(stages.total_ms(), 10.0);
  EXPECT_NE(stages.table(20.0).find("in the background"), std::string::npos);
}

}  // namespace
}  // namespace aoeval
