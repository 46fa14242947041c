"""Hostile inputs, output safety: a tool never deletes a user's files, never leaves half-written
output under a final name (full disk, signals, a dead run's staging), and refuses a second run
into a folder that one is writing. Each case runs the built tool as a user would."""
import json
import os
import pathlib
import shutil
import signal

import pytest

import hostile
from hostile import (assert_fails_clearly, leftovers, run, snapshot, EXTRACT, BUILD_MODELS, TRAIN,
                     CLASSIFY_REGISTRATION, CLASSIFY_SUPERVISED, BAG_TO_FILES, SIMULATE, RENDER,
                     MAKE_REPORT, RUN_PIPELINE)
from granular_tools import output


def folder_writers(drive):
    """Every tool that writes a folder, with the options that make it write `out`."""
    return {
        "bag_to_files": lambda out: BAG_TO_FILES + ["--bag", drive / "drive.bag", "--out", out,
                                                    "--quiet"],
        "extract_objects": lambda out: EXTRACT + ["--in", drive / "frames", "--out", out],
        "build_models": lambda out: BUILD_MODELS + ["--objects", drive / "objects", "--out", out],
        "render_models": lambda out: RENDER + ["--models", drive / "models", "--out", out],
        "run_pipeline": lambda out: RUN_PIPELINE + ["--bag", drive / "drive.bag", "--out", out,
                                                    "--n-thresh", "10"],
    }


WRITERS = ["bag_to_files", "extract_objects", "build_models", "render_models", "run_pipeline"]


# --- --overwrite never deletes a user's files -----------------------------------------------

@pytest.mark.parametrize("writer", WRITERS)
def test_overwrite_refuses_a_folder_of_the_users_files_and_leaves_it_untouched(
        drive, tmp_path, writer):
    mine = hostile.user_folder(tmp_path / "mine")
    before = snapshot(mine)
    result = run(folder_writers(drive)[writer](mine) + ["--overwrite"])
    assert result.status in (1, 2), str(result)
    assert_fails_clearly(result, result.status, mine, "no granular tool wrote")
    assert snapshot(mine) == before
    assert leftovers(tmp_path) == []


def frames_readers(frames):
    """Tools that read a frames folder and write a folder, with the options that make them
    write `out`."""
    simulated = ["--sensor-height", "2.3", "--azimuth-step", "1"]
    return {
        "extract_objects": lambda out: EXTRACT + ["--in", frames, "--out", out],
        "fit_cuboids": lambda out: hostile.tool("granular_ros", "fit_cuboids") + [
            "--frames", frames, "--out", out] + simulated,
        "evaluate_segmentation": lambda out: hostile.tool(
            "granular_ros", "evaluate_segmentation") + ["--frames", frames, "--save", out]
        + simulated,
        "bag_to_files": lambda out: BAG_TO_FILES + ["--bag", frames / "drive.bag", "--out", out,
                                                    "--quiet"],
    }


@pytest.mark.parametrize("reader", ["extract_objects", "fit_cuboids", "evaluate_segmentation",
                                    "bag_to_files"])
def test_overwrite_never_replaces_the_input_it_reads(drive, tmp_path, reader):
    # The input itself, or a granular folder holding it: before, each was replaced, exit 0.
    run_folder = tmp_path / "run"
    frames = run_folder / "frames"
    frames.parent.mkdir()
    shutil.copytree(drive / "frames", frames)
    shutil.copy(drive / "drive.bag", frames / "drive.bag")
    (run_folder / output.MANIFEST).write_text('{"tool": "run_pipeline"}')
    before = snapshot(run_folder)
    for out in (frames, run_folder):
        result = run(frames_readers(frames)[reader](out) + ["--overwrite"])
        assert_fails_clearly(result, 1, "the output", "input")
        assert snapshot(run_folder) == before
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("writer", WRITERS)
def test_a_folder_of_earlier_results_is_replaced_only_with_overwrite(drive, tmp_path, writer):
    out = tmp_path / "out"
    assert run(folder_writers(drive)[writer](out)).status == 0
    before = snapshot(out)
    refused = run(folder_writers(drive)[writer](out))
    assert refused.status in (1, 2)
    assert_fails_clearly(refused, refused.status, out, "--overwrite")
    assert snapshot(out) == before
    replaced = run(folder_writers(drive)[writer](out) + ["--overwrite"])
    assert replaced.status == 0, str(replaced)
    assert (out / output.MANIFEST).is_file()


