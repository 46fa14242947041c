"""A fleet run's options, the folders it writes under OUT, the tool command lines of its tasks,
and the keys that tell a resumed run what is already done.

OUT/fleet.json                 per bag: its status (done, skipped: done by an earlier run with
                               the same key, failed: with the message), keys, objects, accuracy
OUT/bags/<bag>/                a bag of --bags: objects/N<t>/ (frames/ with --keep-frames,
                               cuboids/ with --boxes segment), results/<method>/N<t>.json, log.txt
OUT/train/<bag>/               a bag of --train: objects/N<models-from>/, log.txt
OUT/reduce/<Class>/            the class's objects from every train drive (capped), its model
OUT/models/                    <Class>.pcd, raw/<Class>.pcd, models.json: the class models
OUT/train_objects/             the objects the models were built from, every class: what the
                               supervised classifiers learn from
OUT/classifiers/               <method>.yml; svm_fitness_training/: its registrations; logs/
OUT/fleet_results/             every bag's results and objects index as one test set
OUT/report/                    make_report over the fleet (with boxes from the bags)
OUT/index.md                   the fleet: bags, status, per-bag accuracy, the failed bags
"""
import dataclasses
import hashlib
import json
import os

REGISTRATION_METHODS = ("icp", "ndt", "icp_nl")
SUPERVISED_METHODS = ("knn", "svm", "svm_esf", "svm_fitness")
PRESETS = ("report", "tuned", "fast")
BOXES = ("detections", "segment")
# A class model's filters end in a voxel grid of some 5,000 points (docs/models.md): objects
# past a few thousand add cost, not points. Evenly spaced over the class's objects when capped.
DEFAULT_CLASS_CAP = 20000


def results_name(method, preset):
    """run_evaluation's name of a method's results: the report's preset keeps the bare name."""
    return method if preset == "report" else f"{method}_{preset}"


