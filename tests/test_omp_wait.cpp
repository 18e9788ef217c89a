// The choice of the OpenMP spin from the machine's load (src/app/omp_wait.cpp), on given
// inputs: /proc/loadavg's text, the command line, the other processes' tasks.
#include "app/omp_wait.hpp"

#include <gtest/gtest.h>

#include <array>

using skred::machine_idle_for;
using skred::requested_threads;
using skred::running_tasks_of;

TEST(OmpWait, RunningTasksAreReadFromLoadavg) {
  EXPECT_EQ(running_tasks_of("0.10 0.80 1.40 2/345 6789\n"), 2);
  EXPECT_EQ(running_tasks_of("12.00 11.50 9.25 17/1024 99"), 17);
  EXPECT_EQ(running_tasks_of("0.00  0.01 0.05 1/78 15921"), 1);  // doubled space
  EXPECT_EQ(running_tasks_of(""), -1);
  EXPECT_EQ(running_tasks_of("0.10 0.80 1.40"), -1);
  EXPECT_EQ(running_tasks_of("0.10 0.80 1.40 /345 6789"), -1);
  EXPECT_EQ(running_tasks_of("0.10 0.80 1.40 x2/345 6789"), -1);
}

TEST(OmpWait, ThreadsComeFromTheCommandLineThenTheEnvironmentThenTheCpus) {
  std::array<char*, 6> bench{const_cast<char*>("skred"),
                             const_cast<char*>("bench"),
                             const_cast<char*>("--threads"),
                             const_cast<char*>("3"),
                             nullptr,
                             nullptr};
  EXPECT_EQ(requested_threads(bench.data(), "8", 2), 3);
  std::array<char*, 4> eq{const_cast<char*>("skred"), const_cast<char*>("run"),
                          const_cast<char*>("--threads=5"), nullptr};
  EXPECT_EQ(requested_threads(eq.data(), nullptr, 2), 5);
  std::array<char*, 3> none{const_cast<char*>("skred"), const_cast<char*>("run"), nullptr};
  EXPECT_EQ(requested_threads(none.data(), "4,2", 2), 4);  // nested lists: the outer level
  EXPECT_EQ(requested_threads(none.data(), "junk", 2), 2);
  EXPECT_EQ(requested_threads(none.data(), nullptr, 6), 6);
  std::array<char*, 4> dangling{const_cast<char*>("skred"), const_cast<char*>("run"),
                                const_cast<char*>("--threads"), nullptr};
  EXPECT_EQ(requested_threads(dangling.data(), nullptr, 2), 2);  // CLI11 reports the error later
}

TEST(OmpWait, TheLongSpinOnlyWhenTheThreadsFitBesideTheOtherTasks) {
  EXPECT_TRUE(machine_idle_for(0, 2, 2));
  EXPECT_FALSE(machine_idle_for(1, 2, 2));  // a process computing on one of two CPUs
  EXPECT_TRUE(machine_idle_for(1, 8, 4));   // room beside it
  EXPECT_TRUE(machine_idle_for(4, 8, 4));
  EXPECT_FALSE(machine_idle_for(5, 8, 4));
  EXPECT_FALSE(machine_idle_for(0, 2, 1));   // one thread never waits at a barrier
  EXPECT_FALSE(machine_idle_for(0, 2, 4));   // more threads than CPUs
  EXPECT_FALSE(machine_idle_for(-1, 2, 2));  // load unreadable
}
