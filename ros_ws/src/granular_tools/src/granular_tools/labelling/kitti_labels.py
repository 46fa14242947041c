"""kitti_labels: a frames folder's boxes as KITTI label_2 text files, and back (see --help and
docs/labelling.md).

Which label file is which frame:
- With --calib (a KITTI calib/ folder, or a KITTI folder holding one): the frames are KITTI
  frames as kitti_to_bag stamped them: the k-th calib file in name order (of those --frames
  selects) is the frame stamped --start-time + k * 0.1 s; its label file is named like its
  calib file (000008.txt) and holds the boxes in the rectified camera frame (kitti.py).
- Without: one label file per frame, <stamp>.txt, in the "LiDAR camera" convention: the
  camera frame is the LiDAR frame with KITTI's camera axes, x = -y_lidar (right), y = -z_lidar
  (down), z = x_lidar (forward), at the sensor; so rotation_y = -yaw - pi/2, the location is the
  bottom centre (-y, -z + h/2, x) of a box centred at (x, y, z), and the 2-D box, which needs an
  image, is -1 -1 -1 -1.
Labels are free text; in a label file a label is written in the pipeline's file-name encoding
(labels.py: "Medium-sized Truck" is Medium%2Dsized%20Truck), which KITTI's own classes pass
unchanged, and read back through it.
"""
import argparse
import collections
import itertools
import os
import sys

import numpy as np

from .. import kitti
from ..frames_folder import DETECTIONS_FOLDER, stamp_name
from ..geometry import Cuboid
from ..labels import decode_label, encode_label
from ..output import OutputFolder, run_main
from .document import DocumentError, read_document
from .session import Session, frame_names

TOOL = "kitti_labels"
LABEL_SUFFIX = ".txt"
# The LiDAR frame seen as a KITTI camera at the sensor (the module says why).
LIDAR_AS_CAMERA = kitti.Calibration(
    p2=np.zeros((3, 4)), r0_rect=np.eye(3),
    tr_velo_to_cam=np.array([[0.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0],
                             [1.0, 0.0, 0.0, 0.0]]))
NO_IMAGE_BOX = (-1.0, -1.0, -1.0, -1.0)


class UsageError(ValueError):
    """A bad option or a frames folder that does not match the options; exit 2."""
    status = 2


def calib_folder(path):
    """The calib/ folder of `path` (a calib folder or a KITTI folder holding one)."""
    inner = os.path.join(path, kitti.CALIB)
    folder = inner if os.path.isdir(inner) else path
    if not os.path.isdir(folder):
        raise UsageError(f"{path}: calib folder does not exist")
    return folder


def kitti_frames(calib, wanted, start_time):
    """{frame stamp: KITTI stem} as kitti_to_bag stamps the frames of `calib`'s files."""
    stems = {}
    for name in sorted(os.listdir(calib)):
        stem, extension = os.path.splitext(name)
        if extension == LABEL_SUFFIX and kitti.is_frame_number(stem):
            stems[int(stem)] = stem
    if not stems:
        raise UsageError(f"{calib}: no calib files (NNNNNN.txt)")
    numbers = sorted(stems) if wanted is None else wanted
    missing = [n for n in numbers if n not in stems]
    if missing:
        raise UsageError(f"{calib}: no calib file for frame {missing[0]:06d}"
                         + (f" (and {len(missing) - 1} more)" if len(missing) > 1 else ""))
    from ..messages import ros_time

    ordered = sorted((stems[n] for n in numbers))
    return {stamp_name(ros_time(start_time, k * kitti.FRAME_PERIOD)): stem
            for k, stem in enumerate(ordered)}


class FrameMap:
    """Which label file and which calibration belong to which frame (see the module)."""

    def __init__(self, calib_path=None, wanted=None, start_time=kitti.DEFAULT_START_TIME):
        self.calib = calib_folder(calib_path) if calib_path else None
        self.stems = kitti_frames(self.calib, wanted, start_time) if self.calib else None
        self.start_time = start_time
        self._calibrations = {}

    def label_name(self, name):
        """The label file's stem for frame `name`; UsageError when the frame is not one of
        the KITTI frames."""
        if self.stems is None:
            return name
        if name not in self.stems:
            raise UsageError(f"frame {name} is not one of the {len(self.stems)} KITTI frames "
                             f"of {self.calib} as kitti_to_bag stamps them from --start-time "
                             f"{self.start_time:.1f} (first: {next(iter(self.stems))}); pass "
                             "the --start-time and --frames kitti_to_bag was given")
        return self.stems[name]

    def frame_of(self, label_stem):
        """The frame stamp of a label file's stem, or None."""
        if self.stems is None:
            return label_stem
        return next((name for name, stem in self.stems.items() if stem == label_stem), None)

    def calibration(self, name):
        if self.calib is None:
            return LIDAR_AS_CAMERA
        stem = self.label_name(name)
        if stem not in self._calibrations:
            self._calibrations[stem] = kitti.read_calib(os.path.join(self.calib,
                                                                     stem + LABEL_SUFFIX))
        return self._calibrations[stem]

    def detection_id(self, label_stem, line):
        """kitti_to_bag's ids (frame number * 1000 + line) for KITTI frames, else the line."""
        return int(label_stem) * kitti.ID_STRIDE + line if self.stems is not None else line


