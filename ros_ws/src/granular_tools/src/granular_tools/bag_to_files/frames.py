"""The PCD + JSON pairs on disk: naming, the report's JSON layout, and safe writing."""
import json
import os
import shutil

import genpy
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3
from lgsvl_msgs.msg import BoundingBox3D, Detection3D, Detection3DArray
from std_msgs.msg import Header

from ..output import write_atomically, write_file
from .pcd import cloud_to_pcd

PCD_FOLDER, JSON_FOLDER = "pcd", "detections_3d"


def stamp_name(stamp):
    """File stem for a ROS time: seconds then 9-digit nanoseconds, so names sort by time."""
    return f"{stamp.secs}{stamp.nsecs:09d}"


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


def prepare_output(folder):
    """Empty pcd/ and detections_3d/ in `folder`, whose use the caller has checked (OutputFolder
    or claimed_folder)."""
    for sub in (PCD_FOLDER, JSON_FOLDER):
        shutil.rmtree(os.path.join(folder, sub), ignore_errors=True)
        os.makedirs(os.path.join(folder, sub), exist_ok=True)


class PairWriter:
    """Writes one synchronised pair as pcd/<stamp>.pcd and detections_3d/<stamp>.json.

    `staged`: the folder is a staging folder put in place as a whole at the end, so each file
    is written directly; otherwise (the live node) each file goes through a flushed temporary
    name, so that a reader never sees half a pair's file.
    """

    def __init__(self, folder, staged=False):
        self.folder = folder
        self._write = write_file if staged else write_atomically

    def write(self, cloud, detections):
        """Write the pair, named by the cloud's stamp; return that name."""
        name = stamp_name(cloud.header.stamp)
        pcd = cloud_to_pcd(cloud)
        # One line: json's C encoder is used only without indentation (4x faster).
        text = json.dumps(detections_to_dict(detections), allow_nan=False).encode("utf-8")
        self._write(os.path.join(self.folder, PCD_FOLDER, name + ".pcd"), pcd, "PCD")
        self._write(os.path.join(self.folder, JSON_FOLDER, name + ".json"), text, "JSON")
        return name

    def write_cloud(self, cloud):
        """Write a cloud of a bag without boxes, named by its stamp; return that name."""
        name = stamp_name(cloud.header.stamp)
        self._write(os.path.join(self.folder, PCD_FOLDER, name + ".pcd"), cloud_to_pcd(cloud),
                    "PCD")
        return name


def dict_to_detections(document):
    """The report's JSON back into a Detection3DArray (the inverse of detections_to_dict)."""
    def header(h):
        return Header(seq=h.get("seq", 0), frame_id=h.get("frame_id", ""),
                      stamp=genpy.Time(h["stamp"]["secs"], h["stamp"]["nsecs"]))

    def vector(v, kind=Vector3):
        return kind(v["x"], v["y"], v["z"])

    message = Detection3DArray(header=header(document["header"]))
    for d in document["detections"]:
        pose = d["bbox"]["position"]
        o = pose["orientation"]
        message.detections.append(Detection3D(
            header=header(d["header"]), id=d["id"], label=d["label"], score=d["score"],
            bbox=BoundingBox3D(position=Pose(vector(pose["position"], Point),
                                             Quaternion(o["x"], o["y"], o["z"], o["w"])),
                               size=vector(d["bbox"]["size"])),
            velocity=Twist(vector(d["velocity"]["linear"]), vector(d["velocity"]["angular"]))))
    return message
