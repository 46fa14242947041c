#include "granular_core/dataset/registration_results.h"

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "granular_core/dataset/atomic_file.h"

namespace granular {
namespace {

// The double whose shortest text is `value`'s as a float (at most 9 digits): the file then
// holds "0.016393442", not the widened float's "0.016393441706895828", and reads back as the
// same float, so that features from the file and the online node's agree.
double asWritten(float value) {
  char text[32];
  const std::to_chars_result end = std::to_chars(text, text + sizeof(text), value);
  return std::strtod(std::string(text, end.ptr).c_str(), nullptr);
}

template <typename T>
nlohmann::json orNull(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::string criterionKey(std::size_t index) { return "criterion" + std::to_string(index + 1); }

nlohmann::json pairJson(const RegistrationPairRecord& pair, bool with_transform) {
  nlohmann::json json = {{"converged", pair.converged},
                         {"state", pair.state},
                         {"iterations", pair.iterations},
                         {"fitness", orNull(pair.fitness)}};
  if (pair.fitness) {
    nlohmann::json shares = nlohmann::json::array();
    for (const float share : pair.inlier_shares) {
      shares.push_back(asWritten(share));
    }
    json["inlier_shares"] = shares;
  }
  if (pair.rejected) {
    json["rejected"] = true;
  }
  if (with_transform) {
    json["transform"] = pair.transform ? nlohmann::json(*pair.transform) : nlohmann::json(nullptr);
  }
  return json;
}

RegistrationPairRecord readPair(const nlohmann::json& json, bool with_shares,
                                bool with_transform) {
  RegistrationPairRecord pair;
  const nlohmann::json& fitness = json.at("fitness");
  if (!fitness.is_null()) {
    pair.fitness = fitness.get<double>();
    if (with_shares) {
      pair.inlier_shares = json.at("inlier_shares").get<std::vector<float>>();
    }
  }
  pair.converged = json.value("converged", false);
  pair.state = json.value("state", std::string());
  pair.iterations = json.value("iterations", 0);
  pair.rejected = json.value("rejected", false);
  if (with_transform && json.contains("transform") && !json.at("transform").is_null()) {
    pair.transform = json.at("transform").get<std::array<float, 16>>();
  }
  return pair;
}

}  // namespace

void writeRegistrationResults(const std::filesystem::path& file,
                              const RegistrationResultsFile& results) {
  nlohmann::json objects = nlohmann::json::array();
  for (const RegistrationObjectRecord& object : results.objects) {
    if (object.per_model.size() != results.models.size()) {
      throw std::invalid_argument(object.file + ": " + std::to_string(object.per_model.size()) +
                                  " pairs for " + std::to_string(results.models.size()) +
                                  " models");
    }
    nlohmann::json per_model = nlohmann::json::object();
    for (std::size_t m = 0; m < results.models.size(); ++m) {
      per_model[results.models[m]] = pairJson(object.per_model[m], results.transforms);
    }
    nlohmann::json predictions = nlohmann::json::object();
    for (std::size_t c = 0; c < object.predictions.size(); ++c) {
      predictions[criterionKey(c)] = orNull(object.predictions[c]);
    }
    objects.push_back({{"file", object.file},
                       {"true_label", orNull(object.true_label)},
                       {"points", object.points},
                       {"points_used", object.points_used},
                       {"per_model", per_model},
                       {"predictions", predictions}});
  }
  nlohmann::json missing = nlohmann::json::object();
  nlohmann::json accuracy = nlohmann::json::object();
  for (std::size_t c = 0; c < results.criteria.size(); ++c) {
    const RegistrationCriterionRecord& criterion = results.criteria[c];
    missing[criterionKey(c)] = criterion.missing;
    accuracy[criterionKey(c)] = {{"predicted", criterion.predicted},
                                 {"labelled", criterion.labelled},
                                 {"correct", criterion.correct},
                                 {"accuracy", criterion.accuracy}};
  }
  const nlohmann::json parameters = nlohmann::json::parse(results.parameters, nullptr, false);
  if (!parameters.is_object()) {
    throw std::invalid_argument("registration results: parameters is not a JSON object");
  }
  nlohmann::json document = {{"method", results.method},
                             {"preset", results.preset},
                             {"parameters", parameters},
                             {"models", results.models},
                             {"seconds", results.seconds},
                             {"threads", results.threads},
                             {"objects", objects},
                             {"missing", missing},
                             {"accuracy", accuracy},
                             {"warnings", results.warnings}};
  if (results.inlier_radii) {
    document["inlier_radii"] = *results.inlier_radii;
  }
  writeFileAtomically(file, document.dump(1) + "\n", "JSON");
}

RegistrationResultsFile readRegistrationResults(const std::filesystem::path& file) {
  const auto fail = [&](const std::string& what) {
    return std::runtime_error(file.string() + ": " + what);
  };
  std::ifstream stream(file);
  if (!stream) {
    throw fail("cannot read it");
  }
  RegistrationResultsFile results;
  try {
    const nlohmann::json document = nlohmann::json::parse(stream);
    if (!document.is_object() || !document.contains("models") ||
        !document.contains("objects")) {
      throw fail("not a classify_registration results file (no models or objects)");
    }
    results.method = document.at("method").get<std::string>();
    results.preset = document.value("preset", std::string());
    results.parameters = document.at("parameters").dump();
    results.models = document.at("models").get<std::vector<std::string>>();
    results.seconds = document.value("seconds", 0.0);
    results.threads = document.value("threads", 0);
    if (document.contains("inlier_radii")) {
      results.inlier_radii = document.at("inlier_radii").get<std::vector<double>>();
    }
    for (const nlohmann::json& object : document.at("objects")) {
      RegistrationObjectRecord& record = results.objects.emplace_back();
      record.file = object.at("file").get<std::string>();
      if (object.contains("true_label") && !object.at("true_label").is_null()) {
        record.true_label = object.at("true_label").get<std::string>();
      }
      record.points = object.at("points").get<std::size_t>();
      record.points_used = object.value("points_used", std::size_t{0});
      const nlohmann::json& per_model = object.at("per_model");
      for (const std::string& model : results.models) {
        const nlohmann::json& pair = per_model.at(model);
        results.transforms = results.transforms || pair.contains("transform");
        record.per_model.push_back(
            readPair(pair, results.inlier_radii.has_value(), results.transforms));
      }
      if (object.contains("predictions")) {
        for (std::size_t c = 0; c < record.predictions.size(); ++c) {
          const nlohmann::json& prediction = object.at("predictions").at(criterionKey(c));
          if (!prediction.is_null()) {
            record.predictions[c] = prediction.get<std::string>();
          }
        }
      }
    }
    for (std::size_t c = 0; c < results.criteria.size(); ++c) {
      RegistrationCriterionRecord& criterion = results.criteria[c];
      if (document.contains("missing")) {
        criterion.missing = document.at("missing").at(criterionKey(c)).get<std::size_t>();
      }
      if (document.contains("accuracy")) {
        const nlohmann::json& accuracy = document.at("accuracy").at(criterionKey(c));
        criterion.predicted = accuracy.at("predicted").get<std::size_t>();
        criterion.labelled = accuracy.at("labelled").get<std::size_t>();
        criterion.correct = accuracy.at("correct").get<std::size_t>();
        criterion.accuracy = accuracy.at("accuracy").get<double>();
      }
    }
    results.warnings = document.value("warnings", std::vector<std::string>());
  } catch (const nlohmann::json::exception& error) {
    throw fail(std::string("not a classify_registration results file (") + error.what() + ")");
  }
  return results;
}

}  // namespace granular
