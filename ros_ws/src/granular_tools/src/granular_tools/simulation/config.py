"""Simulator parameters; defaults follow the LGSVL configuration of the report (section 4.1)."""
import dataclasses
from typing import Dict, Tuple

from ..config_loading import bounded
from .meshes import VEHICLE_CLASSES


@dataclasses.dataclass(frozen=True)
class LidarConfig:
    lasers: int = bounded(64, at_least=1)  # rows of the scan
    # deg, spread evenly over the lasers
    vertical_fov_deg: float = bounded(41.33, above=0.0, at_most=180.0)
    # deg, negative is below the horizon
    vertical_centre_deg: float = bounded(-10.0, at_least=-90.0, at_most=90.0)
    measurements_per_revolution: int = bounded(360, at_least=1)
    min_range: float = bounded(0.5, at_least=0.0)  # m
    max_range: float = bounded(50.0, above=0.0)  # m
    # m above the road; the ground lies at z = -mount_height
    mount_height: float = bounded(2.3, above=0.0)
    rate_hz: float = bounded(10.0, above=0.0)  # clouds per second
    stamp_jitter: float = bounded(0.001, at_least=0.0)  # s, uniform +- jitter on each cloud stamp
    range_noise_sigma: float = bounded(0.015, at_least=0.0)  # m, Gaussian noise along each ray
    dropout_probability: float = bounded(0.02, at_least=0.0, at_most=1.0)  # returns lost at random
    # returns weaker than this (0-255) are lost (dark glass)
    min_return_intensity: int = bounded(2, at_least=0, at_most=255)
    frame_id: str = "velodyne"


@dataclasses.dataclass(frozen=True)
class DetectionConfig:
    rate_hz: float = bounded(25.0, above=0.0)  # ground-truth publisher's own clock
    clock_offset: float = 0.013           # s, phase of the first detection after the first cloud
    stamp_jitter: float = bounded(0.002, at_least=0.0)  # s, uniform +- jitter
    # m, objects whose centre is farther are not published
    max_range: float = bounded(50.0, above=0.0)


@dataclasses.dataclass(frozen=True)
class RoadConfig:
    lanes_per_direction: int = bounded(2, at_least=1)
    lane_width: float = bounded(3.5, above=0.0)  # m
    parking_offset: float = 1.4           # m, parked cars' centre beyond the outermost lane
    sidewalk_offset: float = 4.0          # m, pedestrians' path beyond the outermost lane
    clutter_offset: float = 6.5           # m, poles, walls and vegetation beyond the outermost lane
    ego_lane: int = bounded(0, at_least=0)  # 0 is the right-most lane of the ego's direction
    ego_speed: float = bounded(9.0, at_least=0.0)  # m/s
    # m/s per lane, lane 0 first
    same_direction_speeds: Tuple[float, ...] = bounded((9.0, 13.0), at_least=0.0)
    oncoming_speeds: Tuple[float, ...] = bounded((11.0, 14.0), at_least=0.0)  # m/s per lane
    pedestrian_speed: float = bounded(1.3, at_least=0.0)  # m/s


@dataclasses.dataclass(frozen=True)
class TrafficConfig:
    density: float = bounded(1.0, at_least=0.0)  # multiplies every spawn rate below
    vehicles_per_100m_lane: float = bounded(2.2, at_least=0.0)  # moving vehicles per lane
    parked_per_100m_side: float = bounded(4.0, at_least=0.0)
    pedestrians_per_100m_side: float = bounded(2.0, at_least=0.0)
    clutter_per_100m_side: float = bounded(5.0, at_least=0.0)
    min_gap: float = bounded(4.0, at_least=0.0)  # m, bumper to bumper
    yaw_noise_deg: float = 1.5            # moving vehicles
    parked_yaw_noise_deg: float = 6.0
    tilt_noise_deg: float = 0.3           # roll and pitch of every object
    # relative, per instance and axis
    size_variation: float = bounded(0.05, at_least=0.0, at_most=0.5)
    class_weights: Dict[str, float] = bounded(keys=VEHICLE_CLASSES, factory=lambda: {
        "Sedan": 0.24, "SUV": 0.2, "Hatchback": 0.2, "Jeep": 0.2, "BoxTruck": 0.09,
        "SchoolBus": 0.07})


