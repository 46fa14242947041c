"""One frame's detections file (detections_3d/<stamp>.json) as the labelling tool edits it.

Every detection keeps the exact text it had in the file until it is edited, and an edit
changes only the fields it is about (a move the position, a turn the orientation, a face
drag the position and size, a new label the label), so a save leaves the rest of the file,
and every detection the user did not touch, byte for byte as it was.
"""
import copy
import dataclasses
import itertools
import json
from typing import Optional

from ..frames_folder import DetectionsError, parse_detection, stamp_of_name
from ..geometry import Cuboid
from .boxes import drag_distance, edited_by_pose, with_face_dragged

MAX_ID = 2 ** 32 - 1  # Detection3D.id is a uint32


class DocumentError(ValueError):
    """A detections file the tool cannot edit; the message names the file (and the key)."""


def _reject_constant(name):
    raise ValueError(f"{name} is not a JSON number")


_DECODER = json.JSONDecoder(parse_constant=_reject_constant)
_SPACE = " \t\n\r"


def _skip_space(text, index):
    while index < len(text) and text[index] in _SPACE:
        index += 1
    return index


def detection_spans(text):
    """((start, end) of the top-level "detections" array, [(start, end) of each element]) in
    a JSON text already known to be a valid object."""
    index = _skip_space(text, 0) + 1  # past "{"
    found = None
    while True:
        index = _skip_space(text, index)
        if text[index] == "}":
            return found
        key, index = _DECODER.raw_decode(text, index)
        index = _skip_space(text, _skip_space(text, index) + 1)  # past ":"
        if key == "detections":
            start, elements = index, []
            index = _skip_space(text, index + 1)  # past "["
            while text[index] != "]":
                _, end = _DECODER.raw_decode(text, index)
                elements.append((index, end))
                index = _skip_space(text, end)
                if text[index] == ",":
                    index = _skip_space(text, index + 1)
            index += 1
            found = ((start, index), elements)
        else:
            _, index = _DECODER.raw_decode(text, index)
        index = _skip_space(text, index)
        if text[index] == ",":
            index += 1


@dataclasses.dataclass(frozen=True)
class Entry:
    """One detection: `raw` is its text in the file while it is unedited."""
    key: str  # the name of its rviz marker, kept through edits
    detection: dict
    raw: Optional[str]
    box: Optional[Cuboid]  # None when it cannot be drawn (`unusable` says why); kept as it is
    unusable: Optional[str] = None


@dataclasses.dataclass
class Document:
    """A detections file as read: its text (None when there was no file), the document, where
    its detections array lies in the text, and its detections."""
    path: str
    text: Optional[str]
    header: dict
    array_span: Optional[tuple]
    entries: tuple


def empty_header(stamp_name, frame_id):
    """The header of a frame with no detections file: the stamp of its name."""
    secs, nsecs = stamp_of_name(stamp_name)
    return {"stamp": {"secs": secs, "nsecs": nsecs}, "frame_id": frame_id, "seq": 0}


def _entry(key, detection, raw, where):
    if not isinstance(detection, dict):
        raise DocumentError(f"{where}: expected an object, got {detection!r:.40}")
    try:
        parsed, why = parse_detection(detection, where)
    except DetectionsError as error:
        raise DocumentError(str(error)) from error
    return Entry(key, detection, raw, parsed.box if parsed else None, why)


def read_document(path, stamp_name, frame_id, keys, text=None):
    """The Document of `path` (absent: a frame without detections); `keys` yields the marker
    names of its detections. DocumentError when it does not parse or lacks a field."""
    if text is None:
        try:
            with open(path, encoding="utf-8") as stream:
                text = stream.read()
        except FileNotFoundError:
            return Document(path, None, empty_header(stamp_name, frame_id), None, ())
        except UnicodeDecodeError as error:
            raise DocumentError(f"{path}: not a text file ({error.reason})") from error
        except OSError as error:
            raise DocumentError(f"{path}: cannot read: {error.strerror}") from error
    try:
        document = _DECODER.decode(text)
    except ValueError as error:
        raise DocumentError(f"{path}: not valid JSON ({error})") from error
    if not isinstance(document, dict) or not isinstance(document.get("detections"), list):
        raise DocumentError(f"{path}: not a detections file (no 'detections' list)")
    header = document.get("header")
    if not isinstance(header, dict):
        header = empty_header(stamp_name, frame_id)
    array_span, spans = detection_spans(text)
    entries = tuple(_entry(next(keys), detection, text[start:end], f"{path}: detections[{k}]")
                    for k, (detection, (start, end)) in
                    enumerate(zip(document["detections"], spans)))
    return Document(path, text, header, array_span, entries)


