"""simulate_drive: write a rosbag imitating an LGSVL simulator recording."""
import argparse
import dataclasses
import sys
import time

from .. import progress
from ..config_loading import ConfigError, load_yaml_over
from ..output import run_main
from . import meshes
from .config import SimulatorConfig
from .drive import SCENES, Drive
from .sensor import available_sensors, load_sensor


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog="simulate_drive",
        description="Simulate a drive (a road with traffic, or a parking lot) with a spinning "
                    "LiDAR and ground-truth 3D boxes, and write it as a rosbag in the LGSVL "
                    "simulator's format: sensor_msgs/PointCloud2 on /simulator/lidar (at the "
                    "sensor's rate) and lgsvl_msgs/Detection3DArray on "
                    "/simulator/ground_truth/3d_detections (its own clock).")
    parser.add_argument("--out", required=True, metavar="FILE.bag", help="bag to write")
    parser.add_argument("--duration", type=float, default=20.0, metavar="SECONDS",
                        help="length of the drive (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=1,
                        help="random seed; the same seed gives the same clouds and boxes "
                             "(default: %(default)s)")
    parser.add_argument("--traffic", type=float, default=None, metavar="DENSITY",
                        help="road scene: multiplies every spawn rate: 0 is an empty road, 2 "
                             "twice the traffic (default: traffic.density of the config, 1.0)")
    parser.add_argument("--scene", choices=SCENES, default="road",
                        help="road: a straight road with traffic, parked cars, pedestrians and "
                             "roadside clutter; parking_lot: rows of parked cars, trees, hedges, "
                             "poles, kerbs, a wall and pedestrians, the sensor on a mast "
                             "(default: %(default)s)")
    parser.add_argument("--sensor", metavar="NAME|FILE.yaml",
                        help="render with a sensor file: NAME is config/sensors/NAME.yaml "
                             f"({', '.join(available_sensors())}); its rings, azimuth step, "
                             "vertical field of view, range, rate and mount height replace the "
                             "config's lidar section (in a parking lot the mast height stands "
                             "for the mount height) (default: the config's lidar section, which "
                             "is the simulator sensor)")
    parser.add_argument("--mesh", action="append", default=[], metavar="CLASS=FILE",
                        help="use a triangle mesh (OBJ, PLY or STL; metres, x forward, z up) for "
                             f"a class instead of its built-in shape; classes: "
                             f"{', '.join(meshes.CLASSES)}; repeatable")
    parser.add_argument("--config", metavar="FILE.yaml",
                        help="simulator parameters laid over the defaults "
                             "(see config/simulator.yaml)")
    parser.add_argument("--quiet", action="store_true", help="no progress or summary")
    return parser.parse_args(argv)


def load_class_meshes(specs):
    class_meshes = {}
    for spec in specs:
        name, sep, path = spec.partition("=")
        if not sep or not path:
            raise meshes.MeshError(f"--mesh {spec}: expected CLASS=FILE")
        if name not in meshes.CLASSES:
            raise meshes.MeshError(f"--mesh {spec}: unknown class '{name}' "
                                   f"(classes: {', '.join(meshes.CLASSES)})")
        class_meshes[name] = meshes.load_mesh_file(path)
    return class_meshes


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        config = SimulatorConfig()
        if args.config:
            config = load_yaml_over(config, args.config)
        if args.sensor:
            config = dataclasses.replace(
                config, lidar=load_sensor(args.sensor).lidar_config(config.lidar))
        if args.traffic is not None:
            if args.scene != "road":
                raise ConfigError(f"--traffic applies to the road scene, not --scene {args.scene}")
            if args.traffic < 0.0:
                raise ConfigError(f"--traffic must be >= 0, got {args.traffic}")
            config = dataclasses.replace(
                config, traffic=dataclasses.replace(config.traffic, density=args.traffic))
        class_meshes = load_class_meshes(args.mesh)
        drive = Drive(config, args.duration, args.seed, class_meshes, args.scene)
    except (ConfigError, meshes.MeshError, ValueError) as error:
        print(f"simulate_drive: error: {error}", file=sys.stderr)
        return 2

    return run_main("simulate_drive", lambda: record(drive, args))


def record(drive, args):
    from .recorder import write_bag  # ROS imports only once the arguments are good.

    reporter = None if args.quiet else progress.Reporter("simulating", unit="messages")
    started = time.monotonic()
    counts = write_bag(drive, args.out, reporter)
    elapsed = time.monotonic() - started
    if not args.quiet:
        reporter.finish()
        labelled = {}
        for actor in drive.scene.actors:
            if actor.label is not None:
                labelled[actor.label] = labelled.get(actor.label, 0) + 1
        print(f"wrote {args.out}: {counts['cloud']} clouds, {counts['detections']} detection "
              f"messages, {args.duration:g} s simulated in {elapsed:.1f} s "
              f"({counts['cloud'] / elapsed:.1f} clouds/s)")
        print("objects in the scene: " + ", ".join(f"{k} {v}" for k, v in sorted(labelled.items())))
    return 0
