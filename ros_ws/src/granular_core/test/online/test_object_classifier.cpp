// ObjectClassifier: one interface for the online node.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/online/object_classifier.h"
#include "support/registration_scene.h"

namespace granular {
namespace {
using testing_support::ClassifyFolderTest;

TEST_F(ClassifyFolderTest, ObjectClassifierLabelsEveryObjectAndLeavesTinyOnesUnknown) {
  const ObjectClassifier classifier = ObjectClassifier::registration(
      RegistrationMethod::kIcp, converging(), root_ / "models");
  EXPECT_EQ(classifier.method(), "icp");
  EXPECT_EQ(classifier.labels(), (std::vector<std::string>{"Long", "Tall"}));
  std::vector<Cloud> objects;
  for (const ModelCloud& object : objects_) {
    Cloud cloud;
    for (const pcl::PointXYZ& p : object.points) {
      cloud.push_back(PointXYZIT(p.x, p.y, p.z, 0, 0.0));
    }
    objects.push_back(cloud);
  }
  objects.push_back(Cloud());  // nothing to register
  const std::vector<ObjectPrediction> predictions = classifier.classify(objects);
  ASSERT_EQ(predictions.size(), objects.size());
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    EXPECT_TRUE(predictions[i].classified) << i;
    EXPECT_EQ(predictions[i].label, models_[truth_[i]].label) << i;
    // The right model fits far better than the other one.
    EXPECT_GT(predictions[i].score, 0.5) << i;
    EXPECT_LE(predictions[i].score, 1.0) << i;
  }
  EXPECT_FALSE(predictions.back().classified);
  EXPECT_EQ(predictions.back().label, "unknown");
  EXPECT_THROW(ObjectClassifier::registration(RegistrationMethod::kIcp, converging(),
                                              root_ / "no_models"),
               std::runtime_error);
}

}  // namespace
}  // namespace granular
