"""A simulated drive: the scene, the sensor, and the two clocks (clouds and detections)."""
import dataclasses

import numpy as np

from .lidar import Lidar
from .parking_lot import ParkingLot
from .scene import RoadScene

SCENES = {"road": RoadScene, "parking_lot": ParkingLot}

# Separate random streams, so that e.g. changing the noise never moves the traffic.
_STREAM_CLOCKS, _STREAM_CLOUD = 1, 2


class Drive:
    def __init__(self, config, duration, seed, class_meshes=None, scene="road"):
        if duration <= 0.0:
            raise ValueError(f"duration must be positive, got {duration}")
        self.config = config
        self.duration = duration
        self.seed = seed
        self.scene = SCENES[scene](config, duration, seed, class_meshes)
        # The scene says how high the sensor stands (a parking lot's mast).
        self.lidar = Lidar(dataclasses.replace(config.lidar,
                                               mount_height=self.scene.sensor_height))
        clock_rng = np.random.default_rng([seed, _STREAM_CLOCKS])
        self.cloud_times = self._clock(config.lidar.rate_hz, 0.0, config.lidar.stamp_jitter,
                                       clock_rng)
        self.detection_times = self._clock(config.detections.rate_hz,
                                           config.detections.clock_offset,
                                           config.detections.stamp_jitter, clock_rng)

    def _clock(self, rate_hz, offset, jitter, rng):
        """Seconds since the start of the drive at which a publisher fires."""
        nominal = offset + np.arange(0.0, self.duration, 1.0 / rate_hz)
        nominal = nominal[nominal < self.duration]
        return np.clip(nominal + rng.uniform(-jitter, jitter, len(nominal)), 0.0, None)

    def cloud(self, index):
        """Returns of cloud `index`, a snapshot of the scene at its stamp."""
        t = self.cloud_times[index]
        rng = np.random.default_rng([self.seed, _STREAM_CLOUD, index])
        return self.lidar.scan(self.scene.placed_meshes(t), self.scene.ground_reflectivity(t),
                               rng, self.scene.placed_volumes(t))

    def detections(self, index):
        return self.scene.detections(self.detection_times[index])

    def events(self):
        """(time, kind, index) of every message in time order; kind is 'cloud' or 'detections'."""
        merged = [(t, "cloud", i) for i, t in enumerate(self.cloud_times)]
        merged += [(t, "detections", i) for i, t in enumerate(self.detection_times)]
        return sorted(merged)
