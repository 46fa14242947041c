"""Scenes: the actors of a drive and what the sensor sees of them; here the straight road.

World frame: x along the road (or the parking lot's aisles) in the ego's direction, y left,
z up, ground at z = 0. Everything moves at constant velocity along x, so poses at any stamp are
exact.
"""
import dataclasses
from typing import Optional

import numpy as np

from . import meshes
from .lidar import (LANE_MARKING_REFLECTIVITY, PlacedMesh, ROAD_REFLECTIVITY,
                    VERGE_REFLECTIVITY)

VIEW_MARGIN = 70.0  # m beyond the sensor range in which actors are spawned


def rotation_rpy(roll, pitch, yaw):
    cr, sr, cp, sp, cy, sy = (np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch),
                              np.cos(yaw), np.sin(yaw))
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def quaternion_from_rpy(roll, pitch, yaw):
    """(x, y, z, w) for the rotation R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp = np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


@dataclasses.dataclass
class Actor:
    """An object in the world; `label` is None for clutter, which has no ground-truth box."""
    object_id: int
    label: Optional[str]
    mesh: meshes.Mesh          # object frame, centred on its bounding box
    x0: float                  # m, world x of the centre at t = 0
    y: float                   # m
    speed: float               # m/s along world x (negative for oncoming traffic)
    roll: float
    pitch: float
    yaw: float
    reflectivity: float

    @property
    def size(self):
        return self.mesh.extents

    def centre(self, t):
        return np.array([self.x0 + self.speed * t, self.y, self.size[2] / 2.0])


@dataclasses.dataclass
class Detection:
    object_id: int
    label: str
    position: np.ndarray       # sensor frame, box centre
    quaternion: tuple          # (x, y, z, w), sensor frame
    size: np.ndarray           # length, width, height
    forward_speed: float       # m/s in the object's own frame


class Road:
    """Where lanes, markings and verges are; reflectivity of the road surface."""

    def __init__(self, config):
        self.config = config
        self.half_width = config.lanes_per_direction * config.lane_width
        self.ego_y = -(config.ego_lane + 0.5) * config.lane_width

    def lane_centre(self, lane, oncoming):
        offset = (lane + 0.5) * self.config.lane_width
        return offset if oncoming else -offset

    def reflectivity(self, x, y):
        lane_width = self.config.lane_width
        boundary = np.abs(y / lane_width - np.round(y / lane_width)) * lane_width
        on_line = (boundary < 0.08) & (np.abs(y) < self.half_width + 0.1)
        dashed = np.mod(x, 9.0) < 3.0
        solid = np.abs(np.abs(y) - self.half_width) < 0.12
        centre = np.abs(y) < 0.08
        marking = on_line & (dashed | solid | centre)
        return np.where(marking, LANE_MARKING_REFLECTIVITY,
                        np.where(np.abs(y) <= self.half_width + 0.3, ROAD_REFLECTIVITY,
                                 VERGE_REFLECTIVITY))


class World:
    """Actors of one drive generated from a seed, and what the sensor sees of them at a stamp.

    A scene spawns its actors (and foliage volumes) and says where the sensor is.
    """

    def __init__(self, config, duration, seed, class_meshes=None):
        self.config = config
        self.duration = duration
        self.rng = np.random.default_rng(seed)
        self.class_meshes = {name: make() for name, make in meshes.BUILT_IN.items()}
        self.class_meshes.update(class_meshes or {})
        self.actors = []
        self.volumes = []          # foliage in the world frame (lidar.Volume), static
        self._next_id = 100

    @property
    def sensor_height(self):
        """m, the sensor above the ground: the ground lies at z = -sensor_height."""
        raise NotImplementedError

    def ego_position(self, t):
        """World position of the sensor at stamp t."""
        raise NotImplementedError

    def ground_reflectivity(self, t):
        """Reflectivity of the ground at sensor-frame (x, y) positions, for the stamp t."""
        raise NotImplementedError

    # --- spawning ------------------------------------------------------------------------
    def _actor(self, label, x0, y, speed, yaw_nominal, yaw_noise_deg, mesh=None):
        traffic = self.config.traffic
        if mesh is None:
            variation = traffic.size_variation
            mesh = self.class_meshes[label].scaled(1.0 + self.rng.uniform(-variation, variation, 3))
        tilt = np.radians(traffic.tilt_noise_deg)
        actor = Actor(object_id=self._next_id, label=label, mesh=mesh, x0=x0, y=y, speed=speed,
                      roll=self.rng.uniform(-tilt, tilt), pitch=self.rng.uniform(-tilt, tilt),
                      yaw=yaw_nominal + np.radians(self.rng.uniform(-yaw_noise_deg,
                                                                    yaw_noise_deg)),
                      reflectivity=self.rng.uniform(0.25, 0.85))
        self._next_id += 1
        self.actors.append(actor)
        return actor

    # --- observation ---------------------------------------------------------------------
    def _relative_pose(self, actor, t):
        """Actor rotation and centre in the sensor frame (the ego does not turn)."""
        rotation = rotation_rpy(actor.roll, actor.pitch, actor.yaw)
        return rotation, actor.centre(t) - self.ego_position(t)

    def placed_meshes(self, t):
        reach = self.config.lidar.max_range
        placed = []
        for actor in self.actors:
            rotation, centre = self._relative_pose(actor, t)
            if np.hypot(centre[0], centre[1]) > reach + 0.6 * np.max(actor.size) + 1.0:
                continue
            vertices = actor.mesh.vertices @ rotation.T + centre
            placed.append(PlacedMesh(vertices, actor.mesh.faces, actor.mesh.materials,
                                     actor.reflectivity))
        return placed

    def placed_volumes(self, t):
        """Foliage volumes in the sensor frame at stamp t."""
        ego = self.ego_position(t)
        return [dataclasses.replace(volume, centre=volume.centre - ego) for volume in self.volumes]

    def detections(self, t):
        """Ground-truth boxes of labelled actors at stamp t, in the sensor frame."""
        result = []
        for actor in self.actors:
            if actor.label is None:
                continue
            rotation, centre = self._relative_pose(actor, t)
            if np.linalg.norm(centre) > self.config.detections.max_range:
                continue
            result.append(Detection(actor.object_id, actor.label, centre,
                                    quaternion_from_rpy(actor.roll, actor.pitch, actor.yaw),
                                    actor.size, abs(actor.speed)))
        return result


class RoadScene(World):
    """A straight road: moving and parked traffic, pedestrians and roadside clutter."""

    def __init__(self, config, duration, seed, class_meshes=None):
        super().__init__(config, duration, seed, class_meshes)
        self.road = Road(config.road)
        self._spawn_traffic()
        self._spawn_parked()
        self._spawn_pedestrians()
        self._spawn_clutter()

    # --- ego -----------------------------------------------------------------------------
    @property
    def sensor_height(self):
        return self.config.lidar.mount_height

    def ego_position(self, t):
        cfg = self.config
        return np.array([cfg.road.ego_speed * t, self.road.ego_y, cfg.lidar.mount_height])

    # --- spawning ------------------------------------------------------------------------
    def _covering_range(self, speed):
        """World x interval at t = 0 from which actors of this speed pass near the ego."""
        reach = self.config.lidar.max_range + VIEW_MARGIN
        relative = speed - self.config.road.ego_speed
        return (min(-reach, -reach - relative * self.duration),
                max(reach, reach - relative * self.duration))

    def _positions_along(self, start, end, per_100m, min_spacing):
        rate = per_100m * self.config.traffic.density / 100.0
        positions, x = [], start
        if rate <= 0.0:
            return positions
        while True:
            x += min_spacing + self.rng.exponential(1.0 / rate)
            if x > end:
                return positions
            positions.append(x)

    def _vehicle(self, x0, y, speed, yaw_nominal, yaw_noise_deg):
        traffic = self.config.traffic
        names = list(traffic.class_weights)
        weights = np.array([traffic.class_weights[n] for n in names], float)
        label = names[self.rng.choice(len(names), p=weights / weights.sum())]
        return self._actor(label, x0, y, speed, yaw_nominal, yaw_noise_deg)

    def _spawn_traffic(self):
        road, traffic = self.config.road, self.config.traffic
        lanes = [(lane, False, speed) for lane, speed in enumerate(road.same_direction_speeds)]
        lanes += [(lane, True, -speed) for lane, speed in enumerate(road.oncoming_speeds)]
        for lane, oncoming, speed in lanes[:2 * road.lanes_per_direction]:
            start, end = self._covering_range(speed)
            y = self.road.lane_centre(lane, oncoming)
            ego_lane = not oncoming and lane == road.ego_lane
            for x0 in self._positions_along(start, end, traffic.vehicles_per_100m_lane,
                                            traffic.min_gap + 12.0):
                if ego_lane and abs(x0) < 10.0:
                    continue  # the ego's own place in its lane
                self._vehicle(x0, y, speed, np.pi if oncoming else 0.0, traffic.yaw_noise_deg)

    def _spawn_parked(self):
        traffic = self.config.traffic
        start, end = self._covering_range(0.0)
        for side in (-1.0, 1.0):
            y = side * (self.road.half_width + self.config.road.parking_offset)
            for x0 in self._positions_along(start, end, traffic.parked_per_100m_side,
                                            traffic.min_gap + 8.0):
                yaw = 0.0 if side < 0 else np.pi
                self._vehicle(x0, y + self.rng.uniform(-0.2, 0.2), 0.0, yaw,
                              traffic.parked_yaw_noise_deg)

    def _spawn_pedestrians(self):
        road, traffic = self.config.road, self.config.traffic
        for side in (-1.0, 1.0):
            y = side * (self.road.half_width + road.sidewalk_offset)
            for direction in (-1.0, 1.0):
                speed = direction * road.pedestrian_speed
                start, end = self._covering_range(speed)
                for x0 in self._positions_along(start, end, traffic.pedestrians_per_100m_side / 2,
                                                2.0):
                    self._actor("Pedestrian", x0, y + self.rng.uniform(-0.8, 0.8), speed,
                                0.0 if direction > 0 else np.pi, 10.0)

    def _spawn_clutter(self):
        traffic = self.config.traffic
        start, end = self._covering_range(0.0)
        for side in (-1.0, 1.0):
            base_y = side * (self.road.half_width + self.config.road.clutter_offset)
            for x0 in self._positions_along(start, end, traffic.clutter_per_100m_side, 3.0):
                kind = self.rng.choice(3, p=[0.45, 0.2, 0.35])
                if kind == 0:
                    mesh, y = meshes.pole(self.rng.uniform(4.0, 8.0)), base_y
                elif kind == 1:
                    mesh = meshes.wall(self.rng.uniform(4.0, 14.0), self.rng.uniform(1.2, 3.0))
                    y = base_y + side * 3.0
                else:
                    mesh = meshes.shrub(self.rng.uniform(0.6, 1.8), self.rng)
                    y = base_y + side * self.rng.uniform(0.0, 4.0)
                self._actor(None, x0, y, 0.0, 0.0, 0.0 if kind == 2 else 1.0, mesh=mesh)

    # --- observation ---------------------------------------------------------------------
    def ground_reflectivity(self, t):
        """Reflectivity of the road at sensor-frame (x, y) positions, for the stamp t."""
        ego_x, ego_y = self.ego_position(t)[:2]
        return lambda x, y: self.road.reflectivity(x + ego_x, y + ego_y)