@dataclasses.dataclass
class FleetConfig:
    bags: list                      # the drives whose objects are classified
    out: str
    train: list = dataclasses.field(default_factory=list)  # empty: learn from `bags`
    thresholds: tuple = (10, 100)
    models_from: int = 10
    model_method: str = "plain"
    methods: tuple = REGISTRATION_METHODS
    preset: str = "tuned"
    supervised: tuple = ("knn", "svm", "svm_fitness")
    boxes: str = "detections"
    class_cap: int = DEFAULT_CLASS_CAP
    config_dir: str = None
    sensor: str = None  # config/sensors/ name, a sensor file or auto
    sensor_height: float = None
    azimuth_step: float = None
    prior_classes: str = None
    keep_frames: bool = False
    threads: int = 1

    def config_file(self, name):
        path = os.path.join(self.config_dir, name) if self.config_dir else None
        return path if path and os.path.isfile(path) else None

    # Folders under OUT.
    def folder(self, *parts):
        return os.path.join(self.out, *parts)

    @property
    def models(self):
        return self.folder("models")

    @property
    def train_objects(self):
        return self.folder("train_objects")

    @property
    def classifiers(self):
        return self.folder("classifiers")

    @property
    def result_names(self):
        return [results_name(m, self.preset) for m in self.methods] + list(self.supervised)

    def task_options(self):
        """What every task spec carries."""
        return {"config_dir": self.config_dir, "threads": self.threads}

    def extraction_spec(self, bag, folder, learns_only):
        """extract_bag's spec; a train-only bag's objects are needed at N<models-from> only."""
        thresholds = ((self.models_from,) if learns_only else
                      tuple(sorted(set(self.thresholds) | ({self.models_from} if not self.train
                                                           else set()))))
        return dict(self.task_options(), bag=bag, folder=folder, thresholds=thresholds,
                    classes_at=self.models_from,
                    boxes="detections" if learns_only else self.boxes,
                    sensor=self.sensor, sensor_height=self.sensor_height,
                    azimuth_step=self.azimuth_step,
                    prior_classes=self.prior_classes, keep_frames=self.keep_frames)

    def class_spec(self, label, sources):
        work = self.folder("reduce", label)
        return dict(self.task_options(), label=label, sources=sources, cap=self.class_cap,
                    work=work, out=os.path.join(work, "models"), method=self.model_method)

    def registration_command(self, method, objects, out):
        return ["rosrun", "granular_ros", "classify_registration", "--models", self.models,
                "--objects", objects, "--method", method, "--preset", self.preset, "--out", out,
                *(["--config", self.config_file("classification.yaml")]
                  if self.config_file("classification.yaml") else [])]

    def training_specs(self):
        """[(method, spec of run_commands)]: each supervised classifier's training, svm_fitness
        with the registrations of the train objects it learns from."""
        specs = []
        supervised_config = (["--config", self.config_file("supervised.yaml")]
                             if self.config_file("supervised.yaml") else [])
        for method in self.supervised:
            model = os.path.join(self.classifiers, f"{method}.yml")
            commands, registration = [], []
            if method == "svm_fitness":
                training = os.path.join(self.classifiers, "svm_fitness_training")
                for name in self.methods:
                    registration.append(os.path.join(
                        training, f"{results_name(name, self.preset)}.json"))
                    commands.append(self.registration_command(name, self.train_objects,
                                                              registration[-1]))
            commands.append(["rosrun", "granular_ros", "train_classifier", "--objects",
                             self.train_objects, "--method", method, "--out", model,
                             *(["--registration", ",".join(registration)] if registration
                               else []), *supervised_config])
            specs.append((method, dict(
                self.task_options(), commands=commands,
                folders=[self.classifiers] + ([os.path.dirname(registration[0])]
                                              if registration else []),
                log=os.path.join(self.classifiers, "logs", f"{method}.log"))))
        return specs

    def classification_spec(self, folder):
        """run_commands' spec for a bag's objects at every threshold through every method."""
        commands, folders = [], []
        for threshold in self.thresholds:
            objects = os.path.join(folder, "objects", f"N{threshold}")
            registration = {}
            for method in self.methods:
                name = results_name(method, self.preset)
                registration[method] = os.path.join(folder, "results", name,
                                                    f"N{threshold}.json")
                commands.append(self.registration_command(method, objects,
                                                          registration[method]))
            for method in self.supervised:
                command = ["rosrun", "granular_ros", "classify_supervised", "--model",
                           os.path.join(self.classifiers, f"{method}.yml"), "--objects", objects,
                           "--out", os.path.join(folder, "results", method,
                                                 f"N{threshold}.json")]
                if method == "svm_fitness":
                    command += ["--registration", ",".join(registration[m]
                                                           for m in self.methods)]
                commands.append(command)
        folders = [os.path.join(folder, "results", name) for name in self.result_names]
        return dict(self.task_options(), commands=commands, folders=folders,
                    log=os.path.join(folder, "log.txt"))

    # Keys: what a result depends on, hashed; a stored key that matches means done.
    def _configuration(self):
        files = {}
        if self.config_dir and os.path.isdir(self.config_dir):
            for name in sorted(os.listdir(self.config_dir)):
                path = os.path.join(self.config_dir, name)
                if name.endswith(".yaml") and os.path.isfile(path):
                    with open(path, "rb") as stream:
                        files[name] = hashlib.sha256(stream.read()).hexdigest()
        return files

    def extraction_key(self, identity, learns_only):
        spec = self.extraction_spec("", "", learns_only)
        return digest({"bag": identity, "learns_only": learns_only,
                       "thresholds": spec["thresholds"], "boxes": spec["boxes"],
                       "sensor": [self.sensor, self.sensor_height, self.azimuth_step,
                                  self.prior_classes]
                       if spec["boxes"] == "segment" else None,
                       "config": self._configuration()})

    def models_key(self, extraction_keys):
        return digest({"train": sorted(extraction_keys), "cap": self.class_cap,
                       "method": self.model_method, "models_from": self.models_from,
                       "methods": self.methods, "preset": self.preset,
                       "supervised": self.supervised, "config": self._configuration()})

    def classification_key(self, extraction_key, models_digest):
        return digest({"objects": extraction_key, "models": models_digest,
                       "methods": self.methods, "preset": self.preset,
                       "supervised": self.supervised, "thresholds": self.thresholds,
                       "config": self._configuration()})


def digest(value):
    return hashlib.sha256(json.dumps(value, sort_keys=True).encode()).hexdigest()


def files_digest(*folders):
    """A hash of the files directly in `folders` (the models and classifiers the bags are
    classified with), by name and content."""
    hashed = hashlib.sha256()
    for folder in folders:
        for name in sorted(os.listdir(folder)) if os.path.isdir(folder) else []:
            path = os.path.join(folder, name)
            if os.path.isfile(path) and not name.startswith("."):
                hashed.update(name.encode() + b"\0")
                with open(path, "rb") as stream:
                    hashed.update(hashlib.sha256(stream.read()).digest())
    return hashed.hexdigest()


def bag_ids(paths):
    """{path: id}: a bag's file name without .bag, made unique by a hash of its path where two
    bags share a name."""
    stems = [os.path.splitext(os.path.basename(p))[0] for p in paths]
    return {path: stem if stems.count(stem) == 1 else
            f"{stem}-{hashlib.sha1(os.path.realpath(path).encode()).hexdigest()[:8]}"
            for path, stem in zip(paths, stems)}
