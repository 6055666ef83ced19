// The small summaries that rows, benches, figures and the dashboard compute alike: one definition
// each, so a median in a table and a median in a row are the same number.
#pragma once

#include <string>
#include <vector>

namespace aoeval {

// The median of `values` (the mean of the two middle values for an even count); NaN when empty.
double median(std::vector<double> values);

// The interquartile range of `values` (quartiles by linear interpolation between order statistics,
// Hyndman & Fan type 7); 0 for fewer than two values. The robust spread of timed repetitions: one
// slow repetition among five moves it little, where it sets max - min alone.
double interquartile_range(std::vector<double> values);

// The current time in UTC through strftime's `format` (thread-safe: gmtime_r). The default is ISO
// 8601, "2024-05-01T12:34:56Z", the format of RunContext::started and ResultRow::timestamp.
std::string utc_now(const char* format = "%Y-%m-%dT%H:%M:%SZ");

}  // namespace aoeval
