"""Grid search behind scripts/tune_registration; see that script's header."""
import itertools
import json
import os
import subprocess
import sys
import tempfile

THRESHOLDS = ("N10", "N50", "N100")
# ICP and ICP-NL's coarse stage pairs points up to its default 0.1 m (registration_config.h)
# for the iterations given; 0 is none.
CANDIDATES = {
    "icp": {"max_iterations": [1, 10, 30, 100],
            "max_correspondence_distance": [0.01, 0.03, 0.05, 0.1, 0.2, 0.5],
            "coarse_iterations": [0, 1, 3, 10],
            "source_min_z": [None, 0.2]},
    # 100 iterations were left out while ICP-NL's step was PCL's (numerical Jacobians, several
    # times ICP's cost); with the analytic step (point_to_point_lm.h) they take about ICP's time.
    "icp_nl": {"max_iterations": [1, 10, 30, 100],
               "max_correspondence_distance": [0.01, 0.03, 0.05, 0.1, 0.2, 0.5],
               "coarse_iterations": [0, 1, 3, 10],
               "source_min_z": [None, 0.2]},
    "ndt": {"resolution": [0.1, 0.2, 0.3, 0.5, 1.0], "min_points_per_voxel": [3, 6],
            "source_min_z": [None, 0.2]},
}


def preset_yaml(method, values, max_points):
    section = {k: v for k, v in values.items() if k != "source_min_z"}
    body = ", ".join(f"{k}: {v}" for k, v in section.items())
    min_z = "null" if values["source_min_z"] is None else values["source_min_z"]
    return (f"presets:\n  candidate:\n    {method}: {{{body}}}\n    source_min_z: {min_z}\n"
            f"    source_max_points: {max_points}\n")


def accuracy(results_file):
    with open(results_file, encoding="utf-8") as stream:
        objects = json.load(stream)["objects"]
    correct = sum(o["predictions"]["criterion2"] == o["true_label"] for o in objects)
    return correct / len(objects) if objects else 0.0


def evaluate(method, values, models, objects_root, work, max_points):
    config = os.path.join(work, "candidate.yaml")
    with open(config, "w", encoding="utf-8") as stream:
        stream.write(preset_yaml(method, values, max_points))
    scores = []
    for threshold in THRESHOLDS:
        out = os.path.join(work, "results.json")
        run = subprocess.run(["rosrun", "granular_ros", "classify_registration", "--models",
                              models, "--objects", os.path.join(objects_root, threshold),
                              "--method", method, "--preset", "candidate", "--config", config,
                              "--out", out],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                             check=False)
        if run.returncode != 0:
            lines = run.stderr.strip().splitlines() or ["(no message)"]
            sys.exit(f"tune_registration: classify_registration failed on {threshold} with "
                     f"{values}: {lines[-1]}")
        scores.append(accuracy(out))
    return sum(scores) / len(scores), scores


def main(argv):
    # scripts/tune_registration has checked the count and the folders.
    max_points = 0
    if argv[:1] == ["--max-points"]:
        max_points, argv = int(argv[1]), argv[2:]
    models, objects_root, *methods = argv
    unknown = [method for method in methods if method not in CANDIDATES]
    if unknown:
        sys.exit(f"error: unknown method '{unknown[0]}' ({', '.join(CANDIDATES)})")
    with tempfile.TemporaryDirectory() as work:
        for method in methods or CANDIDATES:
            grid = CANDIDATES[method]
            best = None
            for combination in itertools.product(*grid.values()):
                values = dict(zip(grid, combination))
                mean, scores = evaluate(method, values, models, objects_root, work, max_points)
                cells = " ".join(f"{t} {s:.3f}" for t, s in zip(THRESHOLDS, scores))
                print(f"{method} {values}: mean {mean:.3f} ({cells})", flush=True)
                if best is None or mean > best[0]:
                    best = (mean, values)
            print(f"best {method}: {best[1]} mean {best[0]:.3f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
