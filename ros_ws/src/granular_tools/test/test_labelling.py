"""The labelling tool's pieces: box edits, the detections file kept byte for byte, undo, and
its config. The click fit is granular_core's (test_click_fit.cpp)."""
import json
import math

import numpy as np
import pytest

from granular_tools.config_loading import ConfigError
from granular_tools.geometry import Cuboid, rotation_matrix
from granular_tools.labelling import boxes
from granular_tools.labelling.config import LabellingConfig, load_config
from granular_tools.labelling.document import FrameLabels, detection_spans, read_document

STAMP = "1586102742100000000"


def yawed(yaw):
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def keys():
    return (f"box{n}" for n in range(1, 10 ** 6))


def plane_offset(box, face):
    """Where the face's plane lies along its outward normal, m."""
    return float(boxes.face_centre(box, face) @ boxes.outward_normal(box, face))


# ------------------------------------------------------------------------------ box edits

@pytest.mark.parametrize("face", boxes.FACES)
@pytest.mark.parametrize("distance", [0.7, -0.4])
def test_a_face_drag_moves_that_face_only_and_the_opposite_face_stays(face, distance):
    box = Cuboid((3.0, -2.0, -1.0), (4.5, 1.8, 1.5), yawed(0.6))
    dragged, moved_by = boxes.with_face_dragged(box, face, distance, min_size=0.1)
    opposite = ("-" if face[0] == "+" else "+") + face[1]
    assert moved_by == distance
    assert plane_offset(dragged, face) == pytest.approx(plane_offset(box, face) + distance,
                                                        abs=1e-12)
    assert plane_offset(dragged, opposite) == pytest.approx(plane_offset(box, opposite),
                                                            abs=1e-12)
    axis, _ = boxes.face_axis(face)
    assert dragged.size[axis] == pytest.approx(box.size[axis] + distance, abs=1e-12)
    assert [s for i, s in enumerate(dragged.size) if i != axis] == \
        [s for i, s in enumerate(box.size) if i != axis]
    assert dragged.quaternion == box.quaternion


def test_a_face_is_not_dragged_through_the_minimum_size():
    box = Cuboid((0.0, 0.0, 0.0), (4.0, 2.0, 1.5))
    dragged, moved_by = boxes.with_face_dragged(box, "-y", -3.0, min_size=0.1)
    assert moved_by == pytest.approx(-1.9)
    assert dragged.size[1] == pytest.approx(0.1)
    assert plane_offset(dragged, "+y") == pytest.approx(1.0)  # the opposite face stayed


def test_the_drag_distance_is_along_the_face_normal_only():
    box = Cuboid((1.0, 1.0, 0.0), (4.0, 2.0, 1.5), yawed(math.pi / 2))  # length along y
    handle = boxes.face_centre(box, "+x") + np.array([0.3, 0.5, 0.2])  # sideways and up too
    assert boxes.drag_distance(box, "+x", handle) == pytest.approx(0.5)


def test_a_turn_is_about_the_vertical_and_keeps_roll_and_pitch():
    tilted = Cuboid((5.0, 1.0, -1.0), (4.0, 2.0, 1.5),
                    (math.sin(0.01), 0.0, 0.0, math.cos(0.01)))  # rolled by 0.02 rad
    turned = boxes.turned(tilted, math.radians(30))
    assert turned.centre == tilted.centre and turned.size == tilted.size
    assert math.degrees(boxes.yaw_change(tilted.quaternion, turned.quaternion)) == \
        pytest.approx(30.0, abs=1e-9)
    # The up axis keeps its angle to the vertical.
    assert rotation_matrix(turned.quaternion)[2, 2] == \
        pytest.approx(rotation_matrix(tilted.quaternion)[2, 2], abs=1e-12)


def test_a_marker_pose_moves_in_the_ground_plane_and_turns_about_the_vertical():
    box = Cuboid((5.0, 1.0, -1.0), (4.0, 2.0, 1.5), yawed(0.2))
    edited = boxes.edited_by_pose(box, (6.0, 0.5, 3.0), yawed(0.5))  # z is not the plane's
    assert edited.centre == (6.0, 0.5, -1.0)
    assert edited.yaw == pytest.approx(0.5, abs=1e-12)


def test_a_pose_rounded_through_rviz_float32_is_no_edit():
    box = Cuboid((14.32784747140829, 0.0, -1.58848), (4.8, 1.8, 1.4),
                 (0.002051327077167475, 0.0004443705086067754, -0.0007520240463099737,
                  0.9999975145228649))
    position = tuple(float(np.float32(v)) for v in box.centre)
    quaternion = tuple(float(np.float32(v)) for v in box.quaternion)
    assert boxes.edited_by_pose(box, position, quaternion) is None


# ------------------------------------------------------------------------------ the file

DETECTION = ('{"header": {"stamp": {"secs": 1586102742, "nsecs": 100000000}, "frame_id": '
             '"velodyne", "seq": 3}, "id": %d, "label": "%s", "score": 1.0, "bbox": '
             '{"position": {"position": {"x": %s, "y": 2.0, "z": -1.0}, "orientation": '
             '{"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}, "size": {"x": 4.5, "y": 1.8, "z": 1.5}}, '
             '"velocity": {"linear": {"x": 1e-05, "y": 0, "z": 0.0}, "angular": {"x": 0.0, '
             '"y": 0.0, "z": 0.0}}}')


