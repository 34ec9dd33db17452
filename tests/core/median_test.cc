#include "manyworlds/core/median.h"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace manyworlds {
namespace {

TEST(MedianTest, MiddleOfAnOddCountMeanOfTheTwoMiddleOfAnEvenOne) {
  EXPECT_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);  // not 3, the upper middle
  EXPECT_EQ(Median({7.0}), 7.0);
}

TEST(MedianTest, NoValuesIsAnError) {
  EXPECT_THROW(Median(std::vector<double>{}), std::invalid_argument);
}

}  // namespace
}  // namespace manyworlds
