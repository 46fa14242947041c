"""KITTI object-detection conventions in one place, and kitti_to_bag. (Over 400 lines: every
KITTI convention, reading and converting, lives here so that no other file restates one.)

Frames (docs/kitti.md):
- LiDAR (Velodyne): x forward, y left, z up; velodyne/NNNNNN.bin holds float32 x y z
  reflectance (0..1).
- Rectified camera: x right, y down, z forward; label_2 boxes and planes/ live there.
- LiDAR -> rectified camera is R0_rect * Tr_velo_to_cam. Its 3x3 part is a rotation only to the
  7 digits the calibration files print (singular values 1 +- 5e-8), so points and boxes move
  between the frames with its closest rotation (polar decomposition, U V^T of the SVD) and its
  translation: a rigid transform, under which a box stays a box with a unit quaternion.

A label_2 box: dimensions h w l, location = the centre of its bottom face, rotation_y about the
camera's y axis (0: length along the camera's x). As a LiDAR box: centre = bottom centre raised
by h/2 along the box's up axis (camera -y); axes: length, width (left), height (up); size l w h.
"""
import argparse
import dataclasses
import math
import os
import sys
import time
from typing import Optional

import numpy as np

from .geometry import quaternion_from_matrix, rotation_matrix
from .output import check_output_apart, run_main, written_atomically

VELODYNE, LABELS, CALIB, PLANES = "velodyne", "label_2", "calib", "planes"
DONT_CARE = "DontCare"  # regions without a 3D box
FRAME_PERIOD = 0.1  # s: the HDL-64E turns at 10 Hz
ID_STRIDE = 1000  # detection id = frame number * ID_STRIDE + label line
# The largest frame number whose detection ids (frame * ID_STRIDE + line) fit a uint32.
MAX_FRAME = (0xFFFFFFFF - (ID_STRIDE - 1)) // ID_STRIDE
# --frames may ask for at most this many frames (KITTI's object benchmark has 7,481 training
# and 7,518 test frames): a range is counted before it is listed.
MAX_SELECTED_FRAMES = 100_000
CLOUD_TOPIC = "/simulator/lidar"
DETECTIONS_TOPIC = "/simulator/ground_truth/3d_detections"
DEFAULT_START_TIME = 1586102742.0  # s since the epoch, as the simulator's default
ROS_TIME_END = 2 ** 32  # s: ROS stamps count seconds in a uint32


def is_frame_number(text):
    """Whether `text` is a frame number as KITTI writes them: ASCII digits ("²" is a digit to
    str.isdigit, and no number to int)."""
    return text.isascii() and text.isdigit()


def valid_start_time(seconds):
    """Whether `seconds` can stamp a ROS message: finite, from 0 to 2^32 s."""
    return math.isfinite(seconds) and 0.0 <= seconds < ROS_TIME_END
# KITTI tracking calibration files spell two of the keys differently.
_CALIB_KEYS = {"P2": ("P2",), "R0_rect": ("R0_rect", "R_rect"),
               "Tr_velo_to_cam": ("Tr_velo_to_cam", "Tr_velo_cam")}


class KittiError(ValueError):
    """Bad KITTI input; the message names the file (and line). kitti_to_bag exits 2."""
    status = 2


def _read_text(path):
    """The text of `path`; a missing file is a KittiError, another failure an OSError (exit 1)."""
    try:
        with open(path, encoding="utf-8") as stream:
            return stream.read()
    except FileNotFoundError as error:
        raise KittiError(f"{path}: no such file") from error
    except UnicodeDecodeError as error:
        raise KittiError(f"{path}: not a text file ({error.reason})") from error
    except OSError as error:
        raise OSError(f"{path}: cannot read: {error.strerror or error}") from error


# ---------------------------------------------------------------------------------------------
# Calibration and rotations

def closest_rotation(matrix):
    """The rotation nearest `matrix` (3x3) in the Frobenius norm: U V^T of its SVD."""
    u, _, vt = np.linalg.svd(np.asarray(matrix, float))
    if np.linalg.det(u @ vt) < 0.0:
        u[:, -1] = -u[:, -1]
    return u @ vt


