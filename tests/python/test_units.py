"""Clouds in millimetres from Python: refused naming the units unless the sensor says
"units": "mm", then planned as the program plans the same files with the same units."""
import json
import os
import subprocess

import numpy as np
import pytest
from conftest import plain, write_scene

import forcegrasp


def mm_sensor(scene, name, **extra):
    return {"points": scene.points[name] * np.float32(1000), "pose": scene.poses[name], **extra}


def test_millimetres_are_refused_naming_the_units(scene):
    with pytest.raises(ValueError, match="invalid_argument: head: .*likely in millimetres"):
        forcegrasp.Planner().plan(head=mm_sensor(scene, "head"))


def test_declared_millimetres_plan_as_the_program(scene, program, tmp_path):
    sensors = {name: mm_sensor(scene, name, units="mm") for name in ("head", "hand")}
    r = forcegrasp.Planner().plan(**sensors)
    assert r["status"] == "ok"
    path = write_scene(tmp_path, {n: s["points"] for n, s in sensors.items()}, scene.poses)
    manifest = json.load(open(path))
    for s in manifest["sensors"]:
        s["units"] = "mm"
    json.dump(manifest, open(path, "w"))
    out = subprocess.run([program, "plan", path, "--json"], capture_output=True, text=True, check=False)
    assert out.returncode == 0
    assert plain(r) == plain(json.loads(out.stdout))
    # And the program's --units says the same as the manifest's.
    for s in manifest["sensors"]:
        del s["units"]
    json.dump(manifest, open(path, "w"))
    out = subprocess.run([program, "plan", path, "--json", "--units", "head=mm", "--units", "hand=mm"],
                         capture_output=True, text=True, check=False)
    assert out.returncode == 0 and plain(r) == plain(json.loads(out.stdout))
    out = subprocess.run([program, "plan", path, "--json"], capture_output=True, text=True, check=False)
    assert out.returncode == 2 and "millimetres" in json.loads(out.stdout)["error"]


@pytest.mark.parametrize(
    "extra, words",
    [
        ({"units": "inch"}, 'units must be "m", "cm" or "mm"'),
        ({"units": 0.001}, 'units must be "m", "cm" or "mm"'),
    ],
)
def test_bad_units(scene, extra, words):
    with pytest.raises(ValueError, match=words):
        forcegrasp.Planner().plan(head=mm_sensor(scene, "head", **extra))


def test_depth_images_have_no_units(scene):
    with pytest.raises(ValueError, match="a depth image is in millimetres"):
        forcegrasp.Planner().plan(head=dict(scene.depth_sensor("head"), units="mm"))


def test_units_do_not_outlive_a_plan(scene):
    planner = forcegrasp.Planner()
    assert planner.plan(head=mm_sensor(scene, "head", units="mm"))["status"] in ("ok", "no_grasp")
    r = planner.plan(head=(scene.points["head"], scene.poses["head"]))  # metres again
    assert r["status"] in ("ok", "no_grasp") and r["points"]["after_filter"] > 0
