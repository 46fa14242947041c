"""What a fleet's workers run: each task starts the project's tools as subprocesses on folders
of the shared output, so that a worker that dies costs a retry of its task and nothing more.

A task takes a plain dict (its spec) and returns a plain dict. A tool that fails makes the task
return {"status": "failed", "message": ...} (a bad bag: retrying would fail again); anything
else raised is the engine's to retry.

Each tool runs under `setpriv --pdeathsig TERM`: when the worker process dies (killed, out of
memory), its running tool gets SIGTERM, removes its partial output and exits, instead of
running on, orphaned, holding the lock of the folder that the retry is about to write.
"""
import csv
import errno
import os
import shutil
import subprocess
import tempfile
import time

from ..bags import BagError, open_bag
from ..output import OutputFolder
from ..runners.stages import without_rosrun

LOG_NAME = "log.txt"
SCRATCH_PREFIX = "granular-fleet-"  # + the worker's process id: a bag's frames on its disk


class ToolFailed(Exception):
    """A tool that exited non-zero; the message names it and quotes its last error line."""


def _last_message(log, start, tool):
    """The tool's own message: the last line it began with its name ("tool: ..."; every tool
    says what failed that way), else the last line it wrote."""
    with open(log, "rb") as stream:
        stream.seek(start)
        lines = [line.strip() for line in stream.read().decode(errors="replace").splitlines()
                 if line.strip()]
    named = [line for line in lines if line.startswith(f"{tool}:")]
    return (named or lines or ["(no message)"])[-1]


def run_logged(command, log, threads=1):
    """Run `command` (rosrun form) with its output appended to the file `log`; ToolFailed when
    it exits non-zero. `threads`: OpenMP threads for the tool (one per worker by default, as a
    worker is one core)."""
    command = [str(part) for part in without_rosrun(command)]
    environment = dict(os.environ, OMP_NUM_THREADS=str(threads))
    with open(log, "ab") as stream:
        stream.write(("$ " + " ".join(command) + "\n").encode())
        stream.flush()
        start = stream.tell()
        status = subprocess.run(["setpriv", "--pdeathsig", "TERM", *command], stdout=stream,
                                stderr=subprocess.STDOUT, env=environment,
                                check=False).returncode
    if status != 0:
        status = 128 - status if status < 0 else status
        tool = os.path.basename(command[0])
        raise ToolFailed(f"{tool} exited with status {status}: {_last_message(log, start, tool)}")


def _option(name, value):
    return [name, str(value)] if value not in (None, "") else []


def _config(spec, name):
    """--config-style path of `name` in the spec's config folder, when it holds one."""
    folder = spec.get("config_dir")
    path = os.path.join(folder, name) if folder else None
    return path if path and os.path.isfile(path) else None


def count_objects(objects_folder):
    """{label: objects} of an objects folder's index.csv."""
    counts = {}
    with open(os.path.join(objects_folder, "index.csv"), newline="", encoding="utf-8") as stream:
        for row in csv.DictReader(stream):
            counts[row["label"]] = counts.get(row["label"], 0) + 1
    return counts


def clear_dead_scratch():
    """Remove the frames that workers killed on this machine left (their process ids are in the
    names, and no longer run)."""
    folder = tempfile.gettempdir()
    for name in os.listdir(folder):
        pid = name[len(SCRATCH_PREFIX):].split("-")[0]
        if not name.startswith(SCRATCH_PREFIX) or not pid.isdigit():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            shutil.rmtree(os.path.join(folder, name), ignore_errors=True)
        except PermissionError:
            pass  # another user's process, alive


def _failed(error, started):
    return {"status": "failed", "message": str(error), "seconds": time.monotonic() - started}


def extract_bag(spec):
    """Bag to frames, (box-free: frames to cuboids,) frames to objects at every threshold, into
    spec["folder"]: {"status": "done", "objects": {"N<t>": count}, "classes": {label: count at
    N<classes_at>, the models' threshold}, "drive_seconds", "seconds"}."""
    started = time.monotonic()
    folder = spec["folder"]
    os.makedirs(folder, exist_ok=True)
    log = os.path.join(folder, LOG_NAME)
    # The frames are the bulk of the writing (a third of the bag's bytes) and only this task
    # reads them: on the worker's own disk unless asked for, not on the shared storage.
    scratch = None
    if not spec.get("keep_frames"):
        clear_dead_scratch()
        scratch = tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-")
    frames = os.path.join(scratch or folder, "frames")
    cuboids, objects = os.path.join(folder, "cuboids"), os.path.join(folder, "objects")
    segment = spec["boxes"] == "segment"
    try:
        run_logged(["rosrun", "granular_tools", "bag_to_files", "--bag", spec["bag"], "--out",
                    frames, "--overwrite", "--quiet", *_option("--config", _config(
                        spec, "bag_to_files.yaml"))] + (["--clouds-only"] if segment else []),
                   log, spec["threads"])
        if segment:
            run_logged(["rosrun", "granular_ros", "fit_cuboids", "--frames", frames, "--out",
                        cuboids, "--boxes", "segment", "--overwrite",
                        *_option("--config", _config(spec, "cuboids.yaml")),
                        *_option("--ground-config", _config(spec, "ground.yaml")),
                        *_option("--segmentation-config", _config(spec, "segmentation.yaml")),
                        *_option("--sensor", spec.get("sensor")),
                        *_option("--sensor-height", spec.get("sensor_height")),
                        *_option("--azimuth-step", spec.get("azimuth_step")),
                        *_option("--prior-classes", spec.get("prior_classes"))],
                       log, spec["threads"])
        run_logged(["rosrun", "granular_ros", "extract_objects", "--in", frames, "--out",
                    objects, "--n-thresh", ",".join(map(str, spec["thresholds"])),
                    "--threshold-folders", "--overwrite",
                    *_option("--boxes", cuboids if segment else None),
                    *_option("--config", _config(spec, "extraction.yaml"))],
                   log, spec["threads"])
        with open_bag(spec["bag"]) as bag:
            drive_seconds = bag.get_end_time() - bag.get_start_time()
    except (ToolFailed, BagError) as error:
        return _failed(error, started)
    finally:
        if scratch:
            shutil.rmtree(scratch, ignore_errors=True)
    counts = {f"N{t}": sum(count_objects(os.path.join(objects, f"N{t}")).values())
              for t in spec["thresholds"]}
    return {"status": "done", "objects": counts,
            "classes": count_objects(os.path.join(objects, f"N{spec['classes_at']}"))
            if spec["classes_at"] in spec["thresholds"] else {},
            "drive_seconds": drive_seconds,
            "seconds": time.monotonic() - started}


