"""A frames folder, as bag_to_files writes it and every later tool reads it: pcd/<stamp>.pcd and
detections_3d/<stamp>.json, <stamp> the cloud's ROS time (seconds, then nanoseconds in nine
digits, so that names sort by time). The detections JSON is the report's layout (section
4.1.2): written by detections_to_dict, read by load_document, its boxes by parse_detection.
"""
import collections
import dataclasses
import json
import math
import os

from .geometry import Cuboid

CLOUDS_FOLDER, DETECTIONS_FOLDER = "pcd", "detections_3d"


class DetectionsError(ValueError):
    """A frames folder or detections file that cannot be read; the message names it."""


def stamp_name(stamp):
    """File stem for a ROS time: seconds then 9-digit nanoseconds, so names sort by time."""
    return f"{stamp.secs}{stamp.nsecs:09d}"


def stamp_of_name(name):
    """(secs, nsecs) of a stamp_name."""
    return int(name[:-9] or 0), int(name[-9:])


def _xyz(vector):
    return {"x": vector.x, "y": vector.y, "z": vector.z}


def _header(header):
    return {"stamp": {"secs": header.stamp.secs, "nsecs": header.stamp.nsecs},
            "frame_id": header.frame_id, "seq": header.seq}


def detections_to_dict(message):
    """A Detection3DArray as the report's JSON (section 4.1.2)."""
    detections = []
    for detection in message.detections:
        pose = detection.bbox.position
        detections.append({
            "header": _header(detection.header),
            "id": detection.id,
            "label": detection.label,
            "score": detection.score,
            "bbox": {"position": {"position": _xyz(pose.position),
                                  "orientation": {**_xyz(pose.orientation),
                                                  "w": pose.orientation.w}},
                     "size": _xyz(detection.bbox.size)},
            "velocity": {"linear": _xyz(detection.velocity.linear),
                         "angular": _xyz(detection.velocity.angular)},
        })
    return {"header": _header(message.header), "detections": detections}


@dataclasses.dataclass
class Detection:
    id: object
    label: str
    score: float
    box: Cuboid


def detections_folder(path, role):
    """(folder of <stamp>.json, folder of <stamp>.pcd or None) for a frames or JSON folder."""
    if not os.path.isdir(path):
        raise DetectionsError(f"{path}: {role} folder does not exist"
                              if not os.path.exists(path) else f"{path}: {role} is not a folder")
    inner = os.path.join(path, DETECTIONS_FOLDER)
    if os.path.isdir(inner):
        clouds = os.path.join(path, CLOUDS_FOLDER)
        return inner, clouds if os.path.isdir(clouds) else None
    return path, None


def frame_files(folder):
    """{stamp: path} of the folder's <stamp>.json; hidden files (the manifest) are not frames."""
    return {name[:-5]: os.path.join(folder, name) for name in sorted(os.listdir(folder))
            if name.endswith(".json") and not name.startswith(".")}


def _number(mapping, key, where):
    if key not in mapping:
        raise DetectionsError(f"{where}.{key}: missing")
    value = mapping[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DetectionsError(f"{where}.{key}: expected a number, got {value!r}")
    return float(value)


def _section(mapping, key, where):
    if not isinstance(mapping, dict) or not isinstance(mapping.get(key), dict):
        raise DetectionsError(f"{where}.{key}: missing or not an object")
    return mapping[key]


def parse_detection(entry, where):
    """(Detection, None) or (None, why it is skipped); raises DetectionsError on a malformed
    one."""
    bbox = _section(entry, "bbox", where)
    pose = _section(bbox, "position", f"{where}.bbox")
    position = _section(pose, "position", f"{where}.bbox.position")
    orientation = _section(pose, "orientation", f"{where}.bbox.position")
    size = _section(bbox, "size", f"{where}.bbox")
    centre = tuple(_number(position, a, f"{where}.bbox.position.position") for a in "xyz")
    quaternion = tuple(_number(orientation, a, f"{where}.bbox.position.orientation")
                       for a in "xyzw")
    extent = tuple(_number(size, a, f"{where}.bbox.size") for a in "xyz")
    label = entry.get("label", "")
    if not isinstance(label, str):
        raise DetectionsError(f"{where}.label: expected a string, got {label!r}")
    score = entry.get("score", 1.0)
    score = float(score) if isinstance(score, (int, float)) and not isinstance(score, bool) \
        else None
    if not all(math.isfinite(v) for v in centre + quaternion + extent):
        return None, "a box with NaN or infinite numbers"
    if min(extent) <= 0:
        return None, "a box with a zero or negative size"
    norm = math.sqrt(sum(v * v for v in quaternion))
    if norm < 1e-9:
        return None, "a box with a zero quaternion"
    quaternion = tuple(v / norm for v in quaternion)
    return Detection(entry.get("id"), label, score, Cuboid(centre, extent, quaternion)), None


def load_document(path):
    """The JSON document of one <stamp>.json, checked to hold a 'detections' list."""
    try:
        with open(path, encoding="utf-8") as stream:
            document = json.load(stream)
    except OSError as error:
        raise DetectionsError(f"{path}: cannot read: {error.strerror}") from error
    except ValueError as error:  # UnicodeDecodeError too
        raise DetectionsError(f"{path}: not valid JSON ({error})") from error
    except RecursionError as error:
        raise DetectionsError(f"{path}: not a detections file (nested too deeply to read)") \
            from error
    if not isinstance(document, dict) or not isinstance(document.get("detections"), list):
        raise DetectionsError(f"{path}: not a detections file (no 'detections' list)")
    return document


def load_detections(path):
    """(detections, Counter of skip reasons) of one <stamp>.json."""
    detections, skipped = [], collections.Counter()
    for k, entry in enumerate(load_document(path)["detections"]):
        detection, why = parse_detection(entry, f"{path}: detections[{k}]")
        if detection is None:
            skipped[why] += 1
        else:
            detections.append(detection)
    return detections, skipped
