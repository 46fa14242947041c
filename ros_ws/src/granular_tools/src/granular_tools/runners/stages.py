"""What the runners that chain tools share (run_pipeline, run_evaluation, run_cuboids): each tool
run as a stage whose failure stops the run with the tool's exit status, a FAILED marker in the
output folder, and signals passed on to the running tool; the frames stage; fit_cuboids'
command and the sensor options it takes, the simulator's by default."""
import contextlib
import math
import os
import signal
import subprocess

from .. import progress
from ..bag_to_files.config import BagToFilesConfig
from ..bag_to_files.offline import convert_into_new_folder, has_detections
from ..bags import BagError
from ..config_loading import ConfigError, load_yaml_over
from ..output import Interrupted, OutputError, resolve, write_atomically
from ..pcd import CloudError

FAILED_MARKER = "FAILED"
_CHILD_GRACE = 20.0  # s a tool has to clean up after a forwarded signal before it is killed


class StageError(RuntimeError):
    """A stage that failed; `status` is the exit status the runner returns."""

    def __init__(self, stage, message, status=1):
        super().__init__(f"{stage}: {message}")
        self.stage, self.reason, self.status = stage, message, status


def bad_argument(message):
    """The StageError of a bad argument: stage "arguments", exit status 2."""
    return StageError("arguments", message, 2)


class ConfigFolder:
    """For a runner's arguments with a `config_dir` (None: the tools' defaults)."""

    def config_file(self, name):
        """The config file `name` when the config folder is given and holds it."""
        path = os.path.join(self.config_dir, name) if self.config_dir else None
        return path if path and os.path.exists(path) else None


def add_runner_options(parser):
    """--relative-to and --overwrite, as every runner behind a launch file takes them."""
    parser.add_argument("--relative-to", metavar="FOLDER",
                        help="resolve relative paths against FOLDER (the launch file passes the "
                             "folder roslaunch was started from; default: the working folder)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace results that granular tools wrote in OUT")


def existing_file(path, what):
    """`path` when it is a readable file; a StageError naming it otherwise."""
    if not os.path.isfile(path):
        raise StageError("arguments", f"{what} {path} not found"
                         + (" (it is a folder)" if os.path.isdir(path) else ""), 2)
    if not os.access(path, os.R_OK):
        raise StageError("arguments", f"{what} {path} is not readable", 2)
    return path


def positive_number(text, name, kind=float):
    """A positive, finite `kind` from an option's `text`; None for an empty text; a StageError (exit 2)
    naming the option otherwise."""
    if text in (None, ""):
        return None
    try:
        value = kind(text)
    except ValueError:
        value = 0
    # Infinite is no number to pass on: the tools it goes to refuse it after earlier stages ran.
    if not (value > 0 and math.isfinite(value)):
        raise StageError("arguments", f"{name} must be a positive number, got '{text}'", 2)
    return value


def bag_frames_config(bag, config_file):
    """(bag-to-files config: defaults, then `config_file` when given; whether `bag` carries the
    config's detections topic). A bag that cannot be read is a StageError of the frames stage."""
    config = load_yaml_over(BagToFilesConfig(), config_file) if config_file \
        else BagToFilesConfig()
    try:
        return config, has_detections(bag, config)
    except BagError as error:
        raise StageError("frames", str(error)) from error


def frames_stage(bag, folder, config, overwrite):
    """The frames stage: `bag` to files into `folder` (an output folder) with `config`."""
    reporter = progress.Reporter("frames", unit="messages")
    try:
        stats = convert_into_new_folder(bag, folder, config.check(), overwrite, reporter)
    except (BagError, CloudError, OutputError, ConfigError, ValueError) as error:
        raise StageError("frames", str(error)) from error
    reporter.finish()
    print(f"frames: {stats.summary(config.slop)}", flush=True)


# The simulator's sensor and vehicles: the runners' defaults, as the launch files' (cuboids,
# pipeline and online.launch repeat them; test_run_cuboids checks that they agree). The
# height and step are overrides of the sensor file's, empty by default.
SIMULATOR_SENSOR = {"sensor": "simulator", "sensor_height": "", "azimuth_step": "",
                    "prior_classes": "Sedan,SUV,Hatchback,Jeep,BoxTruck,SchoolBus"}


def add_sensor_options(parser):
    """--sensor, --sensor-height, --azimuth-step and --prior-classes: the sensor and the
    vehicles that fit_cuboids needs to know; the simulator's by default, as in the launch
    files. An empty --prior-classes leaves config/cuboids.yaml's priors."""
    parser.add_argument("--sensor", default=SIMULATOR_SENSOR["sensor"], metavar="NAME|FILE|auto",
                        help="the LiDAR: config/sensors/NAME.yaml (simulator, hdl64e, os1_64, "
                             "vlp16, pandar64), a sensor file, or auto (measured from the "
                             "bag's clouds; default %(default)s)")
    parser.add_argument("--sensor-height", default=SIMULATOR_SENSOR["sensor_height"],
                        metavar="M",
                        help="the sensor's height above the road, over the sensor file's")
    parser.add_argument("--azimuth-step", default=SIMULATOR_SENSOR["azimuth_step"],
                        metavar="DEG",
                        help="the sensor's angle between returns along a ring, over the sensor "
                             "file's")
    parser.add_argument("--prior-classes", default=SIMULATOR_SENSOR["prior_classes"],
                        metavar="LIST",
                        help="the size priors the geometric fit chooses among, comma-separated "
                             "(default %(default)s, the simulator's vehicles; KITTI "
                             "Car,Van,Truck)")