@dataclasses.dataclass(frozen=True)
class ParkingLotConfig:
    """The parking-lot scene (--scene parking_lot); ranges are (low, high), drawn uniformly."""
    length: float = bounded(120.0, above=0.0)  # m along the aisles, centred on x = 0
    # m, the sensor above the ground: stands for the sensor's mount height in this scene
    mast_height: float = bounded(2.5, above=0.0)
    # m/s along the main aisle (0: the mast stands still); the drive is centred on the lot
    sensor_speed: float = bounded(1.0, at_least=0.0)
    aisle_width: float = bounded(6.5, above=0.0)  # m, kerb to kerb of the rows either side
    # m, depth of a row of bays; two rows stand back to back, their cars nose to tail
    bay_depth: float = bounded(5.5, above=0.0)
    side_gap: Tuple[float, ...] = bounded((0.4, 1.0), at_least=0.0)  # m, between cars of a row
    nose_gap: Tuple[float, ...] = bounded((0.3, 1.0), at_least=0.0)  # m, back-to-back cars
    occupancy: float = bounded(0.85, at_least=0.0, at_most=1.0)  # share of bays with a car
    parked_yaw_noise_deg: float = bounded(3.0, at_least=0.0)  # deg
    strip_width: float = bounded(3.0, above=0.0)  # m, planted strip beyond the rows
    kerb_size: Tuple[float, ...] = bounded((0.2, 0.15), above=0.0)  # m, width and height
    tree_spacing: Tuple[float, ...] = bounded((8.0, 14.0), above=0.0)  # m, along a strip
    trunk_height: Tuple[float, ...] = bounded((1.8, 2.8), above=0.0)  # m, ground to canopy
    trunk_radius: float = bounded(0.15, above=0.0)  # m
    # m, horizontal semi-axes of the canopy's ellipsoid; the vertical one is 0.8 of it
    canopy_radius: Tuple[float, ...] = bounded((1.5, 2.5), above=0.0)
    # 1/m, leaves met per metre of ray in a canopy: mean free path 1.7 m; a ray through the
    # middle of a 4 m wide canopy passes with probability exp(-0.6 * 4), 9 %
    canopy_density: float = bounded(0.6, above=0.0)
    hedge_height: Tuple[float, ...] = bounded((0.9, 1.5), above=0.0)  # m
    hedge_width: float = bounded(1.0, above=0.0)  # m
    hedge_density: float = bounded(5.0, above=0.0)  # 1/m: mean free path 0.2 m
    light_pole_spacing: float = bounded(30.0, above=0.0)  # m, along each strip
    light_pole_height: float = bounded(8.0, above=0.0)  # m
    wall_height: float = bounded(6.0, above=0.0)  # m, the building along the far side
    # m, from the kerbside row's outer side to the wall: a pavement
    pavement_width: float = bounded(2.0, at_least=0.0)
    pedestrians: int = bounded(10, at_least=0)  # walking along the aisles
    pedestrian_speed: float = bounded(1.3, at_least=0.0)  # m/s
    # cars in the rows of bays; long vehicles park in the kerbside row along the wall
    bay_class_weights: Dict[str, float] = bounded(keys=VEHICLE_CLASSES, factory=lambda: {
        "Sedan": 0.3, "SUV": 0.25, "Hatchback": 0.25, "Jeep": 0.2})
    kerbside_class_weights: Dict[str, float] = bounded(keys=VEHICLE_CLASSES, factory=lambda: {
        "Sedan": 0.3, "SUV": 0.2, "Hatchback": 0.2, "Jeep": 0.1, "BoxTruck": 0.12,
        "SchoolBus": 0.08})


@dataclasses.dataclass(frozen=True)
class SimulatorConfig:
    lidar: LidarConfig = dataclasses.field(default_factory=LidarConfig)
    detections: DetectionConfig = dataclasses.field(default_factory=DetectionConfig)
    road: RoadConfig = dataclasses.field(default_factory=RoadConfig)
    traffic: TrafficConfig = dataclasses.field(default_factory=TrafficConfig)
    parking_lot: ParkingLotConfig = dataclasses.field(default_factory=ParkingLotConfig)
    start_time: float = 1586102742.0      # s since the epoch, first cloud stamp
    cloud_topic: str = "/simulator/lidar"
    detections_topic: str = "/simulator/ground_truth/3d_detections"
