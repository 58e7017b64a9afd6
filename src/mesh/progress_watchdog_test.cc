#include "src/mesh/progress_watchdog.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

TEST(ProgressWatchdog, ReportsWhileTheStepRunsAndStopsAtTheEnd) {
  int num_reports = 0;
  {
    ProgressWatchdog watchdog("test step", std::chrono::milliseconds(20));
    watchdog.SetTotal(10, "items");
    watchdog.AddDone(3);
    std::this_thread::sleep_for(std::chrono::milliseconds(110));
    num_reports = watchdog.NumReports();
    EXPECT_GE(num_reports, 3);
    EXPECT_LE(num_reports, 6);
  }
  // A short step logs nothing.
  ProgressWatchdog quick("quick step", std::chrono::seconds(60));
  EXPECT_EQ(quick.NumReports(), 0);
}

TEST(ProgressWatchdog, RejectsZeroPeriod) {
  EXPECT_THROW(ProgressWatchdog("bad", std::chrono::milliseconds(0)), Error);
}

}  // namespace
}  // namespace colmap_lidar
