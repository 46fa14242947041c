"""Hostile inputs, real-world data: free-text labels that must survive every stage, broken or
implausible boxes, broken bags and configs. Each case runs the built tools as a user would and
asserts the exit status, a message naming the culprit and that nothing crashed."""
import csv
import json
import os

import numpy as np
import pytest
import rosbag

import bagmaker
import hostile
from bagmaker import CLOUD_TOPIC, DETECTIONS_TOPIC
from hostile import (assert_fails_clearly, assert_no_crash, leftovers, run, EXTRACT, BUILD_MODELS,
                     TRAIN, CLASSIFY_REGISTRATION, CLASSIFY_SUPERVISED, BAG_TO_FILES, SIMULATE,
                     MAKE_REPORT)
from granular_tools.messages import POINT_DTYPE, LabelledBox, cloud_message, detections_message


# Labels as real datasets and users write them (PandaSet's, and typed ones).
FREE_TEXT_LABELS = ["Medium-sized_Truck", "Tram_/_Subway", "Other_Vehicle_-_Pedicab",
                    "Other_Vehicle_-_Uncommon", "Straßenbahn Linie 3", ".dotted", "Sedan"]


def boxes_and_points(labels, rng):
    """A box per label, 6 m apart along y, and 150 points on each box's surface."""
    detections, points = [], []
    for index, label in enumerate(labels):
        centre = np.array([12.0, 6.0 * (index - len(labels) / 2.0), -0.8])
        size = np.array([4.0, 1.8, 1.5])
        detections.append(LabelledBox(200 + index, label, centre, (0.0, 0.0, 0.0, 1.0), size))
        local = rng.uniform(-0.5, 0.5, size=(150, 3)) * size * 0.95
        points.append(centre + local)
    return detections, np.vstack(points)


def free_text_bag(path, labels=FREE_TEXT_LABELS, frames=6):
    rng = np.random.default_rng(5)
    messages = []
    for frame in range(frames):
        detections, points = boxes_and_points(labels, rng)
        stamp = bagmaker.stamp(0.1 * frame)
        messages.append((CLOUD_TOPIC, bagmaker.cloud(0.1 * frame, points, frame)))
        messages.append((DETECTIONS_TOPIC,
                         detections_message(detections, stamp, "velodyne", frame)))
    return bagmaker.write(path, messages)


@pytest.fixture(scope="module")
def free_text(tmp_path_factory):
    """The free-text labels taken from a bag through frames, objects and models."""
    folder = tmp_path_factory.mktemp("labels")
    bag = free_text_bag(folder / "labels.bag")
    for command in (BAG_TO_FILES + ["--bag", bag, "--out", folder / "frames", "--quiet"],
                    EXTRACT + ["--in", folder / "frames", "--out", folder / "objects"],
                    BUILD_MODELS + ["--objects", folder / "objects", "--out", folder / "models"]):
        result = run(command)
        assert result.status == 0, str(result)
    return folder


# --- free-text labels round-trip through every stage ---------------------------------------

def test_free_text_labels_reach_the_frames_json_exactly(free_text):
    labels = set()
    for path in (free_text / "frames" / "detections_3d").iterdir():
        labels |= {d["label"] for d in json.loads(path.read_text(encoding="utf-8"))["detections"]}
    assert labels == set(FREE_TEXT_LABELS)


def test_every_free_text_label_gets_its_own_visible_object_files(free_text):
    names = os.listdir(free_text / "objects")
    assert not [name for name in names if name.startswith(".") and name != ".granular.json"]
    index = (free_text / "objects" / "index.csv").read_text(encoding="utf-8").splitlines()[1:]
    # The labels column holds the label as given, however the file name encodes it.
    import csv
    rows = list(csv.DictReader([(free_text / "objects" / "index.csv").read_text(
        encoding="utf-8").splitlines()[0]] + index))
    assert {row["label"] for row in rows} == set(FREE_TEXT_LABELS)
    assert len(rows) == 6 * len(FREE_TEXT_LABELS)
    assert all((free_text / "objects" / row["file"]).is_file() for row in rows)


