"""run_fleet: the pipeline over many bags as a map, a reduce and a map again, on Dask
distributed (an embedded LocalCluster, or a cluster the user started: docs/fleet.md). (Over 400
lines: the ledger, the progress line and the Fleet's callbacks share one run's state, and main
checks the config they read; the folders, tasks and report are plan.py, tasks.py, report.py.)

1. per bag: bag to frames, frames to objects at every N_thresh (box-free: cuboids first);
2. per class, over the train drives (--train, or the bags themselves): the class's objects
   gathered into one task, capped, and build_models on them; then the supervised classifiers
   trained on the same objects;
3. per bag: its objects through every classifier against those models;
then one report over the fleet. Folders: plan.py. A bag that fails fails alone; fleet.json
keeps each bag's status and keys, so that the same command again does only what is not done.
"""
import argparse
import glob
import json
import logging
import os
import shutil
import sys
import time

from ..output import (OutputError, OutputFolder, claimed_folder, resolve, run_main,
                      write_atomically)
from ..runners.stages import (StageError, add_sensor_options, bad_argument, positive_number,
                              sensor_option)
from . import plan, report, tasks
from .identity import BagIdentityError, bag_identity

LEDGER = "fleet.json"
# A task that raised (not a tool that failed: that is the bag's own fault) runs again this many
# times; a task whose worker died is handed to another worker by the scheduler itself.
RETRIES = 2


class Ledger:
    """OUT/fleet.json: per bag its status and keys, the models' key; written atomically at most
    every SAVE_INTERVAL seconds as tasks finish, and at the end: a stopped run resumes from
    there, redoing at most that many seconds of work, and a fleet of 60,000 bags (some 50 MB of
    fleet.json) is not rewritten for each of them."""

    SAVE_INTERVAL = 5.0  # s

    def __init__(self, path, fresh):
        self.path, self.saved = path, 0.0
        self.data = {"bags": {}, "models": {}}
        if not fresh and os.path.exists(path):
            try:
                with open(path, encoding="utf-8") as stream:
                    self.data = json.load(stream)
                self.data["bags"], self.data["models"]  # noqa: B018 - presence check
            except (OSError, ValueError, KeyError, TypeError) as error:
                raise bad_argument(f"{path}: not a fleet.json run_fleet wrote ({error}); "
                                   "--overwrite starts afresh") from error

    def bag(self, bag_id):
        return self.data["bags"].setdefault(bag_id, {})

    def save(self, soon=False):
        """Write fleet.json; with `soon`, only when the last write is SAVE_INTERVAL old."""
        if soon and time.monotonic() - self.saved < self.SAVE_INTERVAL:
            return
        self.saved = time.monotonic()
        write_atomically(self.path, (json.dumps(self.data, indent=1, sort_keys=True) + "\n")
                         .encode(), "fleet.json")


class Progress:
    """One line on stderr: bags finished, objects per second, time left (redrawn on a terminal,
    every 10 s in a log)."""

    def __init__(self, bags):
        self.bags, self.started, self.last = bags, time.monotonic(), 0.0
        self.interactive = sys.stderr.isatty()

    def __call__(self, finished, failed, objects, force=False):
        now = time.monotonic()
        if not force and now - self.last < (0.5 if self.interactive else 10.0):
            return
        self.last = now
        elapsed = now - self.started
        left = (f", about {elapsed / finished * (self.bags - finished) / 60:.1f} min left"
                if 0 < finished < self.bags else "")
        line = (f"run_fleet: {finished}/{self.bags} bags ({failed} failed), "
                f"{objects / max(elapsed, 1e-9):.0f} objects/s{left}")
        sys.stderr.write(("\r" + line + "\x1b[K") if self.interactive else line + "\n")
        sys.stderr.flush()

    def finish(self):
        if self.interactive:
            sys.stderr.write("\n")


