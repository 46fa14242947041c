"""render_frame: a frame the box-free path saved, drawn from above; and the inputs it refuses."""
import hostile
from test_labelling import document_text

RENDER_FRAME = hostile.tool("granular_tools", "render_frame")
STAMP = "1586102742100000000"


def saved_frame(folder, segments_in_json=1):
    """A frame as evaluate_segmentation --save writes it: a ground point, a point in no segment
    and two points of segment 0, and a JSON of `segments_in_json` segments."""
    folder.mkdir()
    points = [(5.0, 0.0, -1.7, 0.0, -1), (6.0, 1.0, -1.0, 0.7, 0), (10.0, 0.0, -1.0, 0.7, 1),
              (10.5, 0.5, -0.5, 1.2, 1)]
    (folder / (STAMP + ".pcd")).write_text(
        "VERSION 0.7\nFIELDS x y z height segment\nSIZE 4 4 4 4 4\nTYPE F F F F I\n"
        f"COUNT 1 1 1 1 1\nWIDTH {len(points)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
        f"POINTS {len(points)}\nDATA ascii\n"
        + "".join(" ".join(str(v) for v in point) + "\n" for point in points))
    (folder / (STAMP + ".json")).write_text(
        document_text(*[(k, "unknown", "10.0") for k in range(segments_in_json)]))
    return folder


def test_a_saved_frame_is_drawn_into_a_png(tmp_path):
    saved = saved_frame(tmp_path / "saved")
    out = tmp_path / "frame.png"
    result = hostile.run(RENDER_FRAME + ["--saved", saved, "--stamp", STAMP, "--out", out,
                                         "--extent", "0,20,-10,10"])
    assert result.status == 0, str(result)
    assert out.read_bytes().startswith(b"\x89PNG")


def test_points_of_a_segment_the_json_lacks_are_named_not_a_traceback(tmp_path):
    saved = saved_frame(tmp_path / "saved", segments_in_json=0)
    result = hostile.run(RENDER_FRAME + ["--saved", saved, "--stamp", STAMP,
                                         "--out", tmp_path / "frame.png"])
    hostile.assert_fails_clearly(result, 1, STAMP + ".pcd", "lists 0 segments")
    assert not (tmp_path / "frame.png").exists()


def test_bad_options_are_exit_2_before_any_drawing(tmp_path):
    saved = saved_frame(tmp_path / "saved")
    base = RENDER_FRAME + ["--saved", saved, "--stamp", STAMP]
    for extra, named in (
            (["--extent", "nan,1,2,3"], "--extent"),
            (["--extent", "0,1e-300,0,1"], "--extent"),
            (["--extent=-1e308,1e308,-1,1"], "--extent"),
            (["--extent", "0,1000,0,1"], "--extent"),
            (["--truth", tmp_path / "nowhere"], "nowhere"),
            (["--cuboids", tmp_path / "nowhere"], "nowhere")):
        result = hostile.run(base + ["--out", tmp_path / "frame.png"] + extra)
        hostile.assert_fails_clearly(result, 2, named)
    notes = tmp_path / "notes.txt"
    result = hostile.run(base + ["--out", notes])
    hostile.assert_fails_clearly(result, 2, "FILE.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["saved"]