def test_labels_that_share_a_prefix_are_not_merged_into_one_model(free_text):
    from granular_tools.labels import model_label

    models = sorted(model_label(path) for path in (free_text / "models").iterdir()
                    if path.suffix == ".pcd")
    assert models == sorted(FREE_TEXT_LABELS)
    document = json.loads((free_text / "models" / "models.json").read_text(encoding="utf-8"))
    assert sorted(document["classes"]) == sorted(FREE_TEXT_LABELS)
    assert all(entry["objects"] == 6 for entry in document["classes"].values())


def test_free_text_labels_survive_classification_and_the_report(free_text, tmp_path):
    results = tmp_path / "results"
    (results / "knn").mkdir(parents=True)
    (results / "ndt").mkdir()
    commands = [
        TRAIN + ["--objects", free_text / "objects", "--method", "knn", "--out",
                 tmp_path / "knn.yml"],
        CLASSIFY_SUPERVISED + ["--model", tmp_path / "knn.yml", "--objects",
                               free_text / "objects", "--out", results / "knn" / "N10.json"],
        CLASSIFY_REGISTRATION + ["--models", free_text / "models", "--objects",
                                 free_text / "objects", "--method", "ndt", "--out",
                                 results / "ndt" / "N10.json"],
        MAKE_REPORT + ["--results", results, "--out", tmp_path / "report"],
    ]
    for command in commands:
        result = run(command)
        assert result.status == 0, str(result)
    for method in ("knn", "ndt"):
        text = (results / method / "N10.json").read_text(encoding="utf-8")
        for label in FREE_TEXT_LABELS:
            assert json.dumps(label)[1:-1] in text or label in text, (method, label)
    summary = json.loads((tmp_path / "report" / "summary.json").read_text(encoding="utf-8"))
    assert set(FREE_TEXT_LABELS) <= set(json.dumps(summary, ensure_ascii=False).split('"'))


def test_free_text_labels_are_drawn_as_given_in_the_rviz_markers():
    import rospy
    from granular_tools.visualization.detection_markers import detection_markers

    detections, _ = boxes_and_points(FREE_TEXT_LABELS, np.random.default_rng(1))
    message = detections_message(detections, bagmaker.stamp(0.0), "velodyne", 0)
    markers = detection_markers(message, rospy.Duration(0.5))
    texts = [m.text for m in markers.markers if m.text]
    assert [t.rsplit(" ", 1)[0] for t in texts] == FREE_TEXT_LABELS


# --- broken and implausible boxes ----------------------------------------------------------

def test_nan_and_infinite_boxes_are_skipped_counted_and_never_written_as_json(tmp_path):
    broken = bagmaker.detections(0.0, ("Sedan", "SUV", "Jeep", "Hatchback"))
    broken.detections[0].bbox.position.position.x = float("nan")
    broken.detections[1].bbox.size.y = float("inf")
    broken.detections[2].bbox.position.orientation.w = float("-inf")
    bag = bagmaker.write(tmp_path / "in.bag", [(CLOUD_TOPIC, bagmaker.cloud(0.0)),
                                               (DETECTIONS_TOPIC, broken)])
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", tmp_path / "frames"])
    assert result.status == 0, str(result)
    assert "3 a box with NaN or infinite numbers (id 100 'Sedan' in frame " \
           "1586102742.000000000, id 101 'SUV' in frame 1586102742.000000000, id 102 'Jeep'" \
           in result.output, str(result)
    (path,) = (tmp_path / "frames" / "detections_3d").iterdir()
    text = path.read_text()
    assert "NaN" not in text and "Infinity" not in text
    document = json.loads(text, parse_constant=lambda name: pytest.fail(f"{name} in JSON"))
    assert [d["label"] for d in document["detections"]] == ["Hatchback"]