def document_text(*detections, indent=False):
    header = '{"stamp": {"secs": 1586102742, "nsecs": 100000000}, "frame_id": "velodyne", "seq": 3}'
    separator = ",\n    " if indent else ", "
    return ('{"header": ' + header + ', "detections": [' +
            separator.join(DETECTION % d for d in detections) + ']}')


def frame(tmp_path, text):
    path = tmp_path / (STAMP + ".json")
    if text is not None:
        path.write_text(text)
    names = keys()  # one sequence: marker names are unique in a session
    return FrameLabels(STAMP, read_document(str(path), STAMP, "velodyne", names), names, 0.1)


@pytest.mark.parametrize("indent", [False, True])
def test_spans_find_each_detection_exactly(indent):
    text = document_text((1, "Car", "10.0"), (2, "Van", "1E+1"), indent=indent)
    (start, end), spans = detection_spans(text)
    assert text[start] == "[" and text[end - 1] == "]"
    assert [json.loads(text[a:b])["id"] for a, b in spans] == [1, 2]


def test_an_unedited_file_is_rendered_as_it_was(tmp_path):
    text = document_text((1, "Car", "10.0"), (2, "Van", "1E+1"), indent=True)
    assert frame(tmp_path, text).text() == text


def test_an_edit_leaves_every_other_detection_byte_for_byte(tmp_path):
    # Numbers as another writer prints them (1E+1, 1e-05, 0): kept as written.
    text = document_text((1, "Car", "10.0"), (2, "Van", "1E+1"), (3, "Car", "3"))
    labels = frame(tmp_path, text)
    key = labels.entries[1].key
    assert labels.move_to_pose(key, (12.0, 3.0, -1.0), (0.0, 0.0, 0.0, 1.0))
    saved = labels.text()
    assert saved.startswith(text[:text.index('"detections"')])
    for detection in ((1, "Car", "10.0"), (3, "Car", "3")):
        assert DETECTION % detection in saved
    moved = json.loads(saved)["detections"][1]
    assert moved["bbox"]["position"]["position"] == {"x": 12.0, "y": 3.0, "z": -1.0}
    assert moved["velocity"]["linear"] == {"x": 1e-05, "y": 0, "z": 0.0}


def test_a_label_change_touches_the_label_only(tmp_path):
    labels = frame(tmp_path, document_text((1, "Car", "10.0")))
    before = json.loads(labels.text())["detections"][0]
    assert labels.set_label(labels.entries[0].key, "Tram_/_Subway")
    assert not labels.set_label(labels.entries[0].key, "Tram_/_Subway")
    after = json.loads(labels.text())["detections"][0]
    assert after == {**before, "label": "Tram_/_Subway"}


def test_undo_takes_back_one_change_then_the_one_before(tmp_path):
    text = document_text((1, "Car", "10.0"), (2, "Van", "20.0"))
    labels = frame(tmp_path, text)
    first, second = (e.key for e in labels.entries)
    labels.delete(first)
    labels.set_label(second, "Truck")
    assert labels.undo()
    assert [e.detection["label"] for e in labels.entries] == ["Van"]
    assert labels.undo()
    assert labels.text() == text
    assert not labels.undo()


def test_one_drag_undoes_as_one_change(tmp_path):
    labels = frame(tmp_path, document_text((1, "Car", "10.0")))
    key = labels.entries[0].key
    labels.begin_gesture()
    for x in (10.5, 11.0, 11.5):  # rviz sends the pose many times during a drag
        labels.move_to_pose(key, (x, 2.0, -1.0), (0.0, 0.0, 0.0, 1.0))
    labels.end_gesture()
    labels.undo()
    assert labels.entries[0].box.centre == (10.0, 2.0, -1.0)


def test_a_new_box_gets_the_next_id_and_the_frames_header(tmp_path):
    labels = frame(tmp_path, document_text((8000, "Car", "10.0"), (8003, "Car", "20.0")))
    key = labels.add("Cyclist", Cuboid((5.0, 1.0, -1.0), (1.75, 0.6, 1.7), yawed(0.3)))
    created = json.loads(labels.text())["detections"][-1]
    assert created["id"] == 8004 and created["label"] == "Cyclist"
    assert created["header"] == json.loads(labels.text())["header"]
    assert labels.find(key).box.size == (1.75, 0.6, 1.7)


def test_a_frame_without_a_file_starts_empty(tmp_path):
    labels = frame(tmp_path, None)
    assert labels.entries == ()
    labels.add("Car", Cuboid((5.0, 1.0, -1.0), (4.5, 1.8, 1.5)))
    document = json.loads(labels.text())
    assert document["header"] == {"stamp": {"secs": 1586102742, "nsecs": 100000000},
                                  "frame_id": "velodyne", "seq": 0}
    assert len(document["detections"]) == 1


def test_a_box_that_cannot_be_drawn_is_kept_as_it_is(tmp_path):
    text = document_text((1, "Car", "10.0")).replace('"size": {"x": 4.5', '"size": {"x": 0')
    labels = frame(tmp_path, text)
    assert labels.boxes() == [] and "zero or negative size" in labels.entries[0].unusable
    assert labels.text() == text


# ------------------------------------------------------------------------------ the config

def test_the_shipped_config_is_the_defaults(repo_root):
    assert load_config(repo_root / "config" / "labelling.yaml") == LabellingConfig()


def test_config_errors_name_the_key(tmp_path):
    config = tmp_path / "labelling.yaml"
    config.write_text("handles:\n  width: -1\n")
    with pytest.raises(ConfigError, match="handles.width"):
        load_config(config)
