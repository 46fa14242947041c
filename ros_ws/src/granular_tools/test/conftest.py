import pathlib

import pytest

REPO_ROOT = pathlib.Path(__file__).resolve().parents[4]


@pytest.fixture
def repo_root():
    return REPO_ROOT


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
