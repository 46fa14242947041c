// Five places reach into PCL's protected members, override its virtual methods or repeat its
// code: NearestTree (pcl::search::KdTree), IcpWithIterations in icp_common.h
// (IterativeClosestPoint's nr_iterations_), point_to_point_icp.h (IterativeClosestPoint's
// loop), and NdtMatcher's ModelCells (VoxelGridCovariance's cells) and NdtParts
// (NormalDistributionsTransform's derivative and More-Thuente helpers). They were written against
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
      << "PCL " << PCL_VERSION_PRETTY
      << ": check NearestTree, IcpWithIterations (icp_common.h), point_to_point_icp.h, "
      << "ModelCells and NdtParts (ndt_matcher.cpp) against its sources, then update this test";
}

}  // namespace
}  // namespace granular
