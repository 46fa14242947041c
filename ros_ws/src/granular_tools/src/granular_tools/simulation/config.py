"""Simulator parameters; defaults follow the LGSVL configuration of the report (section 4.1)."""
import dataclasses
from typing import Dict, Tuple


@dataclasses.dataclass(frozen=True)
class LidarConfig:
    lasers: int = 64                      # rows of the scan
    vertical_fov_deg: float = 41.33       # deg, spread evenly over the lasers
    vertical_centre_deg: float = -10.0    # deg, negative is below the horizon
    measurements_per_revolution: int = 360
    min_range: float = 0.5                # m
    max_range: float = 50.0               # m
    mount_height: float = 2.3             # m above the road; the ground lies at z = -mount_height
    rate_hz: float = 10.0                 # clouds per second
    stamp_jitter: float = 0.001           # s, uniform +- jitter on each cloud stamp
    range_noise_sigma: float = 0.015      # m, Gaussian noise along each ray
    dropout_probability: float = 0.02     # returns lost at random
    min_return_intensity: int = 2         # returns weaker than this (0-255) are lost (dark glass)
    frame_id: str = "velodyne"


@dataclasses.dataclass(frozen=True)
class DetectionConfig:
    rate_hz: float = 25.0                 # ground-truth publisher's own clock
    clock_offset: float = 0.013           # s, phase of the first detection after the first cloud
    stamp_jitter: float = 0.002           # s, uniform +- jitter
    max_range: float = 50.0               # m, objects whose centre is farther are not published


@dataclasses.dataclass(frozen=True)
class RoadConfig:
    lanes_per_direction: int = 2
    lane_width: float = 3.5               # m
    parking_offset: float = 1.4           # m, parked cars' centre beyond the outermost lane
    sidewalk_offset: float = 4.0          # m, pedestrians' path beyond the outermost lane
    clutter_offset: float = 6.5           # m, poles, walls and vegetation beyond the outermost lane
    ego_lane: int = 0                     # 0 is the right-most lane of the ego's direction
    ego_speed: float = 9.0                # m/s
    same_direction_speeds: Tuple[float, ...] = (9.0, 13.0)        # m/s per lane, lane 0 first
    oncoming_speeds: Tuple[float, ...] = (11.0, 14.0)             # m/s per lane
    pedestrian_speed: float = 1.3         # m/s


@dataclasses.dataclass(frozen=True)
class TrafficConfig:
    density: float = 1.0                  # multiplies every spawn rate below
    vehicles_per_100m_lane: float = 2.2   # moving vehicles per lane
    parked_per_100m_side: float = 4.0
    pedestrians_per_100m_side: float = 2.0
    clutter_per_100m_side: float = 5.0
    min_gap: float = 4.0                  # m, bumper to bumper
    yaw_noise_deg: float = 1.5            # moving vehicles
    parked_yaw_noise_deg: float = 6.0
    tilt_noise_deg: float = 0.3           # roll and pitch of every object
    size_variation: float = 0.05          # relative, per instance and axis
    class_weights: Dict[str, float] = dataclasses.field(default_factory=lambda: {
        "Sedan": 0.24, "SUV": 0.2, "Hatchback": 0.2, "Jeep": 0.2, "BoxTruck": 0.09,
        "SchoolBus": 0.07})


@dataclasses.dataclass(frozen=True)
class SimulatorConfig:
    lidar: LidarConfig = dataclasses.field(default_factory=LidarConfig)
    detections: DetectionConfig = dataclasses.field(default_factory=DetectionConfig)
    road: RoadConfig = dataclasses.field(default_factory=RoadConfig)
    traffic: TrafficConfig = dataclasses.field(default_factory=TrafficConfig)
    start_time: float = 1586102742.0      # s since the epoch, first cloud stamp
    cloud_topic: str = "/simulator/lidar"
    detections_topic: str = "/simulator/ground_truth/3d_detections"