def test_through_roslaunch_the_refusal_says_overwrite_true(drive, tmp_path):
    out = tmp_path / "objects"
    assert run(EXTRACT + ["--in", drive / "frames", "--out", out]).status == 0
    env = dict(os.environ, GRANULAR_OVERWRITE_HINT="overwrite:=true")
    result = run(EXTRACT + ["--in", drive / "frames", "--out", out], env=env)
    assert_fails_clearly(result, 1, "overwrite:=true")
    assert "--overwrite" not in result.stderr


def test_an_output_that_is_a_regular_file_is_refused_and_kept(drive, tmp_path):
    target = tmp_path / "results.txt"
    target.write_text("keep me\n")
    result = run(EXTRACT + ["--in", drive / "frames", "--out", target, "--overwrite"])
    assert_fails_clearly(result, 1, target, "not a folder")
    assert target.read_text() == "keep me\n"


def test_models_into_the_objects_folder_itself_is_refused(drive, tmp_path):
    objects = hostile.copy_tree(drive / "objects", tmp_path / "objects")
    before = snapshot(objects)
    result = run(BUILD_MODELS + ["--objects", objects, "--out", objects, "--overwrite"])
    assert_fails_clearly(result, 1, objects)
    assert snapshot(objects) == before


def test_python_tool_into_a_folder_under_a_regular_file_names_the_path(drive, tmp_path):
    blocker = tmp_path / "plain_file"
    blocker.write_text("x")
    result = run(BAG_TO_FILES + ["--bag", drive / "drive.bag", "--out", blocker / "frames"])
    assert_fails_clearly(result, 1, blocker)
    assert blocker.read_text() == "x"


# --- a full disk: an error naming the path, nothing under the final name ------------------

def test_train_classifier_on_a_full_disk_fails_and_leaves_no_model(drive, tmp_path):
    with hostile.full_disk(tmp_path / "disk") as disk:
        result = run(TRAIN + ["--objects", drive / "objects", "--method", "knn",
                              "--out", disk / "knn.yml"])
        assert_fails_clearly(result, 1, disk / "knn.yml")
        assert hostile.files_on(disk) == []


@pytest.mark.parametrize("writer", ["bag_to_files", "extract_objects", "build_models",
                                    "render_models"])
def test_a_folder_writer_on_a_full_disk_fails_and_leaves_nothing(drive, tmp_path, writer):
    with hostile.full_disk(tmp_path / "disk") as disk:
        result = run(folder_writers(drive)[writer](disk / "out"))
        assert_fails_clearly(result, 1, disk)
        assert hostile.files_on(disk) == []


FLEET = hostile.tool("granular_tools", "run_fleet")
FLEET_OPTIONS = ["--workers", "1", "--n-thresh", "10", "--methods", "ndt", "--supervised", "svm"]


def test_run_fleet_into_a_full_disk_fails_and_leaves_nothing(drive, tmp_path):
    with hostile.full_disk(tmp_path / "disk") as disk:
        result = run(FLEET + ["--bags", drive / "drive.bag", "--out", disk / "out"]
                     + FLEET_OPTIONS)
        assert_fails_clearly(result, 1, disk / "out", "No space left on device")
        assert hostile.files_on(disk) == []


