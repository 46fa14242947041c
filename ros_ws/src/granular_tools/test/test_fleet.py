"""run_fleet over short simulated drives: the same models and predictions as the pipeline and the
tools run by hand, on two local workers and on a miniature cluster that loses a worker mid-run;
a bad bag among good ones; a second run that resumes; --overwrite.

Everything on 127.0.0.1: the cluster's scheduler and workers are started here and killed at the
end, whatever happens.
"""
import contextlib
import json
import os
import pathlib
import shutil
import signal
import socket
import subprocess
import sys
import time

import pytest

import hostile

REPO = pathlib.Path(__file__).resolve().parents[4]
CONFIG = REPO / "config"
SEEDS = (1, 2, 3)
# Two classifiers keep the runs short: NDT (registration) and svm_fitness, which learns from
# NDT's results and so checks that the registrations of the train objects reach it.
OPTIONS = ["--n-thresh", "10", "--methods", "ndt", "--supervised", "svm,svm_fitness",
           "--config-dir", str(CONFIG)]
RESULT_NAMES = ("ndt_tuned", "svm", "svm_fitness")
TIMEOUT = 240  # s, a fleet run of three 3 s drives takes some 30 s on a loaded 2-core machine


def run_fleet(*arguments, timeout=TIMEOUT):
    return subprocess.run(hostile.tool("granular_tools", "run_fleet") + [str(a) for a in arguments],
                          capture_output=True, text=True, timeout=timeout, check=False)


def checked(command):
    result = subprocess.run([str(part) for part in command], capture_output=True, text=True,
                            timeout=TIMEOUT, check=False)
    assert result.returncode == 0, f"{command}: {result.stdout}\n{result.stderr}"
    return result


@pytest.fixture(scope="module")
def drives(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fleet_drives")
    for seed in SEEDS:
        checked(hostile.tool("granular_tools", "simulate_drive") + [
            "--out", folder / f"drive{seed}.bag", "--duration", "3", "--seed", seed, "--quiet"])
    return folder


@pytest.fixture(scope="module")
def local_run(drives, tmp_path_factory):
    """run_fleet over the three drives with two local worker processes."""
    out = tmp_path_factory.mktemp("fleet_local") / "results"
    result = run_fleet("--bags", drives / "drive*.bag", "--out", out, "--workers", "2", *OPTIONS)
    assert result.returncode == 0, result.stderr
    return out


def model_files(models):
    return {path.relative_to(models).as_posix(): path.read_bytes()
            for path in sorted(models.glob("*.pcd")) + sorted(models.glob("raw/*.pcd"))}


def predictions(results_file):
    with open(results_file, encoding="utf-8") as stream:
        return {os.path.basename(r["file"]): r["predictions"]
                for r in json.load(stream)["objects"]}


def bag_predictions(out):
    return {(bag.name, name): predictions(bag / "results" / name / "N10.json")
            for bag in sorted((out / "bags").iterdir()) for name in RESULT_NAMES}


def statuses(out):
    with open(out / "fleet.json", encoding="utf-8") as stream:
        return {bag: entry["status"] for bag, entry in json.load(stream)["bags"].items()}


def test_fleet_equals_the_pipeline_and_tools_by_hand(drives, local_run, tmp_path):
    objects = tmp_path / "objects"
    objects.mkdir()
    rows = []
    for seed in SEEDS:
        # run_pipeline is what pipeline.launch runs, with the same arguments.
        checked(hostile.tool("granular_tools", "run_pipeline") + [
            "--bag", drives / f"drive{seed}.bag", "--out", tmp_path / f"drive{seed}",
            "--stages", "frames,objects", "--n-thresh", "10", "--config-dir", CONFIG])
        drive_objects = tmp_path / f"drive{seed}" / "objects" / "N10"
        for pcd in drive_objects.glob("*.pcd"):
            shutil.copyfile(pcd, objects / pcd.name)
        lines = (drive_objects / "index.csv").read_text().splitlines(keepends=True)
        rows += ([lines[0]] if not rows else []) + lines[1:]
    (objects / "index.csv").write_text("".join(rows))
    models = tmp_path / "models"
    checked(hostile.BUILD_MODELS + ["--objects", objects, "--out", models,
                                    "--config", CONFIG / "models.yaml"])
    assert model_files(models) == model_files(local_run / "models")
    assert len(model_files(models)) == 14  # seven classes, filtered and raw

    def ndt(objects_folder, out):
        checked(hostile.CLASSIFY_REGISTRATION + [
            "--models", models, "--objects", objects_folder, "--method", "ndt", "--preset",
            "tuned", "--config", CONFIG / "classification.yaml", "--out", out])

    ndt(objects, tmp_path / "train_ndt.json")
    supervised = ["--config", CONFIG / "supervised.yaml"]
    checked(hostile.TRAIN + ["--objects", objects, "--method", "svm", "--out",
                             tmp_path / "svm.yml"] + supervised)
    checked(hostile.TRAIN + ["--objects", objects, "--method", "svm_fitness", "--registration",
                             tmp_path / "train_ndt.json", "--out",
                             tmp_path / "svm_fitness.yml"] + supervised)
    by_hand = {}
    for seed in SEEDS:
        drive_objects = tmp_path / f"drive{seed}" / "objects" / "N10"
        results = {name: tmp_path / f"drive{seed}-{name}.json" for name in RESULT_NAMES}
        ndt(drive_objects, results["ndt_tuned"])
        for method in ("svm", "svm_fitness"):
            checked(hostile.CLASSIFY_SUPERVISED + [
                "--model", tmp_path / f"{method}.yml", "--objects", drive_objects,
                "--out", results[method]]
                + (["--registration", results["ndt_tuned"]] if method == "svm_fitness" else []))
        for name, path in results.items():
            by_hand[(f"drive{seed}", name)] = predictions(path)
    fleet = bag_predictions(local_run)
    assert fleet == by_hand
    assert sum(len(p) for p in fleet.values()) > 3 * 100  # objects were classified
    assert statuses(local_run) == {f"drive{seed}": "done" for seed in SEEDS}
    index = (local_run / "index.md").read_text()
    assert "| drive1 | both | done |" in index
    assert (local_run / "report" / "index.md").exists()
    with open(local_run / "report" / "summary.json", encoding="utf-8") as stream:
        summary = json.load(stream)["methods"]
    assert summary["svm"]["N10"]["objects"] == sum(len(by_hand[(f"drive{s}", "svm")])
                                                   for s in SEEDS)


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@contextlib.contextmanager
def started(commands, log_folder):
    """Processes started in their own sessions, each killed with its children at the end."""
    processes = []
    try:
        for k, command in enumerate(commands):
            log = open(log_folder / f"process-{k}.log", "wb")  # noqa: SIM115 - closed below
            processes.append((subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT,
                                               start_new_session=True), log))
        yield [process for process, _ in processes]
    finally:
        for process, log in processes:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            log.close()


