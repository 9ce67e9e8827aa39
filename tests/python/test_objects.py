"""Every object on the table and a chosen target from Python, as `forcegrasp plan
--objects all / --target / --target-box` gives them: three boxes apart on a table,
each grasped across itself; bad targets refused with the status's name."""
import json
import subprocess

import numpy as np
import pytest
from conftest import THREE_BOXES, plain, write_scene

import forcegrasp


def sensors(scene):
    return {name: (scene.points[name], scene.poses[name]) for name in ("head", "hand")}


def program_json(program, path, *args):
    out = subprocess.run([program, "plan", path, "--json", *args], capture_output=True, text=True, check=False)
    return out.returncode, json.loads(out.stdout)


def box_of(point):
    """The index of the box (of THREE_BOXES) holding a point within 1 cm, or None."""
    for k, (lo, hi) in enumerate(THREE_BOXES):
        if np.all(point >= lo - 0.01) and np.all(point <= hi + 0.01):
            return k
    return None


def test_objects_all_as_the_program(three_boxes, program, tmp_path):
    r = forcegrasp.Planner().plan(**sensors(three_boxes), objects="all", top=2)
    code, cli = program_json(program, write_scene(tmp_path, three_boxes.points, three_boxes.poses),
                             "--objects", "all", "--top", "2")
    assert code == 0
    assert plain(r) == plain(cli)
    objects = r["objects"]
    assert len(objects) == 3 and r["objects_dropped"] == 0
    # Nearest the workspace centre (0.5, 0) first; the first is the plan's target.
    assert [o["target"] for o in objects] == [True, False, False]
    held = set()
    for o in objects:
        k = box_of(o["centroid"])
        assert k is not None, o["centroid"]
        lo, hi = THREE_BOXES[k]
        assert isinstance(o["centroid"], np.ndarray) and isinstance(o["box"]["min"], np.ndarray)
        assert np.all(o["box"]["min"] >= lo - 0.011) and np.all(o["box"]["max"] <= hi + 0.011)
        assert o["status"] == "ok", o.get("message")
        assert box_of(o["grasp"]["position"]) == k  # its grasp lies on it, not on another
        assert 1 <= len(o["grasps"]) <= 2 and o["grasps"][0]["rank"] == 0
        held.add(k)
    assert held == {0, 1, 2}
    np.testing.assert_array_equal(objects[0]["grasp"]["position"], r["grasp"]["position"])


def test_target_point_and_box(three_boxes, program, tmp_path):
    path = write_scene(tmp_path, three_boxes.points, three_boxes.poses)
    planner = forcegrasp.Planner()
    for k, (lo, hi) in enumerate(THREE_BOXES):
        top_centre = (lo + hi) / 2
        top_centre[2] = hi[2]
        r = planner.plan(**sensors(three_boxes), target=top_centre)
        assert r["status"] == "ok" and box_of(r["grasp"]["position"]) == k
        code, cli = program_json(program, path, "--target", ",".join(str(v) for v in top_centre))
        assert code == 0 and plain(r) == plain(cli)
        box = np.concatenate([lo - 0.005, hi + 0.005])
        r = planner.plan(**sensors(three_boxes), target_box=box)
        assert r["status"] == "ok" and box_of(r["grasp"]["position"]) == k
        code, cli = program_json(program, path, "--target-box", ",".join(str(v) for v in box))
        assert code == 0 and plain(r) == plain(cli)


def test_empty_target_box_is_no_object(three_boxes):
    r = forcegrasp.Planner().plan(**sensors(three_boxes), target_box=(0.7, 0.2, 0.0, 0.8, 0.3, 0.2))
    assert r["status"] == "no_grasp" and r["reason"] == "no_object"
    assert "target box" in r["message"]


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"target": (0.5, 0.0)}, ValueError, "invalid_argument: target must be 3 numbers"),
        ({"target": (0.5, np.nan, 0.0)}, ValueError, "non_finite: target"),
        ({"target": ("a", "b", "c")}, TypeError, "target must be numbers"),
        ({"target": (5.0, 0.0, 0.0)}, ValueError, "invalid_argument: the target point lies outside the workspace"),
        ({"target_box": (0.6, 0.0, 0.0, 0.5, 0.1, 0.1)}, ValueError, "target box: a minimum is above its maximum"),
        ({"target_box": (0, 0, 0, 1, 1)}, ValueError, "target_box must be 6 numbers"),
        ({"target_box": (3, 3, 0, 4, 4, 1)}, ValueError, "the target box does not overlap the workspace"),
        ({"target": (0.5, 0, 0), "target_box": (0, 0, 0, 1, 1, 1)}, ValueError, "not both"),
        ({"objects": "some"}, ValueError, "objects must be None or"),
        ({"objects": 1}, ValueError, "objects must be None or"),
    ],
)
def test_bad_targets(three_boxes, kwargs, error, words):
    with pytest.raises(error, match=words):
        forcegrasp.Planner().plan(**sensors(three_boxes), **kwargs)


def test_table_without_objects():
    """A bare table: no target, no object, and `objects` is an empty list."""
    from conftest import Scene

    r = forcegrasp.Planner().plan(**sensors(Scene(boxes=())), objects="all", top=3)
    assert r["status"] == "no_grasp" and r["reason"] == "no_object"
    assert r["objects"] == [] and r["objects_dropped"] == 0 and "grasps" not in r