def render(document, entries):
    """The file's text with `entries` as its detections: the original text where nothing
    changed, else the original around the detections array and each unedited detection's own
    text inside it (a new file: the layout bag_to_files writes)."""
    if document.text is None:
        return json.dumps({"header": document.header,
                           "detections": [e.detection for e in entries]}, allow_nan=False)
    if tuple(e.raw for e in entries) == tuple(e.raw for e in document.entries) and \
            all(e.raw is not None for e in entries):
        return document.text
    items = [e.raw if e.raw is not None else json.dumps(e.detection, allow_nan=False)
             for e in entries]
    start, end = document.array_span
    return document.text[:start] + "[" + ", ".join(items) + "]" + document.text[end:]


def _with_box(entry, box):
    """`entry` with its detection's pose and size fields set from `box`, only those changed."""
    detection = copy.deepcopy(entry.detection)
    bbox = detection["bbox"]
    if box.centre != entry.box.centre:
        bbox["position"]["position"] = dict(zip("xyz", box.centre))
    if box.quaternion != entry.box.quaternion:
        bbox["position"]["orientation"] = dict(zip("xyzw", box.quaternion))
    if box.size != entry.box.size:
        bbox["size"] = dict(zip("xyz", box.size))
    return dataclasses.replace(entry, detection=detection, raw=None, box=box)


class FrameLabels:
    """A frame's detections as edited, with an undo history. Each method that edits returns
    True when something changed. Between begin_gesture and end_gesture (one mouse drag) the
    changes undo as one."""

    def __init__(self, name, document, keys, min_size):
        self.name, self.document = name, document
        self.entries = document.entries
        self._keys, self._min_size = keys, min_size
        self._history = []
        self._in_gesture = self._gesture_recorded = False

    def find(self, key):
        return next((e for e in self.entries if e.key == key), None)

    def boxes(self):
        return [e for e in self.entries if e.box is not None]

    def text(self):
        return render(self.document, self.entries)

    def begin_gesture(self):
        self._in_gesture, self._gesture_recorded = True, False

    def end_gesture(self):
        self._in_gesture = False

    def can_undo(self):
        return bool(self._history)

    def undo(self):
        if not self._history:
            return False
        self.entries = self._history.pop()
        return True

    def _change(self, entries):
        if not (self._in_gesture and self._gesture_recorded):
            self._history.append(self.entries)
            self._gesture_recorded = self._in_gesture
        self.entries = tuple(entries)
        return True

    def _replace(self, key, new_entry):
        return self._change(new_entry if e.key == key else e for e in self.entries)

    def move_to_pose(self, key, position, quaternion):
        """The box `key` after rviz put its marker at `position`, `quaternion`: moved in the
        ground plane and turned about the vertical."""
        entry = self.find(key)
        box = edited_by_pose(entry.box, position, quaternion) if entry and entry.box else None
        return box is not None and self._replace(key, _with_box(entry, box))

    def drag_face(self, key, face, handle_position):
        """The box `key` with `face` moved to the handle at `handle_position`, along its
        normal; the opposite face stays put."""
        entry = self.find(key)
        if entry is None or entry.box is None:
            return False
        box, moved_by = with_face_dragged(entry.box, face,
                                          drag_distance(entry.box, face, handle_position),
                                          self._min_size)
        return abs(moved_by) >= 1e-4 and self._replace(key, _with_box(entry, box))

    def set_label(self, key, label):
        entry = self.find(key)
        if entry is None or entry.detection.get("label") == label:
            return False
        detection = copy.deepcopy(entry.detection)
        detection["label"] = label
        return self._replace(key, dataclasses.replace(entry, detection=detection, raw=None))

    def delete(self, key):
        if self.find(key) is None:
            return False
        return self._change(e for e in self.entries if e.key != key)

    def new_detection(self, label, box, detection_id, score=1.0):
        """(detection, box) of a new detection in this frame: the frame's header, no velocity."""
        detection = {
            "header": copy.deepcopy(self.document.header), "id": detection_id, "label": label,
            "score": score,
            "bbox": {"position": {"position": dict(zip("xyz", box.centre)),
                                  "orientation": dict(zip("xyzw", box.quaternion))},
                     "size": dict(zip("xyz", box.size))},
            "velocity": {"linear": {"x": 0.0, "y": 0.0, "z": 0.0},
                         "angular": {"x": 0.0, "y": 0.0, "z": 0.0}},
        }
        return detection, box

    def add(self, label, box):
        """A new detection of `label` with `box`; returns its key. Its id is one more than the
        frame's largest (KITTI frames' ids stay frame * 1000 + n)."""
        used = {e.detection.get("id") for e in self.entries}
        new_id = max((i for i in used if isinstance(i, int) and not isinstance(i, bool)),
                     default=-1) + 1
        if new_id > MAX_ID:
            new_id = next(i for i in itertools.count() if i not in used)
        detection, _ = self.new_detection(label, box, new_id)
        key = next(self._keys)
        self._change(self.entries + (Entry(key, detection, None, box),))
        return key

    def replace(self, detections):
        """Every detection replaced by `detections`, [(detection, box)] (an import)."""
        return self._change(Entry(next(self._keys), detection, None, box)
                            for detection, box in detections)