def _link(source, target):
    """A hard link where the file system allows one (a class's objects are gathered without
    copying them), a copy otherwise."""
    try:
        os.link(source, target)
    except OSError as error:
        if error.errno not in (errno.EXDEV, errno.EPERM, errno.EMLINK, errno.ENOTSUP):
            raise
        shutil.copyfile(source, target)


def capped(rows, cap):
    """At most `cap` of `rows` (sorted by file name, so by time within a drive), evenly spaced
    over them so that every drive keeps its share; all of them when there are no more."""
    if not cap or len(rows) <= cap:
        return rows
    return [rows[k * len(rows) // cap] for k in range(cap)]


def gather_objects(sources, label, cap, target, tool="run_fleet"):
    """The objects of class `label` (every class when None) in the objects folders `sources`
    (each with an index.csv), at most `cap` a class, linked into the output folder `target`
    with one index.csv. Two drives holding an object of the same file name are refused."""
    header, rows, from_source = None, [], {}
    for source in sources:
        with open(os.path.join(source, "index.csv"), newline="", encoding="utf-8") as stream:
            reader = csv.reader(stream)
            header = next(reader)
            label_column, file_column = header.index("label"), header.index("file")
            for row in reader:
                if label is not None and row[label_column] != label:
                    continue
                if row[file_column] in from_source:
                    raise ToolFailed(f"{row[file_column]} is an object of both "
                                     f"{from_source[row[file_column]]} and {source}: the same "
                                     "drive given twice?")
                from_source[row[file_column]] = source
                rows.append(row)
    if header is None:
        raise ToolFailed("no objects folders to gather")
    by_class = {}
    for row in sorted(rows, key=lambda r: r[header.index("file")]):
        by_class.setdefault(row[header.index("label")], []).append(row)
    kept = [row for name in sorted(by_class) for row in capped(by_class[name], cap)]
    with OutputFolder(target, tool, overwrite=True) as folder:
        for row in kept:
            name = row[header.index("file")]
            _link(os.path.join(from_source[name], name), os.path.join(folder.staging, name))
        with open(os.path.join(folder.staging, "index.csv"), "w", newline="",
                  encoding="utf-8") as stream:
            writer = csv.writer(stream, lineterminator="\n")
            writer.writerow(header)
            writer.writerows(kept)
        folder.commit()
    return {label_name: len(capped(group, cap)) for label_name, group in by_class.items()}


def build_class_model(spec):
    """The reduce of one class: its objects from every train drive gathered into one folder
    (capped), then build_models on them: {"status", "objects", "seconds"}."""
    started = time.monotonic()
    os.makedirs(spec["work"], exist_ok=True)
    log = os.path.join(spec["work"], LOG_NAME)
    objects = os.path.join(spec["work"], "objects")
    try:
        kept = gather_objects(spec["sources"], spec["label"], spec["cap"], objects)
        run_logged(["rosrun", "granular_ros", "build_models", "--objects", objects, "--out",
                    spec["out"], "--classes", spec["label"], "--method", spec["method"],
                    "--overwrite", *_option("--config", _config(spec, "models.yaml"))],
                   log, spec["threads"])
    except ToolFailed as error:
        return _failed(error, started)
    return {"status": "done", "objects": kept.get(spec["label"], 0),
            "seconds": time.monotonic() - started}


def run_commands(spec):
    """Tools run one after the other, their output into spec["log"], after making the folders
    spec["folders"]: a classifier's training and the registrations it learns from, or a bag's
    objects through every classifier against the broadcast models (svm_fitness after the
    registrations it reads). Returns {"status", "seconds"}."""
    started = time.monotonic()
    for folder in [os.path.dirname(spec["log"]), *spec.get("folders", ())]:
        os.makedirs(folder, exist_ok=True)
    try:
        for command in spec["commands"]:
            run_logged(command, spec["log"], spec["threads"])
    except ToolFailed as error:
        return _failed(error, started)
    return {"status": "done", "seconds": time.monotonic() - started}