def sensor_option(sensor, relative_to):
    """The --sensor value: a name or auto as given, a file resolved against `relative_to`."""
    if sensor and ("/" in sensor or sensor.endswith(".yaml")):
        return resolve(sensor, relative_to)
    return sensor or None


# The classifiers that can name box-free cuboids (fit_cuboids --name-with).
NAME_METHODS = ("icp", "icp_nl", "ndt", "knn", "svm", "svm_esf", "svm_fitness")


def check_naming(name_with, name_models, class_models):
    """A StageError (exit 2) for naming arguments that do not go together: the classifier that
    names each box-free cuboid (fit_cuboids --name-with), its models and, for svm_fitness, the
    class models it learnt from."""
    if name_with and name_with not in NAME_METHODS:
        raise bad_argument(f"name_with must be one of {', '.join(NAME_METHODS)}, got "
                           f"'{name_with}'")
    if bool(name_with) != bool(name_models):
        raise bad_argument("name_with and name_models go together: the classifier and its "
                           "models folder or file")
    if name_with == "svm_fitness" and not class_models:
        raise bad_argument("name_with svm_fitness needs class_models, the models folder it "
                           "learnt from")
    for path in (name_models, class_models):
        if path and not os.path.exists(path):
            raise bad_argument(f"{path} not found")


def sensor_arguments(run):
    """fit_cuboids' sensor options for `run` (its sensor, sensor_height, azimuth_step and
    prior_classes; None leaves an option out)."""
    arguments = []
    for option, value in (("--sensor", run.sensor), ("--sensor-height", run.sensor_height),
                          ("--azimuth-step", run.azimuth_step),
                          ("--prior-classes", run.prior_classes)):
        arguments += [option, str(value)] if value is not None else []
    return arguments


def fit_command(run, frames, out, boxes, method=None, models=None, classifier=None,
                track=False, naming=None):
    """The fit_cuboids command for `run` (a CuboidsRun or a pipeline's PipelineRun: its
    config_file(), sensor, sensor_height, azimuth_step, prior_classes and overwrite); `track`
    tracks the cuboids with the config folder's tracking.yaml; `naming` (name_with,
    name_models, class_models or None) names them with that classifier."""
    command = ["rosrun", "granular_ros", "fit_cuboids", "--frames", frames, "--out", out,
               "--boxes", boxes] + (["--track"] if track else [])
    for option, value in (("--method", method), ("--models", models),
                          ("--classifier", classifier),
                          ("--config", run.config_file("cuboids.yaml")),
                          ("--ground-config", run.config_file("ground.yaml")),
                          ("--segmentation-config", run.config_file("segmentation.yaml")),
                          ("--tracking-config",
                           run.config_file("tracking.yaml") if track else None)):
        command += [option, str(value)] if value is not None else []
    command += sensor_arguments(run)
    name_with, name_models, class_models = naming or (None, None, None)
    for option, value in (("--name-with", name_with), ("--name-models", name_models),
                          ("--class-models", class_models),
                          ("--registration-config",
                           run.config_file("classification.yaml") if name_with else None),
                          ("--extraction-config",
                           run.config_file("extraction.yaml") if name_with else None)):
        command += [option, str(value)] if value is not None else []
    return command + (["--overwrite"] if run.overwrite else [])


_executables = {}  # (package, executable) -> its path, or None where rosrun must find it


def without_rosrun(command):
    """`rosrun PACKAGE EXECUTABLE ARGS...` as `PATH ARGS...`, PATH being the executable catkin
    installed for PACKAGE (the one rosrun runs), looked up once per executable: rosrun's own
    look-up costs about half a second a call, and an evaluation runs some fifty tools. Any
    other command, or one catkin does not know, is returned as it is."""
    if len(command) < 3 or command[0] != "rosrun":
        return command
    key = (command[1], command[2])
    if key not in _executables:
        try:
            from catkin.find_in_workspaces import find_in_workspaces
            found = find_in_workspaces(search_dirs=["libexec"], project=key[0], path=key[1],
                                       first_match_only=True)
        except ImportError:
            found = []
        _executables[key] = (found[0] if found and os.path.isfile(found[0])
                             and os.access(found[0], os.X_OK) else None)
    return [_executables[key], *command[3:]] if _executables[key] else command


def run_tool(command, stage):
    """Run one tool as a stage: its messages reach the user; a failure raises StageError with
    its exit status. A stop signal is passed on, so that the tool removes its partial output,
    and then stops this run too."""
    process = subprocess.Popen(without_rosrun(command))
    try:
        status = process.wait()
    except Interrupted as stop:
        with contextlib.suppress(ProcessLookupError):
            process.send_signal(stop.signum)
        try:
            process.wait(timeout=_CHILD_GRACE)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        raise
    if status != 0:
        if status < 0:
            status = 128 - status  # killed by a signal
        raise StageError(stage, f"failed with exit status {status} (its message is above)",
                         status)


@contextlib.contextmanager
def failure_marker(out):
    """Removes OUT/FAILED when a run starts; leaves one naming the stage and the reason when it
    fails, so that half a run's results never look complete."""
    marker = os.path.join(out, FAILED_MARKER)
    with contextlib.suppress(FileNotFoundError):
        os.remove(marker)
    try:
        yield
    except StageError as error:
        _mark(marker, f"stage: {error.stage}\nreason: {error.reason}\n"
                      f"exit status: {error.status}\n")
        raise
    except Interrupted as stop:
        _mark(marker, f"reason: interrupted by {signal.Signals(stop.signum).name}\n")
        raise
    except Exception as error:  # noqa: BLE001 - every failure leaves the marker, then goes on
        _mark(marker, f"reason: {error}\n")
        raise


def _mark(marker, text):
    with contextlib.suppress(OutputError):
        write_atomically(marker, text.encode(), "failure marker")
