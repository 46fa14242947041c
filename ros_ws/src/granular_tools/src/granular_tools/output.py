"""Safe output for every Python tool, as granular_core/dataset/output_folder.h does it for C++.
(Over 400 lines: the manifest, the lock, the staging, the atomic writers and the signal
handling are one policy, and its pieces call each other.)

- A folder a tool writes carries a manifest (MANIFEST) naming the tool and version; only such a
  folder may be replaced, and only when the user asks (--overwrite).
- A folder is built in a staging sibling ".<name>.partial-<pid>" and renamed into place once
  flushed to disk; a single file through ".<name>.partial-<pid>", fsync and rename.
- An exclusive lock (flock on lock_file_of(folder)) refuses a second run into one folder.
- A later run clears what dead runs left (by the pid in the name).
- SIGINT, SIGTERM and SIGHUP stop a tool with one line and exit 128 + the signal's number,
  removing its staging on the way out (run_main).
"""
import contextlib
import ctypes
import errno
import fcntl
import io
import json
import os
import re
import shutil
import signal
import sys
import time

MANIFEST = ".granular.json"
VERSION = "0.1.0"  # package.xml's; test_output.py checks
_STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class OutputError(OSError):
    """An output that cannot be written as asked; the message names the path."""


class Interrupted(BaseException):
    """A stop signal arrived; raised in the main thread by the handlers of stop_on_signals."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def overwrite_hint():
    """How the user asks for overwriting: '--overwrite', or what a launch file set."""
    return os.environ.get("GRANULAR_OVERWRITE_HINT") or "--overwrite"


def absolute(path):
    """`path` absolute and normalised, without a trailing separator."""
    return os.path.normpath(os.path.abspath(path))


def resolve(path, relative_to=None):
    """`path` made absolute against `relative_to` (the folder the user ran roslaunch from,
    which launch files pass) or the working directory."""
    if path is None or os.path.isabs(path):
        return path
    return os.path.normpath(os.path.join(relative_to or os.getcwd(), path))


def temporary_sibling(path, kind):
    path = absolute(path)
    return os.path.join(os.path.dirname(path), f".{os.path.basename(path)}.{kind}-{os.getpid()}")


def process_running(pid):
    """Whether process `pid` still runs (one of another user's counts as running)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def clear_dead_siblings(path):
    """Remove what dead runs left beside `path`; put back a set-aside previous result."""
    path = absolute(path)
    parent, name = os.path.split(path)
    pattern = re.compile(r"^\." + re.escape(name) + r"\.(partial|previous)-(\d{1,9})(\.removing|\.\w+)?$")
    done, set_aside = [], []
    try:
        entries = os.listdir(parent)
    except OSError:
        return done
    for entry in entries:
        match = pattern.match(entry)
        if not match:
            continue
        pid = int(match.group(2))
        if pid == os.getpid() or process_running(pid):
            continue
        full = os.path.join(parent, entry)
        if match.group(1) == "previous":
            set_aside.append(full)
            continue
        _remove(full)
        done.append(f"removed {full}, left by process {pid}, which is no longer running")
    for old in set_aside:
        if not os.path.lexists(path):
            os.replace(old, path)
            done.append(f"put back {path} from {old}, set aside by a run that was killed "
                        "while replacing it")
        else:
            _remove(old)
            done.append(f"removed {old}, an old result a killed run had replaced")
    return done


def _remove(path):
    if os.path.isdir(path) and not os.path.islink(path):
        shutil.rmtree(path, ignore_errors=True)
    elif os.path.lexists(path):
        with contextlib.suppress(OSError):
            os.remove(path)


def _manifest_tool(folder):
    try:
        with open(os.path.join(folder, MANIFEST), encoding="utf-8") as stream:
            manifest = json.load(stream)
    except (OSError, ValueError):
        return None
    tool = manifest.get("tool") if isinstance(manifest, dict) else None
    return tool if isinstance(tool, str) else None


def check_output_folder(target, overwrite, hint=None):
    """Raise OutputError when a tool may not write the folder `target` (see the module)."""
    hint = hint or overwrite_hint()
    if not os.path.lexists(target):
        return
    if not os.path.isdir(target):
        raise OutputError(f"{target}: output exists and is not a folder")
    if not os.listdir(target):
        return
    tool = _manifest_tool(target)
    if tool is None:
        raise OutputError(f"{target}: output folder holds files that no granular tool wrote "
                          f"(it has no {MANIFEST}); refusing to replace it, even with {hint}: "
                          "choose another folder, or remove it yourself")
    if not overwrite:
        raise OutputError(f"{target}: output folder holds results of {tool}; pass {hint} to "
                          "replace them")


def check_output_apart(target, inputs, error=OutputError):
    """Raise `error` when the output `target` is, or holds, one of `inputs` (paths; None and ""
    are skipped): replacing it would lose the input."""
    real_target = os.path.realpath(target)
    for path in inputs:
        if not path:
            continue
        real = os.path.realpath(path)
        if real == real_target or real.startswith(real_target + os.sep):
            raise error(f"{target}: the output would replace the input {path}; choose another "
                        "output")


def _manifest(tool):
    return json.dumps({"tool": tool, "version": VERSION,
                       "written": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())},
                      indent=1).encode() + b"\n"


