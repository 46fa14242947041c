import pathlib

import pytest

REPO_ROOT = pathlib.Path(__file__).resolve().parents[4]


@pytest.fixture
def repo_root():
    return REPO_ROOT


@pytest.fixture(scope="session")
def kitti_fixture():
    """The ten KITTI frames of ../shared/fixtures/kitti (velodyne/, label_2/, calib/, planes/ of
    frames 000000-000009; not part of the repository): the tests that need them skip without."""
    folder = REPO_ROOT.parent / "shared" / "fixtures" / "kitti"
    if not (folder / "velodyne").is_dir():
        pytest.skip(f"KITTI fixture frames not found at {folder} (velodyne/, label_2/, calib/, "
                    "planes/ of frames 000000-000009; not part of the repository)")
    return folder


@pytest.fixture(scope="session")
def kitti_bag(kitti_fixture, tmp_path_factory):
    """The fixture's frames as kitti_to_bag makes them, with their boxes."""
    from granular_tools import kitti

    bag = tmp_path_factory.mktemp("kitti") / "kitti.bag"
    assert kitti.main([str(kitti_fixture), "--out", str(bag), "--quiet"]) == 0
    return bag


@pytest.fixture(scope="session")
def kitti_frames(kitti_bag, tmp_path_factory):
    """kitti_bag as bag_to_files makes it a frames folder. Shared: tests copy what they change."""
    from granular_tools.bag_to_files import offline

    frames = tmp_path_factory.mktemp("kitti_frames") / "frames"
    assert offline.main(["--bag", str(kitti_bag), "--out", str(frames), "--quiet"]) == 0
    return frames


@pytest.fixture(scope="session")
def drive(tmp_path_factory):
    """A short simulated drive taken through the pipeline once per session: the bag, its frames,
    objects (N10), class models and a kNN classifier. Tests copy what they change."""
    import hostile

    folder = tmp_path_factory.mktemp("drive")
    steps = [
        hostile.tool("granular_tools", "simulate_drive") + [
            "--out", folder / "drive.bag", "--duration", "4", "--seed", "3", "--quiet"],
        hostile.tool("granular_tools", "bag_to_files") + [
            "--bag", folder / "drive.bag", "--out", folder / "frames", "--quiet"],
        hostile.tool("granular_ros", "extract_objects") + [
            "--in", folder / "frames", "--out", folder / "objects"],
        hostile.tool("granular_ros", "build_models") + [
            "--objects", folder / "objects", "--out", folder / "models"],
        hostile.tool("granular_ros", "train_classifier") + [
            "--objects", folder / "objects", "--method", "knn", "--out", folder / "knn.yml"],
    ]
    for step in steps:
        result = hostile.run(step)
        assert result.status == 0, str(result)
    return folder
