#pragma once
// bench_vessel's command runner: commands run as their own processes from a small process forked
// before the benchmarks allocate anything, with their wall time, CPU time and peak memory.
#include <string>
#include <vector>

#include <sys/types.h>

namespace cathbox::bench {

// One command's run: its figures and the first line it printed.
struct Run {
  double wall_s = 0.0;
  double cpu_s = 0.0;
  double peak_bytes = 0.0;
  std::string out;
  bool ok = false;
};

// Commands run from a small process forked before the benchmarks allocate anything: a child's
// peak memory (ru_maxrss) counts what it inherited at fork, so forking the benchmark process
// itself would add its own hundred megabytes to every figure. Requests and answers go through
// two pipes: argv joined by '\n' and terminated by "\n\n"; back a fixed Result.
class Spawner {
 public:
  struct Result {
    double wall_s, cpu_s, peak_bytes;
    int ok;
  };
  // Forks the serving process (call first thing in main).
  void start();
  // Runs argv[0] with its output into stdout_path; waits for it.
  Run run(const std::vector<std::string>& argv, const std::string& stdout_path);

 private:
  static void serve(int in, int out);

  pid_t pid_ = -1;
  int request_ = -1;
  int answer_ = -1;
};

// The program's one spawner.
Spawner& spawner();

}  // namespace cathbox::bench
