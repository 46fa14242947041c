"""render_frame: one frame from above, as the box-free path saw it: ground, the points standing
on it, each segment in its own colour with its box, the true boxes and fitted cuboids beside.

Reads what `evaluate_segmentation --save` writes (<stamp>.pcd with each point's height and
segment, <stamp>.json with the segment boxes), the frame's true boxes and, when given, a folder
of fitted cuboids in the same JSON layout.
"""
import argparse
import math
import os

import numpy as np

from ..frames_folder import DetectionsError, detections_folder, load_detections
from ..geometry import footprint
from ..output import OutputError, run_main, save_figure
from ..pcd import CloudError, read_pcd

GROUND_COLOUR = "#d8cfc0"
OBSTACLE_COLOUR = "#7a7a7a"
TRUTH_COLOUR = "#111111"
CUBOID_COLOUR = "#d62728"


def segment_colours(count):
    """A colour per segment, cycling through a qualitative palette."""
    from matplotlib import cm
    palette = cm.get_cmap("tab20").colors
    return [palette[(2 * k) % 20 if k % 20 < 10 else (2 * k + 1) % 20] for k in range(count)]


def read_saved_points(path):
    """(x, y, segment) of a saved frame's PCD: segment -1 ground, 0 none, k + 1 segment k."""
    _, points, _, _ = read_pcd(path)
    names = points.dtype.names or ()
    if "segment" not in names:
        raise CloudError(f"{path}: no 'segment' field: not a frame evaluate_segmentation "
                         "--save wrote")
    return points["x"].astype(float), points["y"].astype(float), points["segment"].astype(int)


def _outline(axes, box, colour, style="-", width=1.2):
    corners = np.vstack([footprint(box), footprint(box)[:1]])
    axes.plot(corners[:, 0], corners[:, 1], style, color=colour, linewidth=width)
    # The front (the box's +x face) thicker, so that the heading shows.
    axes.plot(corners[3:5, 0], corners[3:5, 1], style, color=colour, linewidth=2.5 * width)