def label_line(entry, calibration, lidar_convention, decimals):
    box = kitti.Box.from_pose(entry.box.centre, entry.box.quaternion, entry.box.size)
    label = kitti.box_to_label(box, calibration, encode_label(entry.detection.get("label", "")),
                               bbox=NO_IMAGE_BOX if lidar_convention else None)
    return kitti.format_label(label, decimals)


def export_labels(args):
    frame_map = FrameMap(args.calib, args.frames, args.start_time)
    names = frame_names(args.folder)
    files, counts, skipped = {}, collections.Counter(), collections.Counter()
    keys = (f"box{n}" for n in itertools.count())
    for name in names:  # every frame is read and checked before anything is written
        stem = frame_map.label_name(name)
        path = os.path.join(args.folder, DETECTIONS_FOLDER, name + ".json")
        document = read_document(path, name, "", keys)
        lines = []
        for entry in document.entries:
            if entry.box is None:
                skipped[entry.unusable] += 1
                continue
            lines.append(label_line(entry, frame_map.calibration(name), frame_map.calib is None,
                                    args.decimals))
            # As the files hold it: a label's newline would break the one-line summary.
            counts[encode_label(entry.detection.get("label", ""))] += 1
        files[stem + LABEL_SUFFIX] = "".join(line + "\n" for line in lines)
    with OutputFolder(args.out, TOOL, args.overwrite,
                      inputs=(args.folder, args.calib)) as folder:
        for file_name, text in files.items():
            with open(os.path.join(folder.staging, file_name), "w", encoding="utf-8") as stream:
                stream.write(text)
        folder.commit()
    if not args.quiet:
        convention = f"camera frame of {frame_map.calib}" if frame_map.calib else \
            "LiDAR camera convention"
        print(f"{TOOL}: wrote {len(files)} label files to {args.out} ({convention}): "
              f"{sum(counts.values())} boxes ({_counted(counts)})"
              + (f"; skipped {_counted(skipped)}" if skipped else ""))
    return 0


def _counted(counter):
    return ", ".join(f"{label} {count}" for label, count in sorted(counter.items())) or "none"


def read_label_files(folder, frame_map, names):
    """{frame: [(id, label, Cuboid, score)]} of every label file that is a frame of `names`,
    and the label files that are not; a bad file stops it (KittiError, exit 2)."""
    boxes, unmatched = {}, []
    if not os.path.isdir(folder):
        raise UsageError(f"{folder}: label folder does not exist")
    for file_name in sorted(os.listdir(folder)):
        stem, extension = os.path.splitext(file_name)
        if extension != LABEL_SUFFIX or file_name.startswith("."):
            continue
        name = frame_map.frame_of(stem)
        if name not in names:
            unmatched.append(file_name)
            continue
        calibration = frame_map.calibration(name)
        boxes[name] = [
            (frame_map.detection_id(stem, line), decode_label(label.type) or label.type,
             _cuboid(kitti.label_to_box(label, calibration)),
             1.0 if label.score is None else label.score)
            for line, label in kitti.read_labels(os.path.join(folder, file_name))
            if label.type != kitti.DONT_CARE]
    return boxes, unmatched


