"""A LiDAR drive simulator that writes rosbags in the LGSVL simulator's format.

Stages: `config` (parameters), `meshes` (class body shapes and mesh files), `scene` (actors and
their motion), `lidar` (ray casting a 64-laser sensor), `recorder` (the drive into a bag).
"""
