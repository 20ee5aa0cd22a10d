// The progress line's time remaining, with the wall time injected (no clock, no sleep).
#include "dmbd/base/progress.hpp"

#include <gtest/gtest.h>

namespace {

TEST(Progress, RemainingIsElapsedTimesTheRestOverTheFractionDone) {
  // 30 % done in 12 s: 70 % left at the same rate, 12 * 0.7 / 0.3 = 28 s.
  ASSERT_TRUE(dmbd::remaining_seconds(12.0, 0.3).has_value());
  EXPECT_NEAR(*dmbd::remaining_seconds(12.0, 0.3), 28.0, 1e-12);
  EXPECT_NEAR(*dmbd::remaining_seconds(2.0, 0.5), 2.0, 1e-12);
  EXPECT_EQ(*dmbd::remaining_seconds(40.0, 1.0), 0.0);  // done: nothing left, whatever the time
}

TEST(Progress, NoEstimateBeforeOneSecondOrTwoPercent) {
  EXPECT_FALSE(dmbd::remaining_seconds(0.99, 0.5).has_value());   // under 1 s of wall time
  EXPECT_FALSE(dmbd::remaining_seconds(30.0, 0.019).has_value()); // under 2 % done
  EXPECT_TRUE(dmbd::remaining_seconds(1.0, 0.02).has_value());    // both thresholds reached
  EXPECT_NEAR(*dmbd::remaining_seconds(1.0, 0.02), 49.0, 1e-12);
  EXPECT_FALSE(dmbd::remaining_seconds(5.0, 0.0).has_value());
  EXPECT_FALSE(dmbd::remaining_seconds(5.0, -0.1).has_value());
  EXPECT_FALSE(dmbd::remaining_seconds(5.0, 1.5).has_value());
}

TEST(Progress, DurationsInSecondsMinutesAndHours) {
  EXPECT_EQ(dmbd::format_duration(std::nullopt), "--");
  EXPECT_EQ(dmbd::format_duration(0.4), "0 s");
  EXPECT_EQ(dmbd::format_duration(28.0), "28 s");
  EXPECT_EQ(dmbd::format_duration(59.6), "1 min 00 s");
  EXPECT_EQ(dmbd::format_duration(185.0), "3 min 05 s");
  EXPECT_EQ(dmbd::format_duration(3599.4), "59 min 59 s");
  EXPECT_EQ(dmbd::format_duration(7620.0), "2 h 07 min");
  EXPECT_EQ(dmbd::format_duration(-1.0), "--");
}

TEST(Progress, LineShowsBarPercentElapsedAndEta) {
  EXPECT_EQ(dmbd::progress_line(0.3, "balance", 12.0),
            "[#########.....................]  30%  balance                    12.0 s  ETA 28 s");
  // Half a second in: no estimate yet.
  EXPECT_EQ(dmbd::progress_line(0.5, "walk", 0.5),
            "[###############...............]  50%  walk                        0.5 s  ETA --");
  EXPECT_EQ(dmbd::progress_line(1.0, "a_label_longer_than_twenty_four", 90.0),
            "[##############################] 100%  a_label_longer_than_twen   90.0 s  ETA 0 s");
}

}  // namespace
