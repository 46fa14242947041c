"""A labelling session on a frames folder (pcd/<stamp>.pcd, detections_3d/<stamp>.json), free
of ROS: which frames can be labelled, their boxes, saving and the backup.

- One session per folder: it holds the lock of FRAMES/labelling_backup/ (a granular output
  folder, output.claimed_folder) while it runs; a second one is refused.
- A folder it cannot write (read-only, a full or read-only file system) is refused at the
  start, before any edit could be lost.
- A frame is a pcd/<stamp>.pcd. Its boxes come from detections_3d/<stamp>.json (none when the
  file is absent), or, with a cuboids folder, from CUBOIDS/<stamp>.json until the tool has
  saved the frame once. A detections file that does not parse is named and its frame skipped:
  the tool never writes it.
- Saving writes detections_3d/<stamp>.json atomically (output.write_atomically). Before the
  first save of a frame, ever, the file as it was goes to labelling_backup/<stamp>.json, or,
  when the frame had none, an empty labelling_backup/<stamp>.json.absent marks that.
"""
import contextlib
import itertools
import os

from ..frames_folder import CLOUDS_FOLDER, DETECTIONS_FOLDER
from ..output import OutputError, absolute, claimed_folder, write_atomically
from .document import DocumentError, FrameLabels, read_document

TOOL = "label_cuboids"
BACKUP_FOLDER = "labelling_backup"
ABSENT_SUFFIX = ".absent"


class SessionError(ValueError):
    """A frames folder that cannot be labelled; the message names it."""


def frame_names(frames):
    """Stamps of FRAMES/pcd/*.pcd, in time order; SessionError when there are none."""
    folder = os.path.join(frames, CLOUDS_FOLDER)
    if not os.path.isdir(frames):
        raise SessionError(f"{frames}: no such folder")
    names = sorted(name[:-4] for name in os.listdir(folder) if name.endswith(".pcd")
                   and not name.startswith(".")) if os.path.isdir(folder) else []
    if not names:
        raise SessionError(f"{frames}: not a frames folder: no {CLOUDS_FOLDER}/*.pcd (make one "
                           "with bag_to_files)")
    # Stamps of equal length sort by time as text; a shorter one is an earlier second.
    return sorted(names, key=lambda name: (len(name), name))


def check_writable(folder):
    """OutputError unless a file can be created in `folder` and removed again: a real write,
    since permissions say nothing of a read-only file system (or to root)."""
    probe = os.path.join(folder, f".{TOOL}.probe-{os.getpid()}")
    try:
        descriptor = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        try:
            os.write(descriptor, b"probe")
            os.fsync(descriptor)
        finally:
            os.close(descriptor)
        os.remove(probe)
    except OSError as error:
        with contextlib.suppress(OSError):
            os.remove(probe)
        raise OutputError(f"{folder}: cannot write there ({error.strerror}); labelling saves "
                          "every change into it, so it does not start") from error


class Session:
    """The frames of one folder and what has been done to them. Use `opened` to hold the lock."""

    def __init__(self, frames, cuboids=None, frame_id="velodyne", min_size=0.1):
        self.frames, self.cuboids = absolute(frames), cuboids and absolute(cuboids)
        self.frame_id, self.min_size = frame_id, min_size
        self.json_folder = os.path.join(self.frames, DETECTIONS_FOLDER)
        self.backup_folder = os.path.join(self.frames, BACKUP_FOLDER)
        self.names, self.skipped = [], {}  # frames to label; stamp -> why a frame is skipped
        # stamp -> FrameLabels; stamp -> the entries its file holds (as read or last saved)
        self._labels, self._saved = {}, {}
        self._keys = (f"box{n}" for n in itertools.count(1))

    @contextlib.contextmanager
    def opened(self):
        """Check the folders, lock the session and find the frames; yields self."""
        names = frame_names(self.frames)
        if self.cuboids and not os.path.isdir(self.cuboids):
            raise SessionError(f"{self.cuboids}: cuboids folder does not exist")
        with claimed_folder(self.backup_folder, TOOL, overwrite=True):
            try:
                os.makedirs(self.json_folder, exist_ok=True)
            except OSError as error:
                raise OutputError(f"{self.json_folder}: cannot create the folder: "
                                  f"{error.strerror}") from error
            check_writable(self.json_folder)
            check_writable(self.backup_folder)
            for name in names:
                try:
                    self.load(name)
                    self.names.append(name)
                except DocumentError as error:
                    self.skipped[name] = str(error)
            if not self.names:
                raise SessionError(f"{self.frames}: no frame can be labelled: "
                                   + "; ".join(self.skipped.values()))
            yield self

    def json_path(self, name):
        return os.path.join(self.json_folder, name + ".json")

    def pcd_path(self, name):
        return os.path.join(self.frames, CLOUDS_FOLDER, name + ".pcd")

    def _backup_path(self, name):
        return os.path.join(self.backup_folder, name + ".json")

    def _labelled_before(self, name):
        backup = self._backup_path(name)
        return os.path.exists(backup) or os.path.exists(backup + ABSENT_SUFFIX)

    def source_path(self, name):
        """The file a frame's boxes start from (see the module)."""
        if self.cuboids and not self._labelled_before(name):
            candidate = os.path.join(self.cuboids, name + ".json")
            if os.path.exists(candidate):
                return candidate
        return self.json_path(name)

    def load(self, name):
        """The frame's FrameLabels, read once per session (its undo history lives there)."""
        if name not in self._labels:
            source = self.source_path(name)
            document = read_document(source, name, self.frame_id, self._keys)
            self._labels[name] = FrameLabels(name, document, self._keys, self.min_size)
            self._saved[name] = document.entries
        return self._labels[name]

    def unsaved(self, name):
        """Whether the frame changed since it was read or saved (undo back to that state
        gives the very same entries, so it is then unchanged)."""
        labels = self._labels.get(name)
        return labels is not None and labels.entries is not self._saved[name]

    def save(self, name):
        """Write the frame's file if it changed since it was read or saved; returns its path
        when written. OutputError (naming the file) when it cannot be written."""
        if not self.unsaved(name):
            return None
        labels = self._labels[name]
        self._back_up(name)
        write_atomically(self.json_path(name), labels.text().encode("utf-8"), "detections JSON")
        self._saved[name] = labels.entries
        return self.json_path(name)

    def _back_up(self, name):
        if self._labelled_before(name):
            return
        backup = self._backup_path(name)
        try:
            with open(self.json_path(name), "rb") as stream:
                original = stream.read()
        except FileNotFoundError:
            write_atomically(backup + ABSENT_SUFFIX, b"", "backup marker")
            return
        except OSError as error:
            raise OutputError(f"{self.json_path(name)}: cannot read it to back it up: "
                              f"{error.strerror}") from error
        write_atomically(backup, original, "backup")