@dataclasses.dataclass(frozen=True, eq=False)
class Calibration:
    """One frame's calib/NNNNNN.txt: P2 (3x4), R0_rect (3x3), Tr_velo_to_cam (3x4)."""
    p2: np.ndarray
    r0_rect: np.ndarray
    tr_velo_to_cam: np.ndarray

    def velo_to_rect(self):
        """KITTI's LiDAR -> rectified camera map (A, t), p_rect = A p_velo + t, A not quite a
        rotation."""
        return self.r0_rect @ self.tr_velo_to_cam[:, :3], self.r0_rect @ self.tr_velo_to_cam[:, 3]

    def rigid_velo_to_rect(self):
        """(R, t): the closest rotation to velo_to_rect's A, and its translation."""
        linear, translation = self.velo_to_rect()
        return closest_rotation(linear), translation

    def to_rect(self, points):
        """LiDAR points (N, 3) or (3,) in the rectified camera frame (rigid)."""
        rotation, translation = self.rigid_velo_to_rect()
        return np.asarray(points, float) @ rotation.T + translation

    def to_velo(self, points):
        """Rectified camera points (N, 3) or (3,) in the LiDAR frame (rigid)."""
        rotation, translation = self.rigid_velo_to_rect()
        return (np.asarray(points, float) - translation) @ rotation


def read_calib(path):
    values = {}
    for number, line in enumerate(_read_text(path).splitlines(), 1):
        key, sep, numbers = line.partition(":")
        if not sep:
            continue
        try:
            values[key.strip()] = np.array([float(x) for x in numbers.split()])
        except ValueError as error:
            raise KittiError(f"{path} line {number}: {key.strip()}: not numbers") from error
    matrices = {}
    for name, shape in (("P2", (3, 4)), ("R0_rect", (3, 3)), ("Tr_velo_to_cam", (3, 4))):
        key = next((k for k in _CALIB_KEYS[name] if k in values), None)
        if key is None:
            raise KittiError(f"{path}: no {name} (keys: {', '.join(values) or 'none'})")
        if values[key].size != shape[0] * shape[1] or not np.all(np.isfinite(values[key])):
            raise KittiError(f"{path}: {key} must be {shape[0] * shape[1]} finite numbers, "
                             f"got {values[key].size}")
        matrices[name] = values[key].reshape(shape)
    if np.linalg.det(matrices["R0_rect"] @ matrices["Tr_velo_to_cam"][:, :3]) <= 0.0:
        raise KittiError(f"{path}: R0_rect * Tr_velo_to_cam is not a rotation (determinant <= 0)")
    return Calibration(matrices["P2"], matrices["R0_rect"], matrices["Tr_velo_to_cam"])


# ---------------------------------------------------------------------------------------------
# Clouds, labels, boxes, planes

def read_velodyne(path):
    """(N, 4) float32: x y z (m, LiDAR frame) and reflectance (0..1)."""
    try:
        raw = np.fromfile(path, dtype="<f4")
    except FileNotFoundError as error:
        raise KittiError(f"{path}: no such file") from error
    except OSError as error:
        raise OSError(f"{path}: cannot read: {error.strerror or error}") from error
    if raw.size % 4:
        raise KittiError(f"{path}: {raw.size * 4} bytes is not a whole number of points "
                         "(16 bytes each: float32 x y z reflectance)")
    return raw.reshape(-1, 4)


def intensity_of(reflectance):
    """Reflectance 0..1 as the simulator's uint8 intensity 0..255 (rounded, clamped)."""
    scaled = np.nan_to_num(np.asarray(reflectance, float) * 255.0, nan=0.0)
    return np.clip(np.rint(scaled), 0, 255).astype(np.uint8)


@dataclasses.dataclass(frozen=True)
class Label:
    """One line of label_2 (the KITTI devkit's readme names the fields)."""
    type: str
    truncated: float
    occluded: int
    alpha: float  # observation angle, rad
    bbox: tuple  # 2-D box in the image of P2: left, top, right, bottom, pixels
    dimensions: tuple  # h, w, l, m
    location: tuple  # x, y, z of the bottom face's centre, rectified camera frame, m
    rotation_y: float  # rad about the camera's y axis; 0: length along the camera's x
    score: Optional[float] = None  # only in detectors' results