def busy_worker(address):
    """The name of a worker of the scheduler at `address` that is running a task; None when
    none is."""
    from distributed import Client

    with Client(address, timeout="30s") as client:
        names = {worker: info["name"] for worker, info in
                 client.scheduler_info()["workers"].items()}
        busy = sorted(names[worker] for worker, keys in client.processing().items() if keys)
    return busy[0] if busy else None


def test_cluster_loses_a_worker_and_ends_with_the_same_results(drives, local_run, tmp_path):
    dask = pathlib.Path(sys.executable).parent
    address = f"tcp://127.0.0.1:{free_port()}"
    workers = [[dask / "dask-worker", address, "--nthreads", "1", "--no-nanny",
                "--no-dashboard", "--host", "127.0.0.1", "--name", str(k)] for k in range(2)]
    out = tmp_path / "results"
    with started([[dask / "dask-scheduler", "--host", "127.0.0.1", "--port",
                   address.rsplit(":", 1)[1], "--no-dashboard"], *workers],
                 tmp_path) as (scheduler, *worker_processes):
        fleet = subprocess.Popen(hostile.tool("granular_tools", "run_fleet") + [
            "--bags", str(drives / "drive*.bag"), "--out", str(out), "--scheduler", address,
            *OPTIONS], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            # The worker to kill is one the scheduler says runs a task, once its tools started.
            deadline, victim = time.monotonic() + TIMEOUT, None
            while victim is None and time.monotonic() < deadline:
                assert fleet.poll() is None, fleet.communicate()
                if list(out.glob("bags/*/log.txt")):
                    victim = busy_worker(address)
                time.sleep(0.05)
            assert victim is not None and fleet.poll() is None, "no task to interrupt"
            killed = worker_processes[int(victim)]
            killed.kill()
            output, errors = fleet.communicate(timeout=TIMEOUT)
        finally:
            if fleet.poll() is None:
                fleet.kill()
                fleet.wait()
        assert killed.wait() == -signal.SIGKILL
        assert all(p.poll() is None for p in worker_processes if p is not killed)
        assert scheduler.poll() is None
    assert fleet.returncode == 0, errors
    assert model_files(out / "models") == model_files(local_run / "models")
    assert bag_predictions(out) == bag_predictions(local_run)


def test_a_bags_identity_is_its_index_and_a_bag_without_one_is_refused(drives, tmp_path):
    from granular_tools.fleet.identity import BagIdentityError, bag_identity, index_position

    first, second = (bag_identity(drives / f"drive{seed}.bag") for seed in SEEDS[:2])
    assert first["size"] == (drives / "drive1.bag").stat().st_size
    assert first["index_sha256"] != second["index_sha256"]
    data = bytearray((drives / "drive1.bag").read_bytes())
    position = index_position(drives / "drive1.bag")
    # The header's index_pos field, as a recorder that never closed the bag leaves it: 0.
    field = data.index(b"index_pos=") + len(b"index_pos=")
    assert int.from_bytes(data[field:field + 8], "little") == position
    data[field:field + 8] = bytes(8)
    (tmp_path / "unclosed.bag").write_bytes(data)
    with pytest.raises(BagIdentityError, match="has no index"):
        bag_identity(tmp_path / "unclosed.bag")
    (tmp_path / "text.bag").write_text("not a bag\n")
    with pytest.raises(BagIdentityError, match="not a rosbag 2.0 file"):
        bag_identity(tmp_path / "text.bag")


def write_bag_without_clouds(path):
    """A well-formed, indexed bag whose only topic is not a LiDAR's."""
    import rosbag
    import rospy
    from std_msgs.msg import String

    with rosbag.Bag(str(path), "w") as bag:
        bag.write("/chatter", String(data="no clouds here"), rospy.Time(1))


def test_bad_bags_fail_alone_then_resume_and_overwrite(drives, tmp_path):
    bags = tmp_path / "bags"
    bags.mkdir()
    for seed in SEEDS[:2]:
        shutil.copyfile(drives / f"drive{seed}.bag", bags / f"drive{seed}.bag")
    data = (drives / "drive3.bag").read_bytes()
    (bags / "cut.bag").write_bytes(data[:len(data) // 2])
    write_bag_without_clouds(bags / "no_clouds.bag")
    out = tmp_path / "results"
    arguments = ["--bags", bags / "*.bag", "--out", out, "--workers", "2", *OPTIONS]

    first = run_fleet(*arguments)
    assert first.returncode == 1, first.stderr
    assert statuses(out) == {"drive1": "done", "drive2": "done", "cut": "failed",
                             "no_clouds": "failed"}
    with open(out / "fleet.json", encoding="utf-8") as stream:
        ledger = json.load(stream)["bags"]
    assert "cut short" in ledger["cut"]["message"]
    assert "objects: bag_to_files exited with status 1" in ledger["no_clouds"]["message"]
    assert "cut failed: " in first.stderr and "no_clouds failed: " in first.stderr
    index = (out / "index.md").read_text()
    assert "## Failed bags" in index and "cut short" in index
    good = {(bag, name): out / "bags" / bag / "results" / name / "N10.json"
            for bag in ("drive1", "drive2") for name in RESULT_NAMES}
    assert all(path.exists() for path in good.values())
    written = {key: path.stat().st_mtime_ns for key, path in good.items()}

    # The same command again: the good bags are skipped, their results left as they were.
    second = run_fleet(*arguments)
    assert second.returncode == 1, second.stderr
    assert statuses(out) == {"drive1": "skipped", "drive2": "skipped", "cut": "failed",
                             "no_clouds": "failed"}
    assert {key: path.stat().st_mtime_ns for key, path in good.items()} == written

    # A repaired bag is picked up by the next run; --overwrite redoes every bag.
    (bags / "cut.bag").unlink()
    (bags / "no_clouds.bag").unlink()
    third = run_fleet(*arguments, "--overwrite")
    assert third.returncode == 0, third.stderr
    assert statuses(out) == {"drive1": "done", "drive2": "done"}
    assert all(path.stat().st_mtime_ns > written[key] for key, path in good.items())