class Fleet:
    """The run's state machine: tasks are submitted as what they need is done."""

    def __init__(self, config, client, ledger, overwrite):
        from distributed import as_completed

        self.config, self.client, self.ledger, self.overwrite = config, client, ledger, overwrite
        self.ids = plan.bag_ids(config.bags + config.train)
        train = config.train or config.bags
        self.roles = {}
        for path in config.bags + config.train:
            self.roles[self.ids[path]] = ("both" if not config.train else
                                          "test" if path in config.bags else "train")
        self.paths = {self.ids[path]: path for path in self.ids}
        self.train_waiting = {self.ids[path] for path in train}
        self.classes_waiting, self.training_waiting = set(), set()
        self.models_digest, self.models_failed = None, None
        self.finished, self.failed, self.objects = set(), set(), 0
        self.pending, self.handlers = as_completed(), {}
        self.progress = Progress(len(self.ids))
        ledger.data["options"] = {"bags": config.bags, "train": config.train,
                                  "thresholds": config.thresholds, "methods": config.methods,
                                  "preset": config.preset, "supervised": config.supervised,
                                  "boxes": config.boxes, "class_cap": config.class_cap}

    def folder(self, bag_id):
        return self.config.folder("train" if self.roles[bag_id] == "train" else "bags", bag_id)

    def submit(self, function, spec, on_done):
        future = self.client.submit(function, spec, pure=False, retries=RETRIES)
        self.handlers[future] = on_done
        self.pending.add(future)

    # Bags ending.
    def _finish(self, bag_id, status, message=None):
        entry = self.ledger.bag(bag_id)
        entry["status"] = status
        entry.pop("message", None)
        if message:
            entry["message"] = message
            self.failed.add(bag_id)
        self.finished.add(bag_id)

    def _fail(self, bag_id, message):
        self._finish(bag_id, "failed", message)
        self.train_waiting.discard(bag_id)

    # 1. per bag: objects.
    def start(self):
        for bag_id, path in sorted(self.paths.items()):
            entry = self.ledger.bag(bag_id)
            entry.update(bag=path, role=self.roles[bag_id])
            entry["ran"] = []  # the stages this run did (the others were done before)
            try:
                identity = bag_identity(path)
            except BagIdentityError as error:
                self._fail(bag_id, str(error))
                continue
            entry["identity"] = identity
            key = self.config.extraction_key(identity, self.roles[bag_id] == "train")
            if (not self.overwrite and entry.get("extracted") == key
                    and os.path.isdir(os.path.join(self.folder(bag_id), "objects"))):
                self._extracted(bag_id)
                continue
            entry["extracted"] = None
            spec = self.config.extraction_spec(path, self.folder(bag_id),
                                               self.roles[bag_id] == "train")
            self.submit(tasks.extract_bag, spec,
                        lambda result, bag_id=bag_id, key=key: self._on_extracted(
                            bag_id, key, result))
        self._maybe_build_models()

    def _on_extracted(self, bag_id, key, result):
        entry = self.ledger.bag(bag_id)
        if result["status"] != "done":
            self._fail(bag_id, f"objects: {result['message']}")
        else:
            entry.update(extracted=key, objects=result["objects"], classes=result["classes"],
                         drive_seconds=result["drive_seconds"],
                         extraction_seconds=result["seconds"])
            entry["ran"].append("objects")
            self.objects += sum(result["objects"].values())
            self._extracted(bag_id)
        self._maybe_build_models()

    def _extracted(self, bag_id):
        if self.roles[bag_id] == "train":
            self._finish(bag_id, "done" if self.ledger.bag(bag_id)["ran"] else "skipped")
        self.train_waiting.discard(bag_id)
        if self.roles[bag_id] != "train" and self.models_digest:
            self._classify(bag_id)

    # 2. per class: models; then the classifiers.
    def _learners(self):
        return [b for b in sorted(self.paths) if self.roles[b] != "test"
                and b not in self.failed]

    def _maybe_build_models(self):
        if self.train_waiting or self.classes_waiting or self.training_waiting \
                or self.models_digest or self.models_failed:
            return
        learners = self._learners()
        if not learners:
            return self._models_failed("no train drive gave objects")
        models = self.ledger.data["models"]
        key = self.config.models_key([self.ledger.bag(b)["extracted"] for b in learners])
        if (not self.overwrite and models.get("key") == key and models.get("status") == "done"
                and os.path.isdir(self.config.models)):
            return self._models_ready(models["digest"])
        self.ledger.data["models"] = {"key": key, "status": "building"}
        classes = sorted({label for b in learners
                          for label, count in self.ledger.bag(b)["classes"].items() if count})
        if not classes:
            return self._models_failed(f"the train drives have no objects of "
                                       f"{self.config.models_from} points or more")
        sources = [os.path.join(self.folder(b), "objects", f"N{self.config.models_from}")
                   for b in learners]
        self.classes_waiting = set(classes)
        self.class_results = {}
        for label in classes:
            self.submit(tasks.build_class_model, self.config.class_spec(label, sources),
                        lambda result, label=label: self._on_class_built(label, result))

    def _on_class_built(self, label, result):
        self.classes_waiting.discard(label)
        self.class_results[label] = result
        if self.classes_waiting:
            return
        failed = [f"{name}: {r['message']}" for name, r in sorted(self.class_results.items())
                  if r["status"] != "done"]
        if failed:
            return self._models_failed("class models: " + "; ".join(failed))
        classes = sorted(self.class_results)
        assemble_models(self.config, classes)
        tasks.gather_objects([os.path.join(self.config.folder("reduce", c), "objects")
                              for c in classes], None, None, self.config.train_objects)
        self.ledger.data["models"]["classes"] = {c: r["objects"]
                                                 for c, r in self.class_results.items()}
        specs = self.config.training_specs()
        self.training_waiting = {method for method, _ in specs}
        self.training_results = {}
        for method, spec in specs:
            self.submit(tasks.run_commands, spec,
                        lambda result, method=method: self._on_trained(method, result))
        if not specs:
            self._trained()

    def _on_trained(self, method, result):
        self.training_waiting.discard(method)
        self.training_results[method] = result
        if not self.training_waiting:
            self._trained()

    def _trained(self):
        failed = [f"{method}: {r['message']}" for method, r in
                  sorted(self.training_results.items()) if r["status"] != "done"]
        if failed:
            return self._models_failed("training: " + "; ".join(failed))
        digest = plan.files_digest(self.config.models, self.config.classifiers)
        self.ledger.data["models"].update(status="done", digest=digest)
        self._models_ready(digest)

    def _models_failed(self, message):
        self.models_failed = message
        self.ledger.data["models"].update(status="failed", message=message)
        for bag_id in sorted(self.paths):
            if self.roles[bag_id] != "train" and bag_id not in self.finished:
                self._fail(bag_id, f"not classified: {message}")

    def _models_ready(self, digest):
        self.models_digest = digest
        for bag_id in sorted(self.paths):
            if (self.roles[bag_id] != "train" and bag_id not in self.finished
                    and self.ledger.bag(bag_id).get("extracted")):
                self._classify(bag_id)

    # 3. per bag: classification.
    def _classify(self, bag_id):
        entry = self.ledger.bag(bag_id)
        key = self.config.classification_key(entry["extracted"], self.models_digest)
        if not self.overwrite and entry.get("classified") == key:
            self._finish(bag_id, "done" if entry["ran"] else "skipped")
            return
        entry["classified"] = None
        self.submit(tasks.run_commands, self.config.classification_spec(self.folder(bag_id)),
                    lambda result: self._on_classified(bag_id, key, result))

    def _on_classified(self, bag_id, key, result):
        entry = self.ledger.bag(bag_id)
        if result["status"] != "done":
            return self._fail(bag_id, f"classification: {result['message']}")
        entry.update(classified=key, classification_seconds=result["seconds"])
        entry["ran"].append("classification")
        self._finish(bag_id, "done")

    def run(self):
        try:
            self.start()
            self.ledger.save()
            for future in self.pending:
                on_done = self.handlers.pop(future)
                try:
                    result = future.result()
                except Exception as error:  # noqa: BLE001 - a task that failed every retry
                    result = {"status": "failed",
                              "message": f"{type(error).__name__}: {error}"}
                on_done(result)
                self.ledger.save(soon=True)
                self.progress(len(self.finished), len(self.failed), self.objects)
        finally:
            self.ledger.save()  # what finished so far, however the run ends
        self.progress(len(self.finished), len(self.failed), self.objects, force=True)
        self.progress.finish()