def parse_label(line, where="label"):
    """The Label of one label_2 line; `where` ("label_2/000001.txt line 3") names it in errors."""
    fields = line.split()
    if len(fields) not in (15, 16):
        raise KittiError(f"{where}: expected 15 fields (16 with a score), got {len(fields)}: "
                         f"{line.strip()!r}")
    try:
        numbers = [float(x) for x in fields[1:2] + fields[3:]]
        occluded = int(fields[2])
    except ValueError as error:
        raise KittiError(f"{where}: {error}: {line.strip()!r}") from error
    if not all(math.isfinite(x) for x in numbers):
        raise KittiError(f"{where}: a number is not finite: {line.strip()!r}")
    label = Label(fields[0], numbers[0], occluded, numbers[1], tuple(numbers[2:6]),
                  tuple(numbers[6:9]), tuple(numbers[9:12]), numbers[12],
                  numbers[13] if len(numbers) == 14 else None)
    if label.type != DONT_CARE and min(label.dimensions) <= 0.0:
        raise KittiError(f"{where}: dimensions h w l must be positive, got "
                         f"{' '.join(fields[8:11])}")
    return label


def read_labels(path):
    """[(line index from 0, Label)] of a label_2 file, blank lines skipped, DontCare kept."""
    labels = []
    for index, line in enumerate(_read_text(path).splitlines()):
        if line.strip():
            labels.append((index, parse_label(line, f"{path} line {index + 1}")))
    return labels


def _format_number(value, decimals):
    return f"{round(value, decimals) + 0.0:.{decimals}f}"  # + 0.0: no "-0.00"


def format_label(label, decimals=2):
    """A label_2 line, numbers with `decimals` decimals (KITTI's files have 2)."""
    numbers = [label.alpha, *label.bbox, *label.dimensions, *label.location, label.rotation_y]
    fields = [label.type, _format_number(label.truncated, decimals), str(label.occluded)]
    fields += [_format_number(x, decimals) for x in numbers]
    if label.score is not None:
        fields.append(_format_number(label.score, max(decimals, 4)))
    return " ".join(fields)


@dataclasses.dataclass(frozen=True, eq=False)
class Box:
    """An oriented box in the LiDAR frame: `rotation`'s columns are its length, width (left)
    and height (up) axes; `size` is (l, w, h), m."""
    centre: np.ndarray
    rotation: np.ndarray
    size: tuple

    @property
    def quaternion(self):
        return quaternion_from_matrix(self.rotation)

    @classmethod
    def from_pose(cls, centre, quaternion, size):
        unit = np.asarray(quaternion, float) / np.linalg.norm(quaternion)
        return cls(np.asarray(centre, float), rotation_matrix(unit), tuple(size))


def _axes_in_rect(rotation_y):
    """Length, width (left), height (up) axes of a label's box in the rectified camera frame."""
    c, s = math.cos(rotation_y), math.sin(rotation_y)
    length, up = np.array([c, 0.0, -s]), np.array([0.0, -1.0, 0.0])
    return np.column_stack([length, np.cross(up, length), up])


def label_to_box(label, calib):
    """The LiDAR-frame Box of a label (not DontCare)."""
    if label.type == DONT_CARE:
        raise ValueError("a DontCare label has no 3D box")
    height, width, length = label.dimensions
    rotation, _ = calib.rigid_velo_to_rect()
    axes = _axes_in_rect(label.rotation_y)
    centre_rect = np.asarray(label.location, float) + axes[:, 2] * height / 2.0
    return Box(calib.to_velo(centre_rect), rotation.T @ axes, (length, width, height))