def test_run_fleet_filling_the_disk_mid_run_names_the_bag_and_keeps_the_users_files(
        drive, tmp_path):
    """Room for the fleet's ledger, not for a bag's objects: the bag fails naming the full
    disk, the ledger and report say so, no staging is left, the user's files are intact."""
    with hostile.full_disk(tmp_path / "disk", size="1m") as disk:
        os.truncate(disk / "filler", 400 * 1024)  # some 600 KB free
        mine = hostile.user_folder(disk / "mine")
        before = snapshot(mine)
        result = run(FLEET + ["--bags", drive / "drive.bag", "--out", disk / "out"]
                     + FLEET_OPTIONS)
        assert_fails_clearly(result, 1, "drive failed: objects:", "No space left on device")
        ledger = json.loads((disk / "out" / "fleet.json").read_text())
        assert ledger["bags"]["drive"]["status"] == "failed"
        assert "No space left on device" in ledger["bags"]["drive"]["message"]
        assert "## Failed bags" in (disk / "out" / "index.md").read_text()
        assert leftovers(disk) == [] and snapshot(mine) == before


@pytest.mark.parametrize("classifier", ["registration", "supervised"])
def test_classification_results_on_a_full_disk_fail_and_leave_nothing(
        drive, tmp_path, classifier):
    with hostile.full_disk(tmp_path / "disk") as disk:
        out = disk / "results.json"
        if classifier == "registration":
            command = CLASSIFY_REGISTRATION + ["--models", drive / "models", "--objects",
                                               drive / "objects", "--method", "ndt",
                                               "--out", out]
        else:
            command = CLASSIFY_SUPERVISED + ["--model", drive / "knn.yml", "--objects",
                                             drive / "objects", "--out", out]
        result = run(command)
        assert_fails_clearly(result, 1, out)
        assert hostile.files_on(disk) == []


def test_simulate_drive_on_a_full_disk_fails_and_leaves_no_bag(tmp_path):
    with hostile.full_disk(tmp_path / "disk") as disk:
        result = run(SIMULATE + ["--out", disk / "drive.bag", "--duration", "2", "--quiet"])
        assert_fails_clearly(result, 1, disk / "drive.bag")
        assert hostile.files_on(disk) == []


def test_make_report_on_a_full_disk_fails_and_leaves_nothing(drive, tmp_path):
    results = tmp_path / "results"
    (results / "knn").mkdir(parents=True)
    classified = run(CLASSIFY_SUPERVISED + ["--model", drive / "knn.yml", "--objects",
                                            drive / "objects", "--out",
                                            results / "knn" / "N10.json"])
    assert classified.status == 0, str(classified)
    with hostile.full_disk(tmp_path / "disk", size="64k") as disk:
        result = run(MAKE_REPORT + ["--results", results, "--out", disk / "report"])
        assert_fails_clearly(result, 1, disk)
        assert hostile.files_on(disk) == []


# --- one run at a time into a folder ------------------------------------------------------

@pytest.mark.parametrize("writer", ["bag_to_files", "extract_objects", "build_models"])
def test_a_second_run_into_a_folder_being_written_is_refused(drive, tmp_path, writer):
    out = tmp_path / "out"
    # The first run: this process holds the folder's lock as a running tool would; C++ and
    # Python tools share the lock file.
    with output.OutputFolder(str(out), "first_run"):
        result = run(folder_writers(drive)[writer](out))
        assert_fails_clearly(result, 1, out, str(os.getpid()))
    assert not out.exists()
    assert leftovers(tmp_path) == []


# --- signals: stop, remove the staging, one line, 130 / 143 --------------------------------

def staging_exists(parent, name):
    return lambda: any(entry.startswith(f".{name}.partial-") for entry in os.listdir(parent))


@pytest.fixture(scope="module")
def many_frames(drive, tmp_path_factory):
    """A frames folder big enough that extraction runs for a while: the drive's frames, copied
    under many stamps."""
    frames = tmp_path_factory.mktemp("many") / "frames"
    hostile.copy_tree(drive / "frames", frames)
    clouds = sorted((frames / "pcd").iterdir())
    for copy in range(1, 40):
        for cloud in clouds:
            stamp = str(int(cloud.stem) + copy)
            (frames / "pcd" / f"{stamp}.pcd").write_bytes(cloud.read_bytes())
            (frames / "detections_3d" / f"{stamp}.json").write_bytes(
                (frames / "detections_3d" / f"{cloud.stem}.json").read_bytes())
    return frames


