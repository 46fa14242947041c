// Plain concatenation.
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/models/concatenate.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::pointsOf;
using testing_clouds::lattice;

// ---- concatenation -------------------------------------------------------------------------

TEST(ConcatenateTest, GivesTheUnionInOrder) {
  const ModelCloud a = lattice({0, 0, 0}, 1.0, 3, 1, 1);
  const ModelCloud b = lattice({0, 5, 1}, 0.5, 1, 2, 1);
  const ModelCloud both = concatenate({a, b});
  ASSERT_EQ(both.size(), 5u);
  const std::vector<Eigen::Vector3f> expected = {
      {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 5, 1}, {0, 5.5f, 1}};
  EXPECT_EQ(pointsOf(both), expected);
  EXPECT_TRUE(concatenate({}).empty());
  EXPECT_EQ(pointsOf(concatenate({ModelCloud(), a})), pointsOf(a));
}

}  // namespace
}  // namespace granular
