"""Labels round-trip through file names exactly as granular_core writes them (the same cases as
granular_core's gtest, from granular_core/test/data/label_names.tsv)."""
import pathlib

import pytest

from granular_tools.labels import decode_label, encode_label, model_label, object_label

CASES = pathlib.Path(__file__).resolve().parents[2] / "granular_core" / "test" / "data" / \
    "label_names.tsv"


def cases():
    lines = CASES.read_text(encoding="utf-8").splitlines()[1:]
    return [tuple(line.split("\t", 1)) for line in lines]


@pytest.mark.parametrize("label,encoded", cases())
def test_every_label_round_trips(label, encoded):
    assert encode_label(label) == encoded
    assert decode_label(encoded) == label
    assert object_label(pathlib.Path(f"{encoded}-1586102742000765440-3.pcd")) == label
    assert model_label(pathlib.Path(f"{encoded}.pcd")) == label


def test_names_no_encoding_gives_have_no_label():
    for name in ("-1-1.pcd", "stray.pcd", "Bad%2-1-1.pcd", "Bad%2d-1-1.pcd", "Bad%41-1-1.pcd",
                 "Bad label-1-1.pcd", "%FF-1-1.pcd"):
        assert object_label(pathlib.Path(name)) is None, name
