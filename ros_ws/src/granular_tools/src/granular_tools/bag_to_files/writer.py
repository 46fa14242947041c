"""The frames folder written pair by pair: pcd/<stamp>.pcd and detections_3d/<stamp>.json
(frames_folder names them), each file safely."""
import json
import os
import shutil

from ..frames_folder import CLOUDS_FOLDER, DETECTIONS_FOLDER, detections_to_dict, stamp_name
from ..output import write_atomically, write_file
from ..pcd import cloud_to_pcd


def prepare_output(folder):
    """Empty pcd/ and detections_3d/ in `folder`, whose use the caller has checked (OutputFolder
    or claimed_folder)."""
    for sub in (CLOUDS_FOLDER, DETECTIONS_FOLDER):
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
        self._write(os.path.join(self.folder, CLOUDS_FOLDER, name + ".pcd"), pcd, "PCD")
        self._write(os.path.join(self.folder, DETECTIONS_FOLDER, name + ".json"), text, "JSON")
        return name

    def write_cloud(self, cloud):
        """Write a cloud of a bag without boxes, named by its stamp; return that name."""
        name = stamp_name(cloud.header.stamp)
        self._write(os.path.join(self.folder, CLOUDS_FOLDER, name + ".pcd"), cloud_to_pcd(cloud),
                    "PCD")
        return name
