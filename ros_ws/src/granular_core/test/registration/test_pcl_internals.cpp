// Four classes reach into PCL's protected members or override its virtual methods:
// NearestTree (pcl::search::KdTree), ReusableIcp in icp_common.h (IterativeClosestPoint's
// nr_iterations_, convergence_criteria_, correspondences_), and NdtMatcher's ModelCells
// (VoxelGridCovariance's cells) and NdtParts (NormalDistributionsTransform's derivative and
// More-Thuente helpers). They were written against
// PCL 1.13; the bit-for-bit tests (test_registration_classifier, test_ndt_matcher) say whether
// they still agree with PCL, and this one says that PCL changed, so that an upgrade is read
// against those classes first.
#include <pcl/pcl_config.h>

#include <gtest/gtest.h>

namespace granular {
namespace {

TEST(PclInternalsTest, ThePclVersionTheSubclassesWereWrittenFor) {
  EXPECT_EQ(PCL_MAJOR_VERSION, 1);
  EXPECT_EQ(PCL_MINOR_VERSION, 13)
      << "PCL " << PCL_VERSION_PRETTY << ": check NearestTree, ReusableIcp (icp_common.h), "
      << "ModelCells and NdtParts (ndt_matcher.cpp) against its sources, then update this test";
}

}  // namespace
}  // namespace granular
