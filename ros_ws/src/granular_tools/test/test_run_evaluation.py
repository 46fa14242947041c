"""run_evaluation: svm_fitness learns from registrations that must also run, refused before
anything is written otherwise."""
import hostile

RUN_EVALUATION = hostile.tool("granular_tools", "run_evaluation")


def test_svm_fitness_without_its_registrations_is_refused_before_anything_runs(tmp_path):
    bag = tmp_path / "drive.bag"
    bag.write_bytes(b"")
    for extra, missing in ((["--methods", "icp"], "ndt_tuned, icp_nl_tuned"),
                           (["--presets", "report"], "icp_tuned, ndt_tuned, icp_nl_tuned"),
                           (["--fitness-from", "icp_nl_tuned", "--methods", "icp,ndt"],
                            "icp_nl_tuned")):
        result = hostile.run(RUN_EVALUATION + ["--train-bag", bag, "--test-bag", bag,
                                               "--out", tmp_path / "evaluation"] + extra)
        assert result.status == 2, result.stderr
        assert f"{missing} of them would not run" in result.stderr
        assert not (tmp_path / "evaluation").exists()
    # Without svm_fitness the same methods are fine as far as svm_fitness is concerned.
    result = hostile.run(RUN_EVALUATION + ["--train-bag", bag, "--test-bag", bag, "--out",
                                           tmp_path / "evaluation", "--methods", "icp",
                                           "--supervised", "knn"])
    assert "would not run" not in result.stderr