def test_a_hand_edited_json_with_nan_is_named_as_not_json(drive, tmp_path):
    frames = hostile.copy_tree(drive / "frames", tmp_path / "frames")
    first = sorted((frames / "detections_3d").iterdir())[0]
    document = json.loads(first.read_text())
    document["detections"][0]["bbox"]["size"]["x"] = float("nan")
    first.write_text(json.dumps(document))
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert_fails_clearly(result, 1, first, "not valid JSON")
    assert not (tmp_path / "objects").exists() and leftovers(tmp_path) == []


def test_a_box_with_a_negative_size_is_an_invalid_detection_not_a_stopped_run(drive, tmp_path):
    frames = hostile.copy_tree(drive / "frames", tmp_path / "frames")
    first = sorted((frames / "detections_3d").iterdir())[0]
    document = json.loads(first.read_text())
    document["detections"][0]["bbox"]["size"]["x"] = -4.0
    first.write_text(json.dumps(document))
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert result.status == 0, str(result)
    assert first.name in result.output and "invalid detections skipped" in result.output


def test_an_implausibly_large_box_is_skipped_with_a_warning(drive, tmp_path):
    frames = hostile.copy_tree(drive / "frames", tmp_path / "frames")
    first = sorted((frames / "detections_3d").iterdir())[0]
    document = json.loads(first.read_text())
    document["detections"][0]["bbox"]["size"] = {"x": 1e30, "y": 1e30, "z": 1e30}
    first.write_text(json.dumps(document))
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert result.status == 0, str(result)
    assert "max_box_size" in result.output and first.name in result.output
    rows = (tmp_path / "objects" / "index.csv").read_text().splitlines()[1:]
    assert all(float(row.split(",")[6]) < 100 for row in rows)


def test_a_detection_json_that_is_not_json_names_the_file(drive, tmp_path):
    frames = hostile.copy_tree(drive / "frames", tmp_path / "frames")
    first = sorted((frames / "detections_3d").iterdir())[0]
    first.write_text('{"detections": [')
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert_fails_clearly(result, 1, first)
    assert not (tmp_path / "objects").exists() and leftovers(tmp_path) == []


def test_a_truncated_pcd_names_the_file(drive, tmp_path):
    frames = hostile.copy_tree(drive / "frames", tmp_path / "frames")
    first = sorted((frames / "pcd").iterdir())[0]
    first.write_bytes(first.read_bytes()[:-100])
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert_fails_clearly(result, 1, first)
    assert not (tmp_path / "objects").exists() and leftovers(tmp_path) == []


def test_detections_of_another_frame_without_tf_are_skipped_and_counted(tmp_path):
    elsewhere = bagmaker.detections(0.0, ("Sedan", "SUV"))
    elsewhere.detections[0].header.frame_id = "map"
    bag = bagmaker.write(tmp_path / "in.bag", [(CLOUD_TOPIC, bagmaker.cloud(0.0)),
                                               (DETECTIONS_TOPIC, elsewhere)])
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", tmp_path / "frames"])
    assert result.status == 0, str(result)
    assert "in frame 'map' with no transform" in result.output


# --- broken bags --------------------------------------------------------------------------