def assemble_models(config, classes):
    """OUT/models from each class's build: <Class>.pcd, raw/<Class>.pcd and one models.json."""
    with OutputFolder(config.models, "run_fleet", overwrite=True) as folder:
        os.mkdir(os.path.join(folder.staging, "raw"))
        merged = None
        for label in classes:
            built = os.path.join(config.folder("reduce", label), "models")
            shutil.copyfile(os.path.join(built, f"{label}.pcd"),
                            os.path.join(folder.staging, f"{label}.pcd"))
            shutil.copyfile(os.path.join(built, "raw", f"{label}.pcd"),
                            os.path.join(folder.staging, "raw", f"{label}.pcd"))
            with open(os.path.join(built, "models.json"), encoding="utf-8") as stream:
                summary = json.load(stream)
            if merged is None:
                merged = dict(summary, classes={}, warnings=[],
                              objects_folder=config.train_objects)
            merged["classes"].update(summary["classes"])
            merged["warnings"] += summary.get("warnings", [])
        with open(os.path.join(folder.staging, "models.json"), "w", encoding="utf-8") as stream:
            json.dump(merged, stream, indent=2)
        folder.commit()


def expand_bags(patterns, relative_to, what):
    """The bags named by comma-separated paths or glob patterns, each once, in order."""
    bags = []
    for pattern in (p.strip() for text in patterns for p in text.split(",")):
        if not pattern:
            continue
        pattern = resolve(pattern, relative_to)
        matched = sorted(glob.glob(pattern)) if glob.has_magic(pattern) else [pattern]
        if not matched:
            raise bad_argument(f"{what} {pattern} matches no file")
        for path in matched:
            if not os.path.isfile(path):
                raise bad_argument(f"{what} {path} not found")
            if path not in bags:
                bags.append(path)
    return bags