@pytest.mark.parametrize("signum,status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_extract_objects_stopped_by_a_signal_removes_its_staging(
        many_frames, tmp_path, signum, status):
    out = tmp_path / "objects"
    process = hostile.start(EXTRACT + ["--in", many_frames, "--out", out,
                                       "--n-thresh", "10,50,100"])
    result = hostile.interrupt_when(process, staging_exists(tmp_path, "objects"), signum,
                                    "the staging folder")
    assert_fails_clearly(result, status, "interrupted")
    assert not out.exists()
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("signum,status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_bag_to_files_stopped_by_a_signal_removes_its_staging(drive, tmp_path, signum, status):
    bag = drive / "drive.bag"
    out = tmp_path / "frames"
    process = hostile.start(BAG_TO_FILES + ["--bag", bag, "--out", out])
    result = hostile.interrupt_when(process, staging_exists(tmp_path, "frames"), signum,
                                    "the staging folder")
    # A run that finished before the signal arrived is not what this case is about.
    if result.status == 0:
        pytest.skip("bag_to_files finished before the signal")
    assert_fails_clearly(result, status, "interrupted")
    assert not out.exists()
    assert leftovers(tmp_path) == []


def test_simulate_drive_stopped_by_sigterm_leaves_no_bag(tmp_path):
    bag = tmp_path / "drive.bag"
    process = hostile.start(SIMULATE + ["--out", bag, "--duration", "60"])
    result = hostile.interrupt_when(process, staging_exists(tmp_path, "drive.bag"),
                                    signal.SIGTERM, "the partial bag")
    assert_fails_clearly(result, 143, "interrupted")
    assert not bag.exists()
    assert leftovers(tmp_path) == []


def test_run_pipeline_stopped_by_sigint_stops_its_stage_and_marks_the_run(many_frames,
                                                                           drive, tmp_path):
    out = tmp_path / "run"
    process = hostile.start(RUN_PIPELINE + ["--bag", drive / "drive.bag", "--out", out,
                                            "--n-thresh", "10"])
    result = hostile.interrupt_when(process, lambda: (out / "frames").is_dir(),
                                    signal.SIGINT, "the frames stage")
    assert_fails_clearly(result, 130, "interrupted")
    assert leftovers(tmp_path) == []
    assert "interrupted" in (out / "FAILED").read_text()


def test_a_later_run_clears_the_staging_a_dead_run_left(drive, tmp_path):
    out = tmp_path / "objects"
    dead_pid = 4194303  # above any pid this kernel hands out (pid_max is at most 2^22)
    stale = tmp_path / f".objects.partial-{dead_pid}"
    (stale / "N10").mkdir(parents=True)
    (stale / "N10" / "Sedan-1-1.pcd").write_bytes(b"half")
    result = run(EXTRACT + ["--in", drive / "frames", "--out", out])
    assert result.status == 0, str(result)
    assert not stale.exists()
    assert str(stale) in result.output
    assert leftovers(tmp_path) == []


def test_the_staging_of_a_live_run_is_not_cleared(drive, tmp_path):
    out = tmp_path / "objects"
    live = tmp_path / f".objects.partial-{os.getppid()}"
    live.mkdir()
    result = run(EXTRACT + ["--in", drive / "frames", "--out", out])
    assert result.status == 0, str(result)
    assert live.is_dir()


def test_a_result_set_aside_by_a_run_killed_mid_swap_is_put_back(drive, tmp_path):
    out = tmp_path / "objects"
    assert run(EXTRACT + ["--in", drive / "frames", "--out", out]).status == 0
    before = snapshot(out)
    set_aside = tmp_path / ".objects.previous-4194303"
    out.rename(set_aside)
    result = run(BUILD_MODELS + ["--objects", drive / "objects", "--out", tmp_path / "models"])
    assert result.status == 0
    # Only a run into that folder looks after it.
    assert set_aside.exists()
    result = run(EXTRACT + ["--in", drive / "frames", "--out", out])
    assert_fails_clearly(result, 1, "--overwrite")
    assert snapshot(out) == before
    assert leftovers(tmp_path) == []
    assert pathlib.Path(out).is_dir()