def _wrap(angle):
    """`angle` in [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def box_corners(box):
    """The 8 corners (8, 3) of a Box, in the frame of its centre (LiDAR)."""
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
    return box.centre + (signs * np.asarray(box.size) / 2.0) @ box.rotation.T


def image_box(box, calib):
    """The 2-D box (left, top, right, bottom; pixels) of a Box's corners projected with P2, not
    clipped to the image (whose size the calibration does not give); (-1, -1, -1, -1) when a
    corner is behind the camera."""
    corners = calib.to_rect(box_corners(box))
    if np.any(corners[:, 2] <= 0.0):
        return (-1.0, -1.0, -1.0, -1.0)
    projected = np.c_[corners, np.ones(8)] @ calib.p2.T
    pixels = projected[:, :2] / projected[:, 2:]
    return tuple(float(v) for v in (*pixels.min(axis=0), *pixels.max(axis=0)))


def box_to_label(box, calib, label_type, truncated=-1.0, occluded=-1, alpha=None, bbox=None,
                 score=None):
    """The Label of a LiDAR-frame Box. KITTI boxes turn about the camera's y axis only: a box
    tilted from it keeps its bottom centre and the heading of its length axis. Unknown
    truncation and occlusion are -1, as in KITTI's results format; alpha defaults to
    rotation_y - atan2(x, z) of the location, bbox to image_box."""
    rotation, _ = calib.rigid_velo_to_rect()
    axes = rotation @ box.rotation
    length, width, height = box.size
    bottom = calib.to_rect(box.centre - box.rotation[:, 2] * height / 2.0)
    rotation_y = _wrap(math.atan2(-axes[2, 0], axes[0, 0]))
    if alpha is None:
        alpha = _wrap(rotation_y - math.atan2(bottom[0], bottom[2]))
    return Label(label_type, float(truncated), int(occluded), float(alpha),
                 tuple(bbox) if bbox is not None else image_box(box, calib),
                 (float(height), float(width), float(length)), tuple(float(v) for v in bottom),
                 rotation_y, score)


def read_plane(path):
    """(a, b, c, d) of planes/NNNNNN.txt: a x + b y + c z + d = 0, rectified camera frame."""
    text = _read_text(path)
    rows = [line for line in text.splitlines() if line.strip() and not line.startswith("#")
            and not line.split()[0] in ("WIDTH", "HEIGHT")]
    try:
        plane = [float(x) for x in rows[-1].split()] if rows else []
    except ValueError as error:
        raise KittiError(f"{path}: the plane is not numbers: {rows[-1]!r}") from error
    if len(plane) != 4 or not all(map(math.isfinite, plane)) or not any(plane[:3]):
        raise KittiError(f"{path}: expected a plane a b c d, got "
                         + (repr(rows[-1]) if rows else "nothing"))
    return tuple(plane)


def plane_to_velo(plane, calib):
    """The road plane in the LiDAR frame: (n, d), n a unit normal pointing up (n_z > 0), so
    that n . p + d = 0 on the road and d is the sensor's height above it."""
    rotation, translation = calib.rigid_velo_to_rect()
    normal_rect = np.asarray(plane[:3], float)
    normal, offset = rotation.T @ normal_rect, normal_rect @ translation + plane[3]
    scale = np.linalg.norm(normal) * (1.0 if normal[2] >= 0.0 else -1.0)
    return normal / scale, float(offset / scale)


# ---------------------------------------------------------------------------------------------
# kitti_to_bag

def parse_frames(text):
    """Frame numbers of "000000-000004", "0,3,8" or "0-2,8" (sorted, unique)."""
    ranges = []
    for item in text.split(","):
        first, sep, last = item.strip().partition("-")
        if not (is_frame_number(first) and (not sep or is_frame_number(last))):
            raise argparse.ArgumentTypeError(
                f"'{text}': expected frame numbers and ranges, e.g. 000000-000004 or 0,3,8")
        low, high = int(first), int(last if sep else first)
        if high < low:
            raise argparse.ArgumentTypeError(f"'{item}': a range runs from low to high")
        if high > MAX_FRAME:
            raise argparse.ArgumentTypeError(
                f"'{item}': frame numbers go up to {MAX_FRAME} (detection ids are frame * "
                f"{ID_STRIDE} + line, a uint32)")
        ranges.append((low, high))
    # Counted on the merged ranges before any is listed.
    ranges.sort()
    merged = [list(ranges[0])]
    for low, high in ranges[1:]:
        if low <= merged[-1][1] + 1:
            merged[-1][1] = max(merged[-1][1], high)
        else:
            merged.append([low, high])
    count = sum(high - low + 1 for low, high in merged)
    if count > MAX_SELECTED_FRAMES:
        raise argparse.ArgumentTypeError(
            f"'{text}': {count} frames; at most {MAX_SELECTED_FRAMES} at once")
    return [n for low, high in merged for n in range(low, high + 1)]


