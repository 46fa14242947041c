"""bag to files: synchronise clouds with 3D detections and save PCD + JSON pairs named by stamp.

`pcd` writes clouds, `frames` the JSON and the output folder, `pairing` the synchronisation
policy shared by the offline reader (`offline`) and the live node (`node`).
"""
