"""render_models draws every model and refuses folders without usable models."""
import numpy as np
import matplotlib.image

from granular_tools.models import pictures


def write_ascii_pcd(path, xyz):
    header = (f"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
              f"WIDTH {len(xyz)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(xyz)}\nDATA ascii\n")
    path.write_text(header + "".join(f"{x} {y} {z}\n" for x, y, z in xyz))


def box_surface(length, width, height, n=400, seed=0):
    rng = np.random.default_rng(seed)
    xyz = rng.uniform([-length / 2, -width / 2, 0.2], [length / 2, width / 2, height], (n, 3))
    xyz[:, 1] = np.where(rng.random(n) < 0.5, -width / 2, width / 2)
    return xyz


def test_every_model_gets_a_picture_and_the_overview_shows_all(tmp_path):
    write_ascii_pcd(tmp_path / "Sedan.pcd", box_surface(4.6, 1.8, 1.45))
    write_ascii_pcd(tmp_path / "SchoolBus.pcd", box_surface(11.0, 2.5, 3.1))
    assert pictures.main(["--models", str(tmp_path)]) == 0
    drawn = sorted(p.name for p in (tmp_path / "pictures").iterdir())
    assert drawn == [".granular.json", "SchoolBus.png", "Sedan.png", "overview.png"]
    overview = matplotlib.image.imread(tmp_path / "pictures" / "overview.png")
    sedan = matplotlib.image.imread(tmp_path / "pictures" / "Sedan.png")
    assert overview.shape[0] >= 2 * 2.0 * 110, "a row of 2 inches at 110 dpi per class"
    assert sedan.std() > 0.05, "points were drawn, not a blank canvas"


def test_folder_without_models_or_with_empty_models_is_an_error(tmp_path, capsys):
    assert pictures.main(["--models", str(tmp_path)]) == 1
    assert "no <Class>.pcd models" in capsys.readouterr().err
    write_ascii_pcd(tmp_path / "Jeep.pcd", np.zeros((0, 3)))
    assert pictures.main(["--models", str(tmp_path)]) == 1
    assert "models without points: Jeep" in capsys.readouterr().err
    assert not (tmp_path / "pictures").exists()