def list_frames(folder):
    """{frame number: name stem} of KITTI/velodyne/*.bin."""
    velodyne = os.path.join(folder, VELODYNE)
    if not os.path.isdir(folder):
        raise KittiError(f"{folder}: no such folder")
    if not os.path.isdir(velodyne):
        raise KittiError(f"{folder}: no {VELODYNE}/ folder (a KITTI object-detection folder "
                         f"holds {VELODYNE}/, {LABELS}/ and {CALIB}/)")
    frames = {}
    for name in sorted(os.listdir(velodyne)):
        stem, extension = os.path.splitext(name)
        if extension != ".bin":
            continue
        if not is_frame_number(stem):
            raise KittiError(f"{os.path.join(velodyne, name)}: not a KITTI frame name "
                             "(digits, e.g. 000008.bin)")
        number = int(stem)
        if number in frames:
            raise KittiError(f"{velodyne}: {frames[number]}.bin and {name} are both frame "
                             f"{number}")
        if number * ID_STRIDE + ID_STRIDE - 1 > 0xFFFFFFFF:
            raise KittiError(f"{os.path.join(velodyne, name)}: frame number too large for a "
                             "uint32 detection id (frame * 1000 + line)")
        frames[number] = stem
    if not frames:
        raise KittiError(f"{velodyne}: no .bin files")
    return frames


@dataclasses.dataclass
class Frame:
    number: int
    stem: str
    boxes: list  # [(detection id, label type, Box)]


def load_frames(folder, wanted=None, boxes=True):
    """The selected frames with their boxes, every calib and label read and checked before a
    cloud is: a bad input stops the run before anything is written."""
    available = list_frames(folder)
    if wanted is not None:
        missing = [n for n in wanted if n not in available]
        if missing:
            shown = ", ".join(f"{n:06d}" for n in missing[:5]) + (" ..." if len(missing) > 5
                                                                  else "")
            raise KittiError(f"{os.path.join(folder, VELODYNE)}: no frame {shown} "
                             f"({len(missing)} of the {len(wanted)} asked for)")
    numbers = sorted(available if wanted is None else wanted, key=available.get)
    if boxes:
        for sub in (CALIB, LABELS):
            if not os.path.isdir(os.path.join(folder, sub)):
                raise KittiError(f"{folder}: no {sub}/ folder (pass --no-boxes to write the "
                                 "clouds only)")
    frames = []
    for number in numbers:
        stem = available[number]
        frame = Frame(number, stem, [])
        if boxes:
            calib = read_calib(os.path.join(folder, CALIB, stem + ".txt"))
            for line, label in read_labels(os.path.join(folder, LABELS, stem + ".txt")):
                if line >= ID_STRIDE:
                    raise KittiError(f"{os.path.join(folder, LABELS, stem + '.txt')}: more "
                                     f"than {ID_STRIDE} lines; ids are frame * {ID_STRIDE} + "
                                     "line")
                if label.type != DONT_CARE:
                    frame.boxes.append((number * ID_STRIDE + line, label.type,
                                        label_to_box(label, calib)))
        frames.append(frame)
    return frames


