"""Sensor files (config/sensors/NAME.yaml): a LiDAR's mount, rings, azimuth step and range.

A sensor file names every key of `Sensor`, and no other: the C++ tools read the same files just
as strictly. `simulate_drive --sensor` renders with one by replacing the geometry of the
`lidar:` section (noise, dropouts and clocks stay as configured).
"""
import dataclasses
import os
import pathlib

import rospkg
import yaml

from ..config_loading import ConfigError, bounded, overlay
from .config import LidarConfig


def sensors_dir():
    """granular_ros's config/sensors where ROS finds the package (its source, whose
    config/sensors links to the repository's, in a devel space; share/granular_ros once
    installed): the files the C++ tools' --sensor NAME reads."""
    try:
        return pathlib.Path(rospkg.RosPack().get_path("granular_ros")) / "config" / "sensors"
    except rospkg.ResourceNotFound as error:
        raise ConfigError("sensor names need package granular_ros on ROS_PACKAGE_PATH (source "
                          "the workspace's setup.bash), or give a sensor FILE.yaml") from error


@dataclasses.dataclass(frozen=True)
class Sensor:
    description: str
    mount_height: float = bounded(above=0.0, finite=True)  # m, sensor origin above the road
    azimuth_step_deg: float = bounded(above=0.0, at_most=360.0)  # deg between returns on a ring
    rings: int = bounded(at_least=2)  # lasers
    min_elevation_deg: float = bounded(at_least=-90.0, at_most=90.0)  # deg, lowest ring
    max_elevation_deg: float = bounded(at_least=-90.0, at_most=90.0)  # deg, highest ring
    min_range: float = bounded(at_least=0.0, finite=True)  # m
    max_range: float = bounded(above=0.0, finite=True)  # m
    rate_hz: float = bounded(above=0.0, finite=True)  # revolutions per second

    @classmethod
    def of_lidar(cls, lidar):
        """The sensor a `lidar:` config section describes."""
        half_fov = lidar.vertical_fov_deg / 2.0
        return cls(description="lidar section of the simulator config",
                   mount_height=lidar.mount_height,
                   azimuth_step_deg=360.0 / lidar.measurements_per_revolution,
                   rings=lidar.lasers, min_elevation_deg=lidar.vertical_centre_deg - half_fov,
                   max_elevation_deg=lidar.vertical_centre_deg + half_fov,
                   min_range=lidar.min_range, max_range=lidar.max_range, rate_hz=lidar.rate_hz)

    @property
    def returns_per_revolution(self):
        """Returns along a ring in one revolution: 360 / azimuth step, to the nearest whole."""
        return max(1, round(360.0 / self.azimuth_step_deg))

    def lidar_config(self, lidar):
        """`lidar` (a LidarConfig) with this sensor's geometry, range and rate."""
        return dataclasses.replace(
            lidar, lasers=self.rings,
            vertical_fov_deg=self.max_elevation_deg - self.min_elevation_deg,
            vertical_centre_deg=(self.max_elevation_deg + self.min_elevation_deg) / 2.0,
            measurements_per_revolution=self.returns_per_revolution,
            min_range=self.min_range, max_range=self.max_range,
            mount_height=self.mount_height, rate_hz=self.rate_hz)


def sensor_path(name_or_file):
    """A sensor file's path: NAME is config/sensors/NAME.yaml, anything ending in .yaml a file."""
    if name_or_file.endswith((".yaml", ".yml")) or os.sep in name_or_file:
        return pathlib.Path(name_or_file)
    return sensors_dir() / f"{name_or_file}.yaml"


def available_sensors():
    return sorted(path.stem for path in sensors_dir().glob("*.yaml"))


def load_sensor(name_or_file):
    """Read and validate a sensor file; a ConfigError names the file and what is wrong."""
    path = sensor_path(name_or_file)
    if not path.is_file():
        known = ", ".join(available_sensors()) or f"none in {sensors_dir()}"
        raise ConfigError(f"sensor '{name_or_file}': no file {path} (sensors: {known})")
    try:
        with open(path, encoding="utf-8") as stream:
            values = yaml.safe_load(stream)
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as error:
        raise ConfigError(f"{path}: cannot read sensor file: {error}") from error
    if not isinstance(values, dict):
        raise ConfigError(f"{path}: expected a mapping of sensor keys")
    required = [field.name for field in dataclasses.fields(Sensor)]
    missing = [key for key in required if key not in values]
    if missing:
        raise ConfigError(f"{path}: missing key(s) {', '.join(missing)} "
                          f"(a sensor file names all of: {', '.join(required)})")
    sensor = overlay(Sensor.of_lidar(LidarConfig()), values, str(path))
    if sensor.max_elevation_deg <= sensor.min_elevation_deg:
        raise ConfigError(f"{path}: max_elevation_deg ({sensor.max_elevation_deg}) must be above "
                          f"min_elevation_deg ({sensor.min_elevation_deg})")
    if sensor.max_range <= sensor.min_range:
        raise ConfigError(f"{path}: max_range ({sensor.max_range}) must be above min_range "
                          f"({sensor.min_range})")
    return sensor
