"""label_box_free: the box-free path's cuboids of a labelled drive, each labelled by the true box
it matches, as a frames folder whose boxes are those cuboids (docs/tracking.md).

extract_objects then crops them as it crops given boxes, so that the classifiers learn from
objects that look like the ones they name without boxes: the cuboid's own extent, not the true
box's, and its heading turned to face away from the sensor, as fit_cuboids --name-with turns it
(the fit knows a heading modulo 180 degrees only). Per frame, the cuboids are
matched one-to-one to the true boxes as evaluate_cuboids matches them (Hungarian on the x-y
centre distance), within --gate metres; a matched cuboid takes its true box's label and id (the
vehicle it shows, as index.csv's detection_id), an unmatched one is left out.
"""
import argparse
import collections
import json
import math
import os

from ..frames_folder import (CLOUDS_FOLDER, DETECTIONS_FOLDER, DetectionsError, frame_files,
                             load_detections, load_document, parse_detection)
from ..geometry import quaternion_multiply, rotate, yaw_difference_deg
from ..output import OutputFolder, check_output_apart, run_main, write_file
from .cuboid_matching import match

TOOL = "label_box_free"
DEFAULT_GATE_M = 1.0


HALF_TURN = (0.0, 0.0, 1.0, 0.0)  # (x, y, z, w): 180 degrees about z


def facing_away(cuboid):
    """The cuboid's quaternion with its x axis turned to point away from the sensor (the rule
    of fit_cuboids' facingAway)."""
    axis = rotate(cuboid.box.quaternion, (1.0, 0.0, 0.0))
    if axis[0] * cuboid.box.centre[0] + axis[1] * cuboid.box.centre[1] >= 0.0:
        return cuboid.box.quaternion
    return quaternion_multiply(cuboid.box.quaternion, HALF_TURN)


def label_frame(truths, document, gate):
    """The cuboid entries of `document` that match a truth within `gate` m, relabelled and
    turned to face away from the sensor; and how many of them then face the other way from
    their truth (yaw off by more than 90 degrees)."""
    cuboids, entries = [], []
    for k, entry in enumerate(document["detections"]):
        cuboid, _ = parse_detection(entry, f"detections[{k}]")
        if cuboid is not None:
            cuboids.append(cuboid)
            entries.append(entry)
    labelled, reversed_heading = [], 0
    for t, c in sorted(match(truths, cuboids, gate), key=lambda pair: pair[1]):
        quaternion = facing_away(cuboids[c])
        bbox = entries[c]["bbox"]
        pose = dict(bbox["position"], orientation=dict(zip("xyzw", quaternion)))
        labelled.append(dict(entries[c], label=truths[t].label, id=truths[t].id,
                             bbox=dict(bbox, position=pose)))
        if yaw_difference_deg(math.atan2(*rotate(quaternion, (1.0, 0.0, 0.0))[1::-1]),
                              truths[t].box.yaw, period=360.0) > 90.0:
            reversed_heading += 1
    return labelled, reversed_heading


def label_box_free(truth_frames, cuboids, out, gate=DEFAULT_GATE_M, overwrite=False):
    """Writes OUT/pcd (links to the truth frames' clouds) and OUT/detections_3d (the labelled
    cuboids); returns {label: cuboids} and the count facing the other way."""
    truth_folder = os.path.join(truth_frames, DETECTIONS_FOLDER)
    clouds = os.path.join(truth_frames, CLOUDS_FOLDER)
    for folder in (truth_folder, clouds, cuboids):
        if not os.path.isdir(folder):
            raise DetectionsError(f"{folder}: no such folder")
    check_output_apart(out, [truth_frames, cuboids])
    truth_files = frame_files(truth_folder)
    labels, reversed_total = collections.Counter(), 0
    with OutputFolder(out, TOOL, overwrite) as folder:
        os.mkdir(os.path.join(folder.staging, CLOUDS_FOLDER))
        os.mkdir(os.path.join(folder.staging, DETECTIONS_FOLDER))
        for stamp, path in frame_files(cuboids).items():
            if stamp not in truth_files:
                raise DetectionsError(f"{path}: no true boxes for this frame in {truth_folder}")
            truths, _ = load_detections(truth_files[stamp])
            document = load_document(path)
            labelled, reversed_heading = label_frame(truths, document, gate)
            reversed_total += reversed_heading
            labels.update(entry["label"] for entry in labelled)
            write_file(os.path.join(folder.staging, DETECTIONS_FOLDER, f"{stamp}.json"),
                       json.dumps(dict(document, detections=labelled)).encode(), "JSON")
            os.symlink(os.path.realpath(os.path.join(clouds, f"{stamp}.pcd")),
                       os.path.join(folder.staging, CLOUDS_FOLDER, f"{stamp}.pcd"))
        folder.commit()
    return labels, reversed_total


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog=TOOL,
        description="Label the box-free path's cuboids of a drive by the true boxes they match "
                    "(Hungarian on the x-y centre distance, within --gate m), and write them as "
                    "a frames folder (pcd/ linked, detections_3d/ the labelled cuboids) that "
                    "extract_objects crops as it crops given boxes: training objects that look "
                    "like the box-free path's. Unmatched cuboids are left out.")
    parser.add_argument("--truth", required=True, metavar="FRAMES",
                        help="the drive's frames folder (pcd/ and detections_3d/ with its boxes)")
    parser.add_argument("--cuboids", required=True, metavar="FOLDER",
                        help="fit_cuboids' <stamp>.json of the same frames (--boxes segment)")
    parser.add_argument("--out", required=True, metavar="FOLDER")
    parser.add_argument("--gate", type=float, default=DEFAULT_GATE_M, metavar="M",
                        help="x-y centre distance within which a cuboid matches a true box "
                             "(default: %(default)s)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace --out when this tool wrote it")
    args = parser.parse_args(argv)
    if not args.gate > 0:
        parser.error("--gate must be positive")

    def body():
        labels, reversed_heading = label_box_free(args.truth, args.cuboids, args.out, args.gate,
                                                  args.overwrite)
        total = sum(labels.values())
        print(f"{TOOL}: {total} cuboids labelled "
              f"({', '.join(f'{k} {v}' for k, v in sorted(labels.items()))}); "
              f"{reversed_heading} face the other way from their true box; in {args.out}")
        return 0

    return run_main(TOOL, body)
