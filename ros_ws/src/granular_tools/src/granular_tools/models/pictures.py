"""render_models: PNG pictures of class models from several viewpoints (like the report's fig. 9).

Models are in the object frame (x forward, y left, z up, the road at z = 0), so the same
views show every class at the same scale: a Sedan's trunk and a Hatchback's flat rear are
visible side by side.
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # Files only: no display needed.
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..labels import encode_label, model_label  # noqa: E402
from ..output import OutputFolder, run_main, save_figure  # noqa: E402
from ..pcd import CloudError, read_pcd  # noqa: E402

# (title, horizontal axis, vertical axis, sign of the horizontal axis)
FLAT_VIEWS = [("side (from the left)", 0, 2, 1.0), ("rear (from behind)", 1, 2, -1.0),
              ("top", 0, 1, 1.0)]
AXIS_NAMES = "xyz"


def load_xyz(path):
    _, points, _, _ = read_pcd(path)
    missing = [a for a in AXIS_NAMES if a not in points.dtype.names]
    if missing:
        raise CloudError(f"{path}: no {'/'.join(missing)} field")
    xyz = np.stack([points[a] for a in AXIS_NAMES], axis=1).astype(float)
    return xyz[np.all(np.isfinite(xyz), axis=1)]


def _flat(ax, xyz, title, horizontal, vertical, sign, limits):
    ax.scatter(sign * xyz[:, horizontal], xyz[:, vertical], c=xyz[:, 2], cmap="viridis",
               s=0.6, vmin=limits[2][0], vmax=limits[2][1], linewidths=0)
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(f"{'-' if sign < 0 else ''}{AXIS_NAMES[horizontal]} (m)", fontsize=8)
    ax.set_ylabel(f"{AXIS_NAMES[vertical]} (m)", fontsize=8)
    ax.set_aspect("equal")
    ax.tick_params(labelsize=7)


def _oblique(ax, xyz, limits):
    ax.scatter(xyz[:, 0], xyz[:, 1], xyz[:, 2], c=xyz[:, 2], cmap="viridis", s=0.4,
               vmin=limits[2][0], vmax=limits[2][1], linewidths=0)
    ax.view_init(elev=20, azim=-135)  # from the rear left
    ax.set_box_aspect(np.ptp(np.array(limits), axis=1))
    ax.set_xlim(*limits[0]), ax.set_ylim(*limits[1]), ax.set_zlim(*limits[2])
    ax.set_title("oblique (rear left)", fontsize=9)
    ax.tick_params(labelsize=6)


def _limits(clouds):
    stacked = np.vstack([c for c in clouds if len(c)])
    low, high = stacked.min(axis=0) - 0.1, stacked.max(axis=0) + 0.1
    return [(low[k], high[k]) for k in range(3)]


def _save(figure, path):
    try:
        save_figure(figure, path, dpi=110)
    finally:
        plt.close(figure)


def render_model(name, xyz, path):
    limits = _limits([xyz])
    figure = plt.figure(figsize=(11, 6.5))
    grid = figure.add_gridspec(2, 2, width_ratios=[2.2, 1])
    cells = [grid[0, 0], grid[0, 1], grid[1, 0]]
    for cell, (title, horizontal, vertical, sign) in zip(cells, FLAT_VIEWS):
        _flat(figure.add_subplot(cell), xyz, title, horizontal, vertical, sign, limits)
    _oblique(figure.add_subplot(grid[1, 1], projection="3d"), xyz, limits)
    figure.suptitle(f"{name} model: {len(xyz)} points", fontsize=11)
    figure.tight_layout()
    _save(figure, path)


def render_overview(models, path):
    """One row per class (side and rear views) at one common scale."""
    limits = _limits(list(models.values()))
    figure, axes = plt.subplots(len(models), 2, figsize=(10, 2.0 * len(models)), squeeze=False,
                                gridspec_kw={"width_ratios": [3, 1.4]})
    for row, (name, xyz) in enumerate(sorted(models.items())):
        for column, (title, horizontal, vertical, sign) in enumerate(FLAT_VIEWS[:2]):
            ax = axes[row][column]
            _flat(ax, xyz, f"{name}: {title}", horizontal, vertical, sign, limits)
            ax.set_xlim(*(sorted(sign * np.array(limits[horizontal]))))
            ax.set_ylim(*limits[vertical])
    figure.tight_layout()
    _save(figure, path)


def render_folder(models_folder, out=None, overwrite=False):
    """Draw every model of `models_folder` into `out` (default MODELS/pictures), built as a
    whole (OutputFolder); returns the exit status, having printed any error."""
    folder = pathlib.Path(models_folder)
    out = pathlib.Path(out) if out else folder / "pictures"

    def body():
        paths = sorted(folder.glob("*.pcd"))
        if not paths:
            raise CloudError(f"{folder}: no <Class>.pcd models")
        unnamed = [path.name for path in paths if model_label(path) is None]
        if unnamed:
            raise CloudError(f"{folder}: not class models' names: {', '.join(unnamed)}")
        models = {model_label(path): load_xyz(path) for path in paths}
        empty = [name for name, xyz in models.items() if len(xyz) == 0]
        if empty:
            raise CloudError(f"{folder}: models without points: {', '.join(empty)}")
        with OutputFolder(out, "render_models", overwrite, inputs=(folder,)) as pictures:
            staging = pathlib.Path(pictures.staging)
            for name, xyz in models.items():
                render_model(name, xyz, str(staging / f"{encode_label(name)}.png"))
            render_overview(models, str(staging / "overview.png"))
            pictures.commit()
        print(f"render_models: {len(models)} models drawn into {out}")
        return 0

    return run_main("render_models", body, (CloudError, OSError))


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="render_models",
        description="Draw each class model (<Class>.pcd in a models folder) from the side, the "
                    "rear, the top and obliquely, into OUT/<Class>.png, and all classes side "
                    "by side into OUT/overview.png.")
    parser.add_argument("--models", required=True, help="folder with <Class>.pcd files")
    parser.add_argument("--out", help="folder for the pictures (default: MODELS/pictures)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace pictures a previous run drew")
    args = parser.parse_args(argv)
    return render_folder(args.models, args.out, args.overwrite)
