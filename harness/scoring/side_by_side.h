// Independent pieces of one scoring run side by side: the first on the calling thread, each other
// on a thread of its own, returning when all are done (rethrowing a piece's error). Not TBB's
// parallel_invoke: on the runners' background lane, TBB's one worker of this 2-core machine did
// not join the lane's tasks (perf of a cold sequence run: every filter pass on the lane's thread,
// the worker idle while the runner waited for the lane), so a scoring used one core (issue 42).
// Each piece computes what it computes alone: the same bits in any schedule.
#pragma once

#include <future>
#include <utility>

namespace aoeval::detail {

template <class First, class... Rest>
void side_by_side(First&& first, Rest&&... rest) {
  std::future<void> others[] = {std::async(std::launch::async, std::forward<Rest>(rest))...};
  first();
  for (std::future<void>& other : others) other.get();
}

}  // namespace aoeval::detail
