"""run_evaluation: svm_fitness learns from registrations that must also run, refused before
anything is written otherwise; several train drives are learnt from together."""
import csv
import json

import hostile
from granular_tools.simulation import cli as simulate

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


def test_several_train_drives_give_models_and_classifiers_of_all_their_objects(tmp_path):
    bags = {}
    for name, seed in (("first", 1), ("second", 3), ("test", 2)):
        bags[name] = tmp_path / f"{name}.bag"
        assert simulate.main(["--out", str(bags[name]), "--duration", "8", "--seed", str(seed),
                              "--quiet"]) == 0
    out = tmp_path / "evaluation"
    common = ["--test-bag", bags["test"], "--out", out, "--methods", "icp", "--presets",
              "tuned", "--supervised", "knn", "--n-thresh", "10"]
    result = hostile.run(RUN_EVALUATION + ["--train-bag", f"{bags['first']},{bags['second']}"]
                         + common)
    assert result.status == 0, str(result)
    train = out / "train"
    drives = [sorted(p.name for p in (train / f"drive-{k}" / "objects" / "N10").glob("*.pcd"))
              for k in (1, 2)]
    assert drives[0] and drives[1]
    merged = sorted(p.name for p in (train / "objects" / "N10").glob("*.pcd"))
    assert merged == sorted(drives[0] + drives[1])
    with open(train / "objects" / "N10" / "index.csv", newline="") as stream:
        assert sorted(row["file"] for row in csv.DictReader(stream)) == merged
    models = json.loads((train / "models" / "models.json").read_text())
    assert sum(c["objects"] for c in models["classes"].values()) == len(merged)
    assert f"{len(merged)} train objects from 2 drives" in result.stdout

    # The same drive twice would count its objects twice: refused before anything runs.
    again = hostile.run(RUN_EVALUATION + ["--train-bag", f"{bags['first']},{bags['first']}"]
                        + common[:3] + [tmp_path / "twice"] + common[4:])
    assert again.status == 2
    assert "names one bag twice" in again.stderr
    assert not (tmp_path / "twice").exists()