def test_a_truncated_bag_names_the_bag(drive, tmp_path):
    bag = tmp_path / "cut.bag"
    raw = (drive / "drive.bag").read_bytes()
    bag.write_bytes(raw[: len(raw) // 2])
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", tmp_path / "frames"])
    assert result.status in (1, 2)
    assert_fails_clearly(result, result.status, bag)
    assert not (tmp_path / "frames").exists() and leftovers(tmp_path) == []


def test_an_unindexed_bag_names_the_bag_and_says_how_to_repair_it(drive, tmp_path):
    bag = tmp_path / "unindexed.bag"
    raw = (drive / "drive.bag").read_bytes()
    # The index sits at the end of a bag: cutting the last bytes leaves an unindexed one.
    bag.write_bytes(raw[: len(raw) - 2000])
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", tmp_path / "frames"])
    assert_fails_clearly(result, result.status, bag)
    assert result.status in (1, 2) and "reindex" in result.output


def test_a_corrupt_record_in_an_indexed_bag_names_the_bag(drive, tmp_path):
    bag = tmp_path / "corrupt.bag"
    raw = bytearray((drive / "drive.bag").read_bytes())
    # The second chunk's record header, where the index says it is.
    with rosbag.Bag(str(drive / "drive.bag")) as reader:
        position = reader._chunks[1].pos
    raw[position:position + 64] = b"\xff" * 64
    bag.write_bytes(bytes(raw))
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", tmp_path / "frames"])
    assert result.status in (1, 2)
    assert_fails_clearly(result, result.status, bag)
    assert not (tmp_path / "frames").exists() and leftovers(tmp_path) == []


def test_a_file_that_is_not_a_bag_names_it(tmp_path):
    bag = tmp_path / "photo.bag"
    bag.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 100)
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", tmp_path / "frames"])
    assert result.status in (1, 2)
    assert_fails_clearly(result, result.status, bag)


def test_a_bag_that_does_not_exist_names_the_path(tmp_path):
    result = run(BAG_TO_FILES + ["--bag", tmp_path / "missing.bag", "--out", tmp_path / "f"])
    assert result.status in (1, 2)
    assert_fails_clearly(result, result.status, tmp_path / "missing.bag")


# --- simulator configs: the file, key, value and range named ---------------------------------

@pytest.mark.parametrize("yaml_text,names", [
    ("rate_hz: 0\n", ["rate_hz", "0"]),
    ("lidar:\n  rate_hz: 0\n", ["lidar.rate_hz", "0"]),
    ("lidar:\n  measurements_per_revolution: -5\n", ["measurements_per_revolution", "-5"]),
    ("lidar:\n  lasers: 0\n", ["lasers", "0"]),
    ("traffic:\n  class_weights:\n    Sedna: 1.0\n", ["Sedna"]),
    ("lidar: [1, 2]\n", ["lidar"]),
    ("lidar:\n  rate_hz: fast\n", ["rate_hz", "fast"]),
])
def test_simulator_configs_out_of_range_are_named(tmp_path, yaml_text, names):
    config = tmp_path / "sim.yaml"
    config.write_text(yaml_text)
    result = run(SIMULATE + ["--out", tmp_path / "d.bag", "--duration", "1", "--config", config,
                             "--quiet"])
    assert_fails_clearly(result, 2, config, *names)
    assert not (tmp_path / "d.bag").exists()


# --- typos that must not pass silently ------------------------------------------------------

def test_an_unknown_key_in_a_tool_config_names_the_file_the_key_and_the_known_keys(drive,
                                                                                    tmp_path):
    config = tmp_path / "extraction.yaml"
    config.write_text("n_tresh: [10]\n")
    result = run(EXTRACT + ["--in", drive / "frames", "--out", tmp_path / "o", "--config",
                            config])
    assert_fails_clearly(result, 2, config, "n_tresh", "n_thresh")


@pytest.mark.parametrize("option,value,culprit", [
    ("--n-thresh", "ten", "ten"), ("--n-thresh", "-5", "-5"), ("--padding", "1,2", "1,2"),
    ("--padding", "a,b,c", "'a'")])
def test_bad_option_values_name_the_option_and_value(drive, tmp_path, option, value, culprit):
    result = run(EXTRACT + ["--in", drive / "frames", "--out", tmp_path / "o", option, value])
    assert_fails_clearly(result, 2, option, culprit)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("threads", ["0", "-1", "two", "99999"])
def test_threads_below_one_or_past_1024_are_refused_by_every_tool_that_has_the_option(
        drive, tmp_path, threads):
    commands = [
        CLASSIFY_REGISTRATION + ["--models", drive / "models", "--objects", drive / "objects",
                                 "--method", "ndt", "--out", tmp_path / "r.json"],
        CLASSIFY_SUPERVISED + ["--model", drive / "knn.yml", "--objects", drive / "objects",
                               "--out", tmp_path / "s.json"],
        TRAIN + ["--objects", drive / "objects", "--method", "knn", "--out", tmp_path / "m.yml"],
    ]
    for command in commands:
        result = run(command + ["--threads", threads])
        assert_fails_clearly(result, 2, "--threads", threads)
    assert sorted(os.listdir(tmp_path)) == []


def test_an_unknown_preset_is_named_with_the_known_ones(drive, tmp_path):
    result = run(CLASSIFY_REGISTRATION + ["--models", drive / "models", "--objects",
                                          drive / "objects", "--method", "ndt", "--preset",
                                          "tunned", "--out", tmp_path / "r.json"])
    assert_fails_clearly(result, 2, "tunned", "tuned")


def test_a_classifier_file_cut_short_is_named(drive, tmp_path):
    model = tmp_path / "knn.yml"
    raw = (drive / "knn.yml").read_bytes()
    model.write_bytes(raw[: len(raw) // 2])
    result = run(CLASSIFY_SUPERVISED + ["--model", model, "--objects", drive / "objects",
                                        "--out", tmp_path / "s.json"])
    assert result.status in (1, 2)
    assert_fails_clearly(result, result.status, model)
    assert not (tmp_path / "s.json").exists()


def test_a_models_folder_given_as_a_classifier_says_what_was_expected(drive, tmp_path):
    result = run(CLASSIFY_SUPERVISED + ["--model", drive / "models", "--objects",
                                        drive / "objects", "--out", tmp_path / "s.json"])
    assert result.status in (1, 2)
    assert_fails_clearly(result, result.status, drive / "models")
    assert_no_crash(result)


def test_labels_that_match_no_detection_are_an_error_not_an_empty_result(drive, tmp_path):
    result = run(EXTRACT + ["--in", drive / "frames", "--out", tmp_path / "o", "--labels",
                            "Sedna,Jepp"])
    assert_fails_clearly(result, 1, "Sedna", "Jepp", "labels seen")
    assert not (tmp_path / "o").exists() and leftovers(tmp_path) == []


def test_a_label_that_matches_nothing_beside_one_that_does_is_warned(drive, tmp_path):
    result = run(EXTRACT + ["--in", drive / "frames", "--out", tmp_path / "o", "--labels",
                            "Sedan,Sedna"])
    assert result.status == 0, str(result)
    assert "'Sedna' (labels) matches no detection" in result.output


def test_a_misspelt_class_under_class_filters_is_warned(drive, tmp_path):
    config = tmp_path / "models.yaml"
    config.write_text("class_filters:\n  Sedna: {voxel_grid: {leaf_size: 0.05}}\n")
    result = run(BUILD_MODELS + ["--objects", drive / "objects", "--out", tmp_path / "m",
                                 "--config", config])
    assert result.status == 0, str(result)
    assert "class_filters.Sedna: no objects of class 'Sedna'" in result.output


def test_a_voxel_leaf_too_small_for_pcl_is_refused_not_skipped(drive, tmp_path):
    config = tmp_path / "models.yaml"
    config.write_text("class_filters:\n  Sedan: {voxel_grid: {leaf_size: 1.0e-6}}\n")
    result = run(BUILD_MODELS + ["--objects", drive / "objects", "--out", tmp_path / "m",
                                 "--config", config, "--classes", "Sedan"])
    assert_fails_clearly(result, 1, "voxel_grid.leaf_size", "class 'Sedan'", "use at least")
    assert not (tmp_path / "m").exists() and leftovers(tmp_path) == []


def sparse_objects_folder(folder):
    """An objects folder with a class whose points lie a metre apart: the radius filter keeps
    none of them (a sparse real Bus)."""
    folder.mkdir()
    points = np.array([[x, 0.0, 1.0] for x in range(-5, 6)], float)
    message = cloud_message(points, np.zeros(len(points), np.uint8), bagmaker.stamp(0.0),
                                     "object", 0)
    header = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity timestamp\nSIZE 4 4 4 1 8\n"
              "TYPE F F F U F\nCOUNT 1 1 1 1 1\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
              "POINTS {n}\nDATA binary\n").format(n=len(points))
    record = np.frombuffer(message.data, dtype=POINT_DTYPE)
    packed = np.zeros(len(record), dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"),
                                          ("intensity", "u1"), ("timestamp", "<f8")])
    for name in packed.dtype.names:
        packed[name] = record[name]
    for index in range(1, 4):
        packed["y"] = 0.5 * index  # the objects' points do not meet either
        (folder / f"Bus-100-{index}.pcd").write_bytes(header.encode() + packed.tobytes())
    return folder


def test_a_cloud_whose_every_point_is_nan_is_named_when_its_objects_are_extracted(tmp_path):
    """It failed stages later, in build_models ("the filters left no points"), with no word
    that the points were not finite."""
    points = np.full((200, 3), np.nan)
    points[:, 1:] = 0.0  # every x NaN
    bag = bagmaker.write(tmp_path / "in.bag", [(CLOUD_TOPIC, bagmaker.cloud(0.0, points)),
                                               (DETECTIONS_TOPIC, bagmaker.detections(0.0))])
    frames = tmp_path / "frames"
    assert run(BAG_TO_FILES + ["--bag", bag, "--out", frames, "--quiet"]).status == 0
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    (pcd,) = (frames / "pcd").iterdir()
    assert result.status == 0, str(result)
    hostile.assert_no_crash(result)
    assert f"{pcd}: all 200 points are NaN or infinite" in result.output, str(result)


def test_a_model_that_the_filters_empty_names_the_class_the_filter_and_what_to_change(
        tmp_path):
    objects = sparse_objects_folder(tmp_path / "objects")
    result = run(BUILD_MODELS + ["--objects", objects, "--out", tmp_path / "m"])
    assert_fails_clearly(result, 1, "class 'Bus'", "radius_outlier",
                         "class_filters.Bus.radius_outlier")
    assert not (tmp_path / "m").exists() and leftovers(tmp_path) == []


def test_tall_classes_keep_their_roofs(drive, tmp_path):
    result = run(BUILD_MODELS + ["--objects", drive / "objects", "--out", tmp_path / "m"])
    assert result.status == 0, str(result)
    document = json.loads((tmp_path / "m" / "models.json").read_text())
    heights = {}
    with open(drive / "objects" / "index.csv", encoding="utf-8") as stream:
        for row in csv.DictReader(stream):
            heights.setdefault(row["label"], []).append(float(row["height_m"]))
    for label, entry in document["classes"].items():
        band_top = entry["filters"]["pass_through"]["max_z"]
        assert band_top >= np.percentile(heights[label], 95), label
    tall = [label for label in document["classes"] if max(heights[label]) > 2.5]
    assert tall, "the drive holds a bus or a truck"


def test_a_background_decision_without_a_background_class_names_the_classes(drive):
    result = run(hostile.tool("granular_ros", "evaluate_segmentation")
                 + ["--frames", drive / "frames", "--classifier", drive / "knn.yml"])
    assert_fails_clearly(result, 1, drive / "knn.yml", "no class 'Background'", "Sedan",
                         "--background")


def test_cuboid_options_of_evaluate_segmentation_are_checked(drive, tmp_path, repo_root):
    tool = hostile.tool("granular_ros", "evaluate_segmentation") + ["--frames", drive / "frames"]
    assert_fails_clearly(run(tool + ["--prior-classes", "Sedan"]), 2, "--prior-classes",
                         "--cuboids")
    model = tmp_path / "model.yaml"
    model.write_text("method: model\n")
    assert_fails_clearly(run(tool + ["--cuboids", model]), 2, "--cuboids", "model",
                         "geometric")
    cuboids = repo_root / "config" / "cuboids.yaml"
    assert_fails_clearly(run(tool + ["--cuboids", cuboids, "--prior-classes", "Sedan,Tank"]),
                         2, "Tank", "priors")


def test_background_harvest_options_without_background_are_refused(drive, tmp_path):
    result = run(EXTRACT + ["--in", drive / "frames", "--out", tmp_path / "o",
                            "--sensor-height", "2.3"])
    assert_fails_clearly(result, 2, "--sensor-height", "--background")
    result = run(EXTRACT + ["--in", drive / "frames", "--out", tmp_path / "o",
                            "--segment-objects"])
    assert_fails_clearly(result, 2, "--segment-objects", "--background")
    assert not (tmp_path / "o").exists()


def test_a_class_too_small_for_the_svm_is_named_with_its_objects_and_can_be_left_out(
        drive, tmp_path):
    """train_classifier said "nu infeasible for their classes" without naming the class."""
    objects = hostile.copy_tree(drive / "objects", tmp_path / "objects")
    donor = sorted(objects.glob("Sedan-*.pcd"))[0]
    (objects / donor.name.replace("Sedan-", "Tram-")).write_bytes(donor.read_bytes())
    config = tmp_path / "supervised.yaml"
    config.write_text("svm: {nu: [0.5]}\n")  # infeasible for 1 object against a few
    result = run(TRAIN + ["--objects", objects, "--method", "svm", "--out", tmp_path / "svm.yml",
                          "--config", config])
    assert_fails_clearly(result, 1, "class 'Tram' has 1 object(s)", "--classes")
    assert not (tmp_path / "svm.yml").exists()
    classes = sorted({path.name.split("-")[0] for path in objects.glob("*.pcd")} - {"Tram"})
    result = run(TRAIN + ["--objects", objects, "--method", "knn", "--out", tmp_path / "k.yml",
                          "--classes", ",".join(classes)])
    assert result.status == 0, str(result)
    assert f"of {len(classes)} classes" in result.output
    result = run(TRAIN + ["--objects", objects, "--method", "knn", "--out", tmp_path / "k.yml",
                          "--classes", "Sedan,Zeppelin"])
    assert_fails_clearly(result, 1, "no objects of class 'Zeppelin'")


def test_classify_supervised_into_a_path_under_a_regular_file_is_refused_before_the_work(
        drive, tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    result = run(CLASSIFY_SUPERVISED + ["--model", drive / "knn.yml", "--objects",
                                        drive / "objects", "--out",
                                        tmp_path / "notes.txt" / "knn.json"])
    assert_fails_clearly(result, 1, tmp_path / "notes.txt", "is not a folder")
    assert "objects in" not in result.output  # refused before classifying
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_a_detection_in_another_frame_than_its_cloud_is_refused_naming_both_frames(drive,
                                                                                   tmp_path):
    """Boxes in frame 'map' beside clouds in the sensor's frame were cropped as if they were in
    the sensor's: objects of the wrong points, exit 0, no word."""
    frames = hostile.copy_tree(drive / "frames", tmp_path / "frames")
    path = sorted((frames / "detections_3d").glob("[!.]*.json"))[0]
    document = json.loads(path.read_text())
    moved = document["detections"][0]
    moved["header"]["frame_id"] = "map"
    path.write_text(json.dumps(document))
    cloud_frame = document["header"]["frame_id"]
    before = hostile.snapshot(frames)
    result = run(EXTRACT + ["--in", frames, "--out", tmp_path / "objects"])
    assert_fails_clearly(result, 1, path, f"detection id {moved['id']} '{moved['label']}' is in "
                         f"frame 'map', the cloud in '{cloud_frame}'", "/tf_static")
    assert not (tmp_path / "objects").exists() and leftovers(tmp_path) == []
    assert hostile.snapshot(frames) == before


def test_a_detection_in_map_with_the_bags_tf_static_is_cropped_in_the_clouds_frame(tmp_path):
    """The transform the bag gives is used: bag_to_files moves the box from 'map' into the
    cloud's frame, and extract_objects crops the points there."""
    from test_bag_to_files import _static_transform

    rng = np.random.default_rng(2)
    # A car of 400 points 10 m ahead of the sensor, which stands at (100, 50) in 'map'.
    car = np.array([10.0, 0.0, -1.5]) + rng.uniform(-0.5, 0.5, (400, 3)) * [4.0, 1.8, 1.4]
    boxes = bagmaker.detections(0.0, ("Sedan",))
    boxes.header.frame_id = "map"
    box = boxes.detections[0]
    box.header.frame_id = "map"
    box.bbox.position.position.x, box.bbox.position.position.y = 110.0, 50.0
    box.bbox.position.position.z = -1.5
    box.bbox.size.x, box.bbox.size.y, box.bbox.size.z = 4.2, 2.0, 1.6
    tf_static = _static_transform("velodyne", "map", (-100.0, -50.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    bag = bagmaker.write(tmp_path / "in.bag", [("/tf_static", tf_static),
                                               (CLOUD_TOPIC, bagmaker.cloud(0.0, car)),
                                               (DETECTIONS_TOPIC, boxes)],
                         stamp=bagmaker.stamp(0.0))
    result = run(BAG_TO_FILES + ["--bag", bag, "--out", tmp_path / "frames"])
    assert result.status == 0, str(result)
    assert "1 detections moved into the cloud's frame with tf" in result.output, str(result)
    result = run(EXTRACT + ["--in", tmp_path / "frames", "--out", tmp_path / "objects",
                            "--n-thresh", "10"])
    assert result.status == 0, str(result)
    (row,) = list(csv.DictReader((tmp_path / "objects" / "index.csv").open()))
    assert (row["label"], row["points"]) == ("Sedan", "400")


def test_run_fleet_with_a_bag_that_vanishes_mid_run_fails_that_bag_alone(drive, tmp_path):
    """One worker: once the first bag's stages have begun, the other bag is deleted. That bag
    fails naming its path; the first is done; the ledger and report say which."""
    import shutil

    bags = tmp_path / "bags"
    bags.mkdir()
    for name in ("first", "second"):
        shutil.copyfile(drive / "drive.bag", bags / f"{name}.bag")
    out = tmp_path / "out"
    process = hostile.start(hostile.tool("granular_tools", "run_fleet") + [
        "--bags", bags / "*.bag", "--out", out, "--workers", "1", "--n-thresh", "10",
        "--methods", "ndt", "--supervised", "svm"])
    try:
        hostile.wait_for(lambda: any((out / "bags" / name / "log.txt").exists()
                                     for name in ("first", "second")), 120, "a bag's stages")
        started = "first" if (out / "bags" / "first" / "log.txt").exists() else "second"
        vanished = "second" if started == "first" else "first"
        (bags / f"{vanished}.bag").unlink()
    finally:
        result = hostile.finish(process, timeout=240)
    assert_fails_clearly(result, 1, f"{vanished} failed: objects:", bags / f"{vanished}.bag",
                         "No such file or directory")
    ledger = json.loads((out / "fleet.json").read_text())["bags"]
    assert (ledger[started]["status"], ledger[vanished]["status"]) == ("done", "failed")
    assert "## Failed bags" in (out / "index.md").read_text()
    assert leftovers(tmp_path) == [] and (bags / f"{started}.bag").exists()