def write_bag(folder, frames, path, start_time, frame_id, boxes=True, progress=None):
    """Each frame's cloud (and with `boxes` its detections) at start_time + k / 10 s; the bag
    appears under `path` only when complete. Returns ({label: boxes written}, [a line for each
    velodyne file without a finite point, which the box-free tools find no ground in])."""
    import rosbag  # ROS imports only once the input is known good.
    from .messages import LabelledBox, cloud_message, detections_message, ros_time

    counts, pointless = {}, []
    with written_atomically(path, "bag") as partial:
        try:
            with rosbag.Bag(partial, "w") as bag:
                for k, frame in enumerate(frames):
                    stamp = ros_time(start_time, k * FRAME_PERIOD)
                    cloud = os.path.join(folder, VELODYNE, frame.stem + ".bin")
                    points = read_velodyne(cloud)
                    if not np.isfinite(points[:, :3]).all(axis=1).any():
                        pointless.append(f"{cloud}: no points" if len(points) == 0 else
                                         f"{cloud}: all {len(points)} points are NaN or infinite")
                    bag.write(CLOUD_TOPIC, cloud_message(points[:, :3], intensity_of(points[:, 3]),
                                                         stamp, frame_id, k), stamp)
                    if boxes:
                        detections = [LabelledBox(i, label, box.centre, box.quaternion, box.size)
                                      for i, label, box in frame.boxes]
                        bag.write(DETECTIONS_TOPIC,
                                  detections_message(detections, stamp, frame_id, k), stamp)
                        for _, label, _ in frame.boxes:
                            counts[label] = counts.get(label, 0) + 1
                    if progress is not None:
                        progress(k + 1, len(frames))
        except rosbag.ROSBagException as error:
            raise OSError(f"{path}: cannot write bag: {error}") from error
    return counts, pointless


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog="kitti_to_bag",
        description="Write a KITTI object-detection folder (velodyne/NNNNNN.bin, label_2/, "
                    "calib/) as one rosbag in the layout simulate_drive writes: "
                    f"sensor_msgs/PointCloud2 on {CLOUD_TOPIC} (x y z float32, intensity uint8 "
                    "= reflectance * 255, timestamp float64) and lgsvl_msgs/Detection3DArray on "
                    f"{DETECTIONS_TOPIC}, both stamped start time + k / 10 s for the k-th frame "
                    "in file-name order. Boxes are the label_2 boxes moved into the LiDAR frame "
                    "with the closest rotation to R0_rect * Tr_velo_to_cam, labelled with "
                    "KITTI's class as written (DontCare lines skipped: they have no 3D box), id "
                    "= frame number * 1000 + label line (from 0), score 1.",
        epilog="Every calib and label file is checked before the bag is written; the bag is "
               "written beside its name and renamed when complete. Exit status: 0 done, 1 I/O "
               "failure, 2 bad option or bad input (a missing folder, a frame without calib or "
               "labels, a malformed label line: the file and line are named), 130/143 "
               "interrupted (nothing left half written). See docs/kitti.md.")
    parser.add_argument("folder", metavar="KITTI_DIR",
                        help="folder holding velodyne/, label_2/ and calib/ (e.g. "
                             "training/ of the object benchmark)")
    parser.add_argument("--out", required=True, metavar="FILE.bag", help="bag to write")
    parser.add_argument("--frames", type=parse_frames, metavar="LIST",
                        help="frames to convert: numbers and ranges, e.g. 000000-000004 or "
                             "0,3,8 (default: every velodyne/*.bin)")
    parser.add_argument("--start-time", type=float, default=DEFAULT_START_TIME,
                        metavar="SECONDS", help="stamp of the first frame, s since the epoch "
                                                "(default: %(default).0f)")
    parser.add_argument("--frame-id", default="velodyne",
                        help="frame_id of the clouds and boxes (default: %(default)s)")
    parser.add_argument("--no-boxes", action="store_true",
                        help=f"clouds only: no {DETECTIONS_TOPIC} topic; label_2/ and calib/ "
                             "are then not read")
    parser.add_argument("--quiet", action="store_true", help="no progress or summary")
    args = parser.parse_args(argv)
    if not valid_start_time(args.start_time):
        parser.error(f"--start-time must be between 0 and 2^32 s, got {args.start_time}")
    if not args.frame_id.strip():
        parser.error("--frame-id must not be empty")
    if not args.out.strip():
        parser.error("--out must name the bag to write")
    return args


def convert(args):
    from . import progress

    started = time.monotonic()
    frames = load_frames(args.folder, args.frames, boxes=not args.no_boxes)
    last_stamp = args.start_time + (len(frames) - 1) * FRAME_PERIOD
    if last_stamp >= ROS_TIME_END:
        raise KittiError(f"--start-time {args.start_time:.1f}: the last of {len(frames)} frames "
                         f"would be stamped {last_stamp:.1f} s, past ROS time's 2^32 s")
    read = [os.path.join(args.folder, VELODYNE, frame.stem + ".bin") for frame in frames]
    if not args.no_boxes:
        read += [os.path.join(args.folder, sub, frame.stem + ".txt") for frame in frames
                 for sub in (CALIB, LABELS)]
    check_output_apart(args.out, read, KittiError)
    reporter = None if args.quiet else progress.Reporter("kitti to bag", unit="frames")
    counts, pointless = write_bag(args.folder, frames, args.out, args.start_time, args.frame_id,
                                  boxes=not args.no_boxes, progress=reporter)
    if reporter:
        reporter.finish()
    for line in pointless:  # written as they are, but the user must know
        print(f"kitti_to_bag: warning: {line}", file=sys.stderr)
    if not args.quiet:
        boxes = "no boxes" if args.no_boxes else \
            f"{sum(counts.values())} boxes (" + \
            (", ".join(f"{k} {v}" for k, v in sorted(counts.items())) or "none") + ")"
        print(f"kitti_to_bag: wrote {args.out}: {len(frames)} frames, {boxes} "
              f"({time.monotonic() - started:.1f} s)")
    return 0


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    return run_main("kitti_to_bag", lambda: convert(args))