def render(saved, stamp, out, truth=None, cuboids=None, extent=None, title=None):
    """Draw one frame into `out` (PNG). `extent`: (xmin, xmax, ymin, ymax) in metres."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib import pyplot
    from matplotlib.lines import Line2D

    x, y, segment = read_saved_points(os.path.join(saved, stamp + ".pcd"))
    segments, _ = load_detections(os.path.join(saved, stamp + ".json"))
    if segment.size and segment.max() > len(segments):
        raise CloudError(f"{os.path.join(saved, stamp + '.pcd')}: its points name segment "
                         f"{segment.max() - 1}, but {stamp}.json lists {len(segments)} segments: "
                         "the two files are not of one evaluate_segmentation --save")
    extent = extent or (-10.0, 50.0, -25.0, 25.0)
    inside = (x >= extent[0]) & (x <= extent[1]) & (y >= extent[2]) & (y <= extent[3])
    figure, axes = pyplot.subplots(figsize=(10, 10 * (extent[3] - extent[2]) /
                                            (extent[1] - extent[0])))
    ground = inside & (segment < 0)
    loose = inside & (segment == 0)
    axes.scatter(x[ground], y[ground], s=0.3, c=GROUND_COLOUR, linewidths=0)
    axes.scatter(x[loose], y[loose], s=0.6, c=OBSTACLE_COLOUR, linewidths=0)
    colours = segment_colours(len(segments))
    members = inside & (segment > 0)
    axes.scatter(x[members], y[members], s=1.2, linewidths=0,
                 c=[colours[k - 1] for k in segment[members]])
    for k, detection in enumerate(segments):
        _outline(axes, detection.box, colours[k], width=0.8)
    legend = [Line2D([], [], marker="o", linestyle="", color=GROUND_COLOUR, label="ground"),
              Line2D([], [], marker="o", linestyle="", color=OBSTACLE_COLOUR,
                     label="above ground, in no segment"),
              Line2D([], [], color=colours[0] if colours else OBSTACLE_COLOUR,
                     label="segments and their boxes")]
    for folder, colour, style, label in ((truth, TRUTH_COLOUR, "--", "true boxes"),
                                         (cuboids, CUBOID_COLOUR, "-", "fitted cuboids")):
        path = os.path.join(folder, stamp + ".json") if folder else None
        if path and os.path.exists(path):
            for detection in load_detections(path)[0]:
                _outline(axes, detection.box, colour, style, width=1.4)
            legend.append(Line2D([], [], color=colour, linestyle=style, label=label))
    axes.plot([0], [0], marker=">", color="black", markersize=9)  # the sensor, facing +x
    axes.set_xlim(extent[0], extent[1])
    axes.set_ylim(extent[2], extent[3])
    axes.set_aspect("equal")
    axes.set_xlabel("x (m, ahead)")
    axes.set_ylabel("y (m, left)")
    axes.legend(handles=legend, loc="upper left", fontsize=8, framealpha=0.9)
    axes.set_title(title or stamp)
    figure.tight_layout()
    save_figure(figure, out, dpi=110)
    pyplot.close(figure)


# m: the sides a picture's extent may have (a figure 10 inches wide is drawn at its scale).
EXTENT_SIDES = (0.1, 1000.0)


def _extent(text):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    low, high = EXTENT_SIDES
    if len(values) != 4 or not all(math.isfinite(v) for v in values) or not all(
            low <= side <= high for side in (values[1] - values[0], values[3] - values[2])):
        raise argparse.ArgumentTypeError(
            f"expected XMIN,XMAX,YMIN,YMAX in metres, each side {low:g} to {high:g} m long")
    if not 0.05 <= (values[3] - values[2]) / (values[1] - values[0]) <= 20.0:
        raise argparse.ArgumentTypeError("the extent's sides may differ twentyfold at most")
    return tuple(values)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="render_frame",
        description="Draw one frame from above as the box-free path saw it (a folder that "
                    "evaluate_segmentation --save wrote): ground points, the points standing on "
                    "it, each segment in its own colour with its box (the thick side is the "
                    "box's front, +x), the true boxes dashed, fitted cuboids in red.")
    parser.add_argument("--saved", required=True, metavar="FOLDER",
                        help="evaluate_segmentation --save's folder")
    parser.add_argument("--stamp", required=True, help="the frame, by its file name's stamp")
    parser.add_argument("--out", required=True, metavar="FILE.png")
    parser.add_argument("--truth", metavar="FOLDER",
                        help="true boxes: a frames folder's detections_3d/ (or the frames "
                             "folder)")
    parser.add_argument("--cuboids", metavar="FOLDER",
                        help="fitted cuboids (fit_cuboids' output folder)")
    parser.add_argument("--extent", type=_extent, metavar="XMIN,XMAX,YMIN,YMAX",
                        help="metres around the sensor (default -10,50,-25,25)")
    parser.add_argument("--title", help="the picture's title (default: the stamp)")
    args = parser.parse_args(argv)
    if not args.out.lower().endswith(".png"):
        parser.error(f"--out {args.out}: the picture is a PNG; name it FILE.png")
    for option, folder in (("--truth", args.truth), ("--cuboids", args.cuboids)):
        if folder and not os.path.isdir(folder):
            parser.error(f"{option} {folder}: no such folder")

    def body():
        truth = detections_folder(args.truth, "truth")[0] if args.truth else None
        for path in (os.path.join(args.saved, args.stamp + ".pcd"),
                     os.path.join(args.saved, args.stamp + ".json")):
            if not os.path.isfile(path):
                raise CloudError(f"{path}: no such file (is --saved a folder "
                                 "evaluate_segmentation --save wrote, and --stamp one of its "
                                 "frames?)")
        render(args.saved, args.stamp, args.out, truth, args.cuboids, args.extent, args.title)
        return 0

    return run_main("render_frame", body, (CloudError, DetectionsError, OutputError, OSError))
