// commands.h — the subcommands of the treelearn program (apps/ is the only layer that prints and exits).
#pragma once

#include <string>

namespace apps {

/// `treelearn bench` options.
struct BenchOptions {
  double seconds = 20.0;  ///< simulated seconds per physics measurement
  int frames = 300;       ///< frames per rendering measurement
  std::string csv;        ///< optional CSV output path
};

/// Runs the benchmarks and prints a table; returns the exit code.
int runBench(const BenchOptions& options);

}  // namespace apps
