// report 8.3: NDT through NdtMatcher (PCL's NormalDistributionsTransform, bit for bit), its
// cells built once per model and shared by every thread.
#include <string>

#include "granular_core/registration/ndt_matcher.h"
#include "granular_core/registration/registration.h"
#include "ndt_common.h"

namespace granular {
namespace {

class NdtAligner : public ModelAligner {
 public:
  NdtAligner(const std::vector<std::unique_ptr<const NdtMatcher>>& matchers, int max_iterations)
      : matchers_(matchers), max_iterations_(max_iterations) {}

  PairResult align(const ModelCloud::ConstPtr& source, std::size_t model) override {
    const NdtMatcher::Result aligned = matchers_[model]->align(*source);
    PairResult result;
    result.iterations = aligned.iterations;
    result.state = ndt_detail::ndtState(aligned.likelihood, aligned.converged,
                                        aligned.iterations, max_iterations_);
    result.transform = aligned.transform;
    return result;
  }

 private:
  const std::vector<std::unique_ptr<const NdtMatcher>>& matchers_;
  int max_iterations_;
};

class NdtMethod : public RegistrationMethodImpl {
 public:
  NdtMethod(const NdtClassifierConfig& config, const PreparedModels& models,
            const std::vector<std::string>& labels)
      : config_(config) {
    for (std::size_t m = 0; m < models.clouds.size(); ++m) {
      const ModelCloud& cloud = *models.clouds[m];
      auto matcher = std::make_unique<const NdtMatcher>(cloud, config);
      if (matcher->cells() == 0) {
        // PCL's NDT then returns at once without aligning; the pairs record that as
        // no_correspondences, with the fitness of the object where it is.
        warnings_.push_back(
            "NDT: no voxel of " + std::to_string(config.resolution) + " m holds " +
            std::to_string(config.min_points_per_voxel) + " of the " +
            std::to_string(cloud.size()) + " points of the model of class '" + labels[m] +
            "', so it has no cell to match and no object is aligned to it "
            "(no_correspondences); a coarser ndt.resolution gives it cells");
      }
      matchers_.push_back(std::move(matcher));
    }
  }

  std::unique_ptr<ModelAligner> aligner() const override {
    // NdtMatcher::align is const: every thread shares the matchers.
    return std::make_unique<NdtAligner>(matchers_, config_.max_iterations);
  }

  std::vector<std::string> warnings() const override { return warnings_; }

 private:
  NdtClassifierConfig config_;
  std::vector<std::unique_ptr<const NdtMatcher>> matchers_;
  std::vector<std::string> warnings_;
};

}  // namespace

std::unique_ptr<RegistrationMethodImpl> prepareNdt(const NdtClassifierConfig& config,
                                                   const PreparedModels& models,
                                                   const std::vector<std::string>& labels) {
  return std::make_unique<NdtMethod>(config, models, labels);
}

}  // namespace granular
