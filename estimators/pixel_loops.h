// Small loops the CPU estimators share: every pixel with rows in parallel (TBB), and a stopwatch
// in milliseconds for their per-pass times.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>

namespace aoeval {

// Runs body(i, j) over every pixel of a width x height image, rows in parallel (one task per
// row: rows cost alike, and a row is long enough to amortise the task).
template <class Body>
void for_each_pixel(int width, int height, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 1),
                    [&](const tbb::blocked_range<int>& rows) {
                      for (int j = rows.begin(); j < rows.end(); ++j)
                        for (int i = 0; i < width; ++i) body(i, j);
                    });
}

// Milliseconds since `start` on the steady clock.
inline double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace aoeval