def import_labels(args):
    frame_map = FrameMap(args.calib, args.frames, args.start_time)
    names = set(frame_names(args.into))
    boxes, unmatched = read_label_files(args.folder, frame_map, names)
    session = Session(args.into)
    with session.opened():
        refused = [session.skipped[name] for name in boxes if name in session.skipped]
        if refused:
            raise DocumentError(f"nothing imported: {len(refused)} detections files cannot be "
                                f"read, and are not replaced: {refused[0]}")
        for name, frame_boxes in sorted(boxes.items()):
            labels = session.load(name)
            labels.replace([labels.new_detection(label, box, detection_id, score)
                            for detection_id, label, box, score in frame_boxes])
            session.save(name)
    if not args.quiet:
        counts = collections.Counter(label for frame in boxes.values() for _, label, _, _ in frame)
        print(f"{TOOL}: imported {len(boxes)} label files into {args.into}: "
              f"{sum(counts.values())} boxes ({_counted(counts)}); backups in "
              f"{session.backup_folder}"
              + (f"; {len(unmatched)} label files match no frame: {', '.join(unmatched[:5])}"
                 if unmatched else ""))
    return 0


def _cuboid(box):
    return Cuboid(tuple(float(v) for v in box.centre), tuple(float(v) for v in box.size),
                  box.quaternion)


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog=TOOL,
        description="Write the boxes of a frames folder (detections_3d/<stamp>.json) as KITTI "
                    "label_2 text files, or read label files into it. With --calib the frames "
                    "are KITTI frames as kitti_to_bag stamped them (the k-th calib file in name "
                    "order, of those --frames selects, is the frame stamped --start-time + "
                    "k * 0.1 s), and the label files are named and placed as KITTI's "
                    "(000008.txt, rectified camera frame). Without it, label files are named "
                    "<stamp>.txt and use the LiDAR frame with KITTI's camera axes (x right = "
                    "-y, y down = -z, z forward = x; rotation_y = -yaw - pi/2; 2-D box -1).")
    commands = parser.add_subparsers(dest="command", required=True, metavar="export|import")
    export = commands.add_parser(
        "export", help="frames folder to label files",
        description="Write one label file per frame of FRAMES (pcd/<stamp>.pcd), empty for a "
                    "frame without boxes, into a new folder OUT (built beside it and renamed "
                    "into place; replaced only with --overwrite and only when a granular tool "
                    "wrote it). Truncation and occlusion are -1 (unknown), alpha from the "
                    "location, the 2-D box projected with P2 (-1 without --calib); a box's roll "
                    "and pitch away from the camera's y axis are lost.")
    export.add_argument("folder", metavar="FRAMES", help="frames folder (pcd/, detections_3d/)")
    export.add_argument("--out", required=True, metavar="LABEL_DIR", help="folder to write")
    export.add_argument("--decimals", type=int, default=2, choices=range(2, 10), metavar="N",
                        help="decimals of the numbers (default: %(default)s, as KITTI's files)")
    export.add_argument("--overwrite", action="store_true",
                        help="replace OUT if a granular tool wrote it")
    importing = commands.add_parser(
        "import", help="label files into a frames folder",
        description="Replace the boxes of each frame of FRAMES that has a label file in "
                    "LABEL_DIR by that file's (DontCare lines skipped; ids as kitti_to_bag "
                    "gives them with --calib, the line from 0 without; score 1, or the 16th "
                    "field); frames without a label file are left alone. Each detections file "
                    "keeps its header and is backed up as the labelling tool does "
                    "(FRAMES/labelling_backup/); refused while a labelling session holds FRAMES.")
    importing.add_argument("folder", metavar="LABEL_DIR", help="folder of label files")
    importing.add_argument("--into", required=True, metavar="FRAMES",
                           help="frames folder whose boxes are replaced")
    for command in (export, importing):
        command.add_argument("--calib", metavar="DIR",
                             help="KITTI calib/ folder (or a KITTI folder holding one): label "
                                  "files in the camera frame, named by KITTI frame")
        command.add_argument("--frames", type=kitti.parse_frames, metavar="LIST",
                             help="the --frames kitti_to_bag was given (default: every calib "
                                  "file)")
        command.add_argument("--start-time", type=float, default=kitti.DEFAULT_START_TIME,
                             metavar="SECONDS", help="the --start-time kitti_to_bag was given "
                                                     "(default: %(default).0f)")
        command.add_argument("--quiet", action="store_true", help="no summary")
        command.epilog = ("Exit status: 0 done, 1 unreadable or unwritable files, 2 bad option "
                          "or label file (file and line named), 130/143 interrupted. See "
                          "docs/labelling.md.")
    args = parser.parse_args(argv)
    if not kitti.valid_start_time(args.start_time):
        parser.error(f"--start-time must be between 0 and 2^32 s, as kitti_to_bag's, got "
                     f"{args.start_time}")
    return args


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    run = export_labels if args.command == "export" else import_labels
    return run_main(TOOL, lambda: run(args))