def open_client(scheduler, workers):
    """(client, cluster): connected to `scheduler`, or to a LocalCluster of `workers` processes
    of one thread (one core each: every tool a task runs is given one OpenMP thread)."""
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="30s"), None
        except (OSError, TimeoutError, ValueError) as error:
            raise StageError("scheduler", f"cannot reach the scheduler {scheduler}: {error}") \
                from error
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=None, silence_logs=logging.ERROR)
    return Client(cluster), cluster


def parse_list(text, known, what):
    values = tuple(v for v in (text or "").split(",") if v)
    unknown = sorted(set(values) - set(known))
    if unknown:
        raise bad_argument(f"unknown {what}(s) {', '.join(unknown)}; known: {', '.join(known)}")
    return values


def checked_config(args):
    """The FleetConfig of the command line; StageError (exit 2) for anything wrong."""
    bags = expand_bags(args.bags, args.relative_to, "--bags")
    train = expand_bags(args.train, args.relative_to, "--train") if args.train else []
    if not bags:
        raise bad_argument("--bags names no bag")
    both = set(map(os.path.realpath, bags)) & set(map(os.path.realpath, train))
    if both:
        raise bad_argument(f"{sorted(both)[0]} is in both --bags and --train: a drive is "
                           "either learnt from or classified")
    try:
        thresholds = tuple(int(t) for t in args.n_thresh.split(",") if t.strip())
        models_from, cap = int(args.models_from), int(args.class_cap)
    except ValueError as error:
        raise bad_argument(f"--n-thresh, --models-from and --class-cap take whole numbers "
                           f"({error})") from error
    if not thresholds or min(thresholds) < 1 or models_from < 1 or cap < 0:
        raise bad_argument("--n-thresh and --models-from must be positive, --class-cap 0 "
                           "(no cap) or more")
    methods = parse_list(args.methods, plan.REGISTRATION_METHODS, "method")
    supervised = parse_list(args.supervised, plan.SUPERVISED_METHODS, "supervised method")
    if args.preset not in plan.PRESETS:
        raise bad_argument(f"--preset must be one of {', '.join(plan.PRESETS)}")
    if "svm_fitness" in supervised and not methods:
        raise bad_argument("svm_fitness learns from the registration methods' fitness: give "
                           "--methods too")
    if args.boxes not in plan.BOXES:
        raise bad_argument(f"--boxes must be {' or '.join(plan.BOXES)}")
    if args.boxes == "segment" and not train:
        raise bad_argument("--boxes segment gives objects without a class, from which no "
                           "models can be learnt: name the labelled drives with --train")
    config_dir = resolve(args.config_dir, args.relative_to)
    if config_dir and not os.path.isdir(config_dir):
        raise bad_argument(f"config folder {config_dir} not found")
    workers = positive_number(args.workers, "--workers", int) if args.workers else None
    args.workers = workers or os.cpu_count() or 1
    return plan.FleetConfig(
        bags=bags, out=resolve(args.out, args.relative_to), train=train, thresholds=thresholds,
        models_from=models_from, model_method=args.model_method, methods=methods,
        preset=args.preset, supervised=supervised, boxes=args.boxes, class_cap=cap,
        config_dir=config_dir,
        sensor=sensor_option(args.sensor, args.relative_to),
        sensor_height=positive_number(args.sensor_height, "--sensor-height"),
        azimuth_step=positive_number(args.azimuth_step, "--azimuth-step"),
        prior_classes=args.prior_classes or None, keep_frames=args.keep_frames)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="run_fleet",
        description="The pipeline over many bags on Dask distributed: per bag its objects, per "
                    "class the models over the train drives (--train, else the bags "
                    "themselves), the supervised classifiers trained on the same objects, per "
                    "bag its objects classified, then one report (OUT/index.md, "
                    "OUT/report/index.md). Without --scheduler, on this machine (one worker "
                    "process per core). OUT/fleet.json holds each bag's status; the same "
                    "command again does only what is not done yet. Progress (bags finished, "
                    "objects per second, time left) on stderr. Folders and figures: "
                    "docs/fleet.md. Exit status: 0 every bag done, 1 a bag or stage failed "
                    "(the others finish), 2 bad arguments, 130/143 interrupted.")
    parser.add_argument("--bags", required=True, nargs="+", metavar="BAGS",
                        help="the drives to classify: paths or quoted glob patterns "
                             "('drives/*.bag'), comma- or space-separated")
    parser.add_argument("--out", required=True, help="output folder (resumed when it holds a "
                                                     "fleet run's results)")
    parser.add_argument("--train", nargs="+", metavar="BAGS",
                        help="drives the class models and supervised classifiers learn from "
                             "(default: the --bags themselves, whose report then scores "
                             "objects the classifiers have seen)")
    parser.add_argument("--scheduler", metavar="tcp://HOST:8786",
                        help="a running dask-scheduler whose workers see the workspace, the "
                             "bags and OUT at the same paths (default: a cluster on this "
                             "machine)")
    parser.add_argument("--workers", metavar="N",
                        help="without --scheduler: worker processes (default: one per core)")
    parser.add_argument("--n-thresh", default="10,100", metavar="N,N,...",
                        help="minimum points per object of the classified test sets "
                             "(default: %(default)s)")
    parser.add_argument("--models-from", default="10", metavar="N",
                        help="the models and classifiers learn from objects of N points or "
                             "more (default: %(default)s, as the report)")
    parser.add_argument("--model-method", default="plain", choices=("plain", "icp"),
                        help="build_models' concatenation (default: %(default)s)")
    parser.add_argument("--class-cap", default=str(plan.DEFAULT_CLASS_CAP), metavar="N",
                        help="most objects a class's model and the classifiers learn from, "
                             "evenly spaced over the class's objects in name (time) order; 0: "
                             "all (default: %(default)s)")
    parser.add_argument("--methods", default=",".join(plan.REGISTRATION_METHODS),
                        help="registration methods, '' for none (default: %(default)s)")
    parser.add_argument("--preset", default="tuned",
                        help="their preset of config/classification.yaml (default: "
                             "%(default)s)")
    parser.add_argument("--supervised", default="knn,svm,svm_fitness",
                        help="supervised methods, '' for none; svm_fitness learns from the "
                             "registration methods' results (default: %(default)s)")
    parser.add_argument("--boxes", default="detections",
                        help="detections (the bags' boxes) or segment (the box-free path: "
                             "cuboids fitted to segments; objects without truth, so no "
                             "accuracy; needs --train) (default: %(default)s)")
    add_sensor_options(parser)  # --boxes segment: the LiDAR and the cuboids' size priors
    parser.add_argument("--config-dir", metavar="FOLDER",
                        help="folder of the tools' YAML files (default: their built-in "
                             "defaults)")
    parser.add_argument("--keep-frames", action="store_true",
                        help="keep each bag's frames (PCD + JSON) beside its objects "
                             "(default: written on the worker's own disk and removed once the "
                             "bag's objects are cut out)")
    parser.add_argument("--relative-to", metavar="FOLDER",
                        help="resolve relative paths and patterns against FOLDER (the launch "
                             "file passes the folder roslaunch was started from; default: the "
                             "working folder)")
    parser.add_argument("--overwrite", action="store_true",
                        help="redo every bag, the models and the classifiers, whatever "
                             "OUT/fleet.json says is done (and write into an OUT another "
                             "granular tool wrote)")
    args = parser.parse_args(argv)
    started = time.monotonic()

    def body():
        config = checked_config(args)
        ledger_path = os.path.join(config.out, LEDGER)
        # A fleet folder is resumed; any other granular folder is replaced only when asked.
        with claimed_folder(config.out, "run_fleet",
                            overwrite=args.overwrite or os.path.exists(ledger_path)):
            ledger = Ledger(ledger_path, fresh=args.overwrite)
            client, cluster = open_client(args.scheduler, args.workers)
            try:
                fleet = Fleet(config, client, ledger, args.overwrite)
                fleet.run()
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
            index = report.write(config, ledger, fleet.ids)
        # fleet.json may also hold bags of earlier runs that this one was not given.
        bags = {bag_id: ledger.data["bags"][bag_id] for bag_id in fleet.ids.values()}
        counts = {s: sum(entry.get("status") == s for entry in bags.values())
                  for s in ("done", "skipped", "failed")}
        for bag_id, entry in sorted(bags.items()):
            if entry.get("status") == "failed":
                print(f"run_fleet: {bag_id} failed: {entry.get('message')}", file=sys.stderr)
        print(f"run_fleet: {len(bags)} bags: {counts['done']} done, {counts['skipped']} "
              f"skipped (done before), {counts['failed']} failed, in "
              f"{time.monotonic() - started:.1f} s; report: {index}")
        return 1 if counts["failed"] or ledger.data["models"].get("status") == "failed" else 0

    return run_main("run_fleet", body, (StageError, OutputError, OSError, ValueError))
