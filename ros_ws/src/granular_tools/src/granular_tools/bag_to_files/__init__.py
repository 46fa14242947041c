"""bag to files: synchronise clouds with 3D detections and save PCD + JSON pairs named by stamp.

`writer` writes each pair into the output folder, `detections` cleans a pair's boxes, `pairing`
the synchronisation policy shared by the offline reader (`offline`) and the live node (`node`).
"""