def _fsync_folder(folder):
    with contextlib.suppress(OSError):
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


_LIBC = ctypes.CDLL(None, use_errno=True)


def _sync_filesystem(folder):
    """Flush the file system that holds `folder` (syncfs: not every disk, as os.sync would)."""
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        if _LIBC.syncfs(fd) != 0:
            code = ctypes.get_errno()
            raise OSError(code, os.strerror(code))
    finally:
        os.close(fd)


def write_file(path, data, what="file"):
    """Write `data` (bytes) to `path`; on failure remove it and raise OutputError naming it."""
    try:
        with open(path, "wb") as stream:
            stream.write(data)
    except OSError as error:
        _remove(path)
        raise OutputError(f"{path}: cannot write {what}: {error.strerror or error}") from error


def _check_parent(path):
    parent = os.path.dirname(absolute(path))
    if not os.path.isdir(parent):
        raise OutputError(f"{path}: folder {parent} does not exist")
    if os.path.isdir(path):
        raise OutputError(f"{path}: is a folder")


def write_atomically(path, data, what="file"):
    """Write `data` (bytes) to `path` through a flushed temporary sibling and a rename."""
    _check_parent(path)
    clear_dead_siblings(path)
    partial = temporary_sibling(path, "partial")
    _pending.add(partial)
    try:
        with open(partial, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        os.replace(partial, path)
    except OSError as error:
        _remove(partial)
        raise OutputError(f"{path}: cannot write {what}: {error.strerror or error}") from error
    finally:
        _pending.discard(partial)
    _fsync_folder(os.path.dirname(absolute(path)))


def save_figure(figure, path, dpi=100):
    """Draw a matplotlib figure into `path` (format from its extension) atomically: drawn in
    memory first, so that a full disk is an OutputError naming `path`, never half a picture."""
    drawn = io.BytesIO()
    figure.savefig(drawn, format=os.path.splitext(path)[1][1:] or "png", dpi=dpi)
    write_atomically(path, drawn.getvalue(), "picture")


@contextlib.contextmanager
def written_atomically(path, what="file"):
    """Yield a temporary sibling of `path` for a writer that takes a file name (savefig...);
    on leaving without an exception it is flushed and renamed to `path`, else removed."""
    _check_parent(path)
    clear_dead_siblings(path)
    # Writers that pick the format from the name see the final extension.
    partial = temporary_sibling(path, "partial") + os.path.splitext(path)[1]
    _pending.add(partial)
    try:
        yield partial
        with open(partial, "rb+") as stream:
            os.fsync(stream.fileno())
        os.replace(partial, path)
    except OSError as error:
        _remove(partial)
        raise OutputError(f"{path}: cannot write {what}: {error.strerror or error}") from error
    except BaseException:
        _remove(partial)
        raise
    finally:
        _pending.discard(partial)


def lock_file_of(target):
    """The lock file of an output folder, as granular_core's lockFileOf: FNV-1a of the folder's
    canonical path, under $XDG_RUNTIME_DIR/granular-locks (or /tmp/granular-locks)."""
    hashed = 14695981039346656037
    for byte in os.path.realpath(target).encode():
        hashed = ((hashed ^ byte) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    base = os.environ.get("XDG_RUNTIME_DIR") or "/tmp"
    return os.path.join(base, "granular-locks", f"{hashed:016x}.lock")


class _Lock:
    """An exclusive flock on lock_file_of(target), noting who holds it."""

    def __init__(self, target, tool):
        self.path = lock_file_of(target)
        try:
            os.mkdir(os.path.dirname(self.path))
            os.chmod(os.path.dirname(self.path), 0o1777)  # every user's, like /tmp
        except FileExistsError:
            pass
        except OSError as error:
            raise OutputError(f"{target}: cannot create the lock folder "
                              f"{os.path.dirname(self.path)}: {error.strerror}") from error
        try:
            self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except OSError as error:
            raise OutputError(f"{target}: cannot create the lock file {self.path}: "
                              f"{error.strerror}") from error
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as error:
            holder = ""
            with contextlib.suppress(OSError), open(self.path, encoding="utf-8") as stream:
                holder = stream.readline().strip()
            os.close(self.fd)
            if error.errno in (errno.EWOULDBLOCK, errno.EAGAIN):
                raise OutputError(f"{target}: another granular run is writing this folder"
                                  + (f" ({holder})" if holder else "")
                                  + "; wait for it to finish or choose another output folder") \
                    from error
            raise OutputError(f"{target}: cannot lock {self.path}: {error.strerror}") from error
        with contextlib.suppress(OSError):
            os.ftruncate(self.fd, 0)
            os.write(self.fd, f"process {os.getpid()}, {tool}\n".encode())

    def release(self):
        os.close(self.fd)


def _make_parent(target):
    parent = os.path.dirname(target)
    try:
        os.makedirs(parent, exist_ok=True)
    except OSError as error:
        raise OutputError(f"{target}: cannot create the folder {parent}: "
                          f"{error.strerror}") from error


class OutputFolder:
    """A folder built as a whole (see the module):

        with OutputFolder(out, "bag_to_files", overwrite) as folder:
            ... write into folder.staging ...
            folder.commit()
    """

    def __init__(self, target, tool, overwrite=False, hint=None, inputs=()):
        """`inputs`: the run's input files and folders, which the output may not replace."""
        self.target = absolute(target)
        self.tool, self.overwrite, self.hint = tool, overwrite, hint
        self.inputs = tuple(inputs)
        self.staging = temporary_sibling(self.target, "partial")
        self.cleared = []
        self._lock = None
        self._committed = False

    def __enter__(self):
        check_output_apart(self.target, self.inputs)
        _make_parent(self.target)
        self._lock = _Lock(self.target, self.tool)
        try:
            self.cleared = clear_dead_siblings(self.target)
            check_output_folder(self.target, self.overwrite, self.hint)
            _pending.add(self.staging)
            _remove(self.staging)
            os.mkdir(self.staging)
        except OSError as error:
            self._lock.release()
            _pending.discard(self.staging)
            if isinstance(error, OutputError):
                raise
            raise OutputError(f"{self.target}: cannot create the staging folder "
                              f"{self.staging}: {error.strerror}") from error
        except BaseException:
            self._lock.release()
            raise
        return self

    def commit(self):
        write_file(os.path.join(self.staging, MANIFEST), _manifest(self.tool), "manifest")
        try:
            _sync_filesystem(self.staging)
        except OSError as error:
            raise OutputError(f"{self.target}: cannot flush the results to disk: "
                              f"{error.strerror}") from error
        previous = temporary_sibling(self.target, "previous")
        with _pending.hold():
            had_previous = os.path.lexists(self.target)
            if had_previous:
                os.replace(self.target, previous)
            try:
                os.replace(self.staging, self.target)
            except OSError as error:
                if had_previous:
                    os.replace(previous, self.target)
                raise OutputError(f"{self.target}: cannot put the results in place: "
                                  f"{error.strerror}") from error
            _pending.discard(self.staging)
            if had_previous:
                _pending.add(previous)
        self._committed = True
        _fsync_folder(os.path.dirname(self.target))
        if had_previous:
            _remove(previous)
            _pending.discard(previous)

    def __exit__(self, *exc):
        if not self._committed:
            _remove(self.staging)
            _pending.discard(self.staging)
        self._lock.release()
        return False


@contextlib.contextmanager
def claimed_folder(target, tool, overwrite=True, hint=None):
    """A folder written in place (run_pipeline's OUT, whose stages replace its sub-folders; the
    live bag_to_files node's folder): locked for the run, created with a manifest when absent or
    empty, refused when it holds files that no granular tool wrote, or (unless `overwrite`) a
    granular tool's results. Yields its absolute path."""
    target = absolute(target)
    _make_parent(target)
    lock = _Lock(target, tool)
    try:
        created = not os.path.lexists(target)
        if not created:
            check_output_folder(target, overwrite, hint)
        try:
            os.makedirs(target, exist_ok=True)
            if _manifest_tool(target) is None:
                write_file(os.path.join(target, MANIFEST), _manifest(tool), "manifest")
        except OSError as error:
            if created:  # made here a moment ago (a full disk): not left behind empty
                shutil.rmtree(target, ignore_errors=True)
            if isinstance(error, OutputError):
                raise
            raise OutputError(f"{target}: cannot create the folder: {error.strerror}") from error
        yield target
    finally:
        lock.release()


class _PendingOutputs:
    """Staging folders and temporary files to remove when a signal stops the tool."""

    def __init__(self):
        self.paths = set()
        self._held = 0

    def add(self, path):
        self.paths.add(path)

    def discard(self, path):
        self.paths.discard(path)

    @contextlib.contextmanager
    def hold(self):
        """Defers a stop signal until the renames of a commit are done."""
        self._held += 1
        try:
            yield
        finally:
            self._held -= 1
            if self._held == 0 and _deferred:
                raise Interrupted(_deferred.pop())

    def held(self):
        return self._held > 0

    def remove_all(self):
        removed = [path for path in sorted(self.paths) if os.path.lexists(path)]
        for path in removed:
            _remove(path)
        self.paths.clear()
        return removed


_pending = _PendingOutputs()
_deferred = []


def _on_signal(signum, _frame):
    if _pending.held():
        _deferred.append(signum)
        return
    raise Interrupted(signum)


def stop_on_signals():
    """SIGINT, SIGTERM and SIGHUP raise Interrupted in the main thread (run_main reports it)."""
    for signum in _STOP_SIGNALS:
        signal.signal(signum, _on_signal)


def run_main(name, body, errors=(OSError, ValueError)):
    """Run a tool's `body()` (its exit status) with stop_on_signals; an error of `errors` is
    printed as "NAME: error: message" (exit 1, or the error's `status`), a signal as one line
    (exit 128 + signal)."""
    stop_on_signals()
    try:
        return body()
    except Interrupted as stop:
        _pending.remove_all()
        # On a new line, past a progress line that a terminal leaves unfinished.
        print(("\n" if sys.stderr.isatty() else "")
              + f"{name}: interrupted by {signal.Signals(stop.signum).name}; nothing left half "
                "written", file=sys.stderr)
        return 128 + stop.signum
    except errors as error:
        _pending.remove_all()
        print(f"{name}: error: {error}", file=sys.stderr)
        return getattr(error, "status", 1)
