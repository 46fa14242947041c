"""What the hostile-input tests share: running a built tool as a user would, the checks every
case makes (exit status, a message naming the culprit, no traceback, nothing half written, no
unrelated file touched), a full disk, and a small dataset made once per test session."""
import contextlib
import dataclasses
import hashlib
import os
import pathlib
import shutil
import signal
import subprocess
import tempfile
import time

import pytest

from granular_tools.runners.stages import without_rosrun

# Signs that a tool fell over instead of reporting: Python and C++ crash output.
CRASH_SIGNS = ("Traceback (most recent call last)", "terminate called", "Segmentation fault",
               "core dumped", "what():")


@dataclasses.dataclass
class Result:
    command: list
    status: int
    stdout: str
    stderr: str

    @property
    def output(self):
        return self.stdout + self.stderr

    def __str__(self):
        return (f"$ {' '.join(map(str, self.command))}\nexit {self.status}\n"
                f"--- stdout\n{self.stdout}--- stderr\n{self.stderr}")


def tool(package, name):
    """The command that runs a built tool: the executable `rosrun PACKAGE NAME` runs, without
    rosrun's half a second of looking it up each time."""
    return without_rosrun(["rosrun", package, name])


# The tools the cases run.
EXTRACT = tool("granular_ros", "extract_objects")
BUILD_MODELS = tool("granular_ros", "build_models")
TRAIN = tool("granular_ros", "train_classifier")
CLASSIFY_REGISTRATION = tool("granular_ros", "classify_registration")
CLASSIFY_SUPERVISED = tool("granular_ros", "classify_supervised")
ONLINE_CLASSIFIER = tool("granular_ros", "online_classifier")
SEGMENT_CLOUD = tool("granular_ros", "segment_cloud")
BAG_TO_FILES = tool("granular_tools", "bag_to_files")
BAG_TO_FILES_NODE = tool("granular_tools", "bag_to_files_node")
SIMULATE = tool("granular_tools", "simulate_drive")
RENDER = tool("granular_tools", "render_models")
MAKE_REPORT = tool("granular_tools", "make_report")
RUN_PIPELINE = tool("granular_tools", "run_pipeline")


def run(command, cwd=None, env=None, timeout=300):
    """Run `command` to its end; its output is captured as text."""
    command = [str(part) for part in command]
    completed = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True,
                               errors="replace", timeout=timeout, check=False)
    return Result(command, completed.returncode, completed.stdout, completed.stderr)


def start(command, cwd=None, env=None):
    """Start `command` in its own process group, output captured to files (no pipe to fill)."""
    command = [str(part) for part in command]
    out = tempfile.TemporaryFile(mode="w+")
    err = tempfile.TemporaryFile(mode="w+")
    process = subprocess.Popen(command, cwd=cwd, env=env, stdout=out, stderr=err,
                               start_new_session=True)
    process.streams = (out, err)
    process.command = command
    return process


def finish(process, timeout=120):
    process.wait(timeout=timeout)
    out, err = process.streams
    out.seek(0)
    err.seek(0)
    return Result(process.command, process.returncode, out.read(), err.read())


def wait_for(condition, timeout=60.0, what="the condition"):
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.02)


def assert_fails_clearly(result, status, *names):
    """A failure as a user should meet it: the expected exit status, every name in `names`
    (path, key, value) in the message, and no traceback or crash."""
    assert result.status == status, str(result)
    assert_no_crash(result)
    for name in names:
        assert str(name) in result.output, f"{name!r} not named\n{result}"


def assert_no_crash(result):
    for sign in CRASH_SIGNS:
        assert sign not in result.output, str(result)


def leftovers(folder):
    """Hidden staging and temporary files that a tool left in `folder` (recursively)."""
    folder = pathlib.Path(folder)
    if not folder.exists():
        return []
    return sorted(str(path) for path in folder.rglob("*")
                  if ".partial-" in path.name or ".previous-" in path.name)


def snapshot(folder):
    """Every file below `folder` with a digest of its bytes, to show that nothing changed."""
    folder = pathlib.Path(folder)
    return {str(path.relative_to(folder)): hashlib.sha1(path.read_bytes()).hexdigest()
            for path in sorted(folder.rglob("*")) if path.is_file()}


def user_folder(path):
    """A folder of a user's own files (no granular manifest), with a nested one."""
    path = pathlib.Path(path)
    (path / "thesis").mkdir(parents=True)
    (path / "notes.txt").write_text("my notes\n")
    (path / "thesis" / "chapter1.tex").write_text("\\chapter{One}\n")
    return path


@contextlib.contextmanager
def full_disk(folder, size="256k"):
    """A tmpfs of `size` mounted at `folder`, filled to the last byte; skips when this machine
    cannot mount one."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)],
                             capture_output=True, text=True, check=False)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs for a full disk here: {mounted.stderr.strip()}")
    try:
        filler = folder / "filler"
        with contextlib.suppress(OSError), open(filler, "wb") as stream:
            while True:
                stream.write(b"\0" * 4096)
                stream.flush()
        yield folder
    finally:
        subprocess.run(["umount", "-l", str(folder)], check=False)


def files_on(folder, keep=("filler",)):
    """What a tool left on a full disk besides the filler."""
    return sorted(name for name in os.listdir(folder) if name not in keep)


def interrupt_when(process, condition, signum, what, timeout=60.0):
    """Send `signum` to `process` once `condition()` holds (it is mid-run), and finish it."""
    try:
        wait_for(lambda: condition() or process.poll() is not None, timeout, what)
    finally:
        if process.poll() is None:
            # Ctrl-C reaches the whole foreground group; kill(1) names one process.
            if signum == signal.SIGINT:
                os.killpg(process.pid, signum)
            else:
                process.send_signal(signum)
    return finish(process)


def copy_tree(source, target):
    shutil.copytree(source, target)
    return pathlib.Path(target)
