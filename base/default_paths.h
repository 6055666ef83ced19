// The default paths of the command line (CONTRACT §4 "Results": every run appends to a SQLite
// database, default out/results.sqlite), written once: every runner's options start from these.
#pragma once

namespace aoeval {

// The results database every sweep, run, tune, bench, merge and dashboard uses without --db.
inline constexpr const char* kDefaultDatabase = "out/results.sqlite";

}  // namespace aoeval
