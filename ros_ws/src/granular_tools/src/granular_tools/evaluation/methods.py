"""The classification methods the evaluation compares, and which it runs unless asked
(run_evaluation, evaluate_many)."""
REGISTRATION_METHODS = ("icp", "icp_nl", "ndt")
SUPERVISED_METHODS = ("knn", "svm", "svm_esf", "svm_fitness")
# ESF takes 8 ms an object (docs/supervised.md), the demo's two minutes and 80 % of a frame's
# budget online, for the lowest accuracy: asked for by name only.
DEFAULT_SUPERVISED = ("knn", "svm", "svm_fitness")
PRESETS = ("report", "tuned", "fast")
# What run_evaluation compares unless asked: the report's values and the tuned ones.
DEFAULT_PRESETS = ("report", "tuned")
# The registrations svm_fitness learns from: tuned ICP, NDT and ICP-NL (ICP-NL's fitness was
# worth 0.6 points on the four cars at N_thresh 100, and about 0.1 since ICP-NL shares ICP's
# coarse stage and values, docs/classification.md; the evaluation runs all three anyway).
DEFAULT_FITNESS_FROM = ("icp_tuned", "ndt_tuned", "icp_nl_tuned")
