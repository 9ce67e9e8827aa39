"""The Python module plans as `forcegrasp plan` does, from every layout it takes,
refuses bad input with the right exception, takes the program's options, and plans
on two threads at once."""
import json
import os
import subprocess
import threading

import numpy as np
import pytest
from conftest import INTRINSICS, ROOT, plain, program_report, write_scene

import forcegrasp

EXAMPLE = os.path.join(ROOT, "examples", "two-sensor-box")


def pose_of(p):
    """A scene file's pose as a 4x4 world_T_sensor."""
    pose = np.eye(4)
    pose[:3, :3] = p["rotation"]
    pose[:3, 3] = p["position"]
    return pose


def both(scene, clouds):
    return {name: (clouds[name], scene.poses[name]) for name in ("head", "hand")}


@pytest.fixture(scope="module")
def planner():
    return forcegrasp.Planner()


@pytest.fixture(scope="module")
def reference(scene, planner):
    """The plan of the scene's returns as float32 (N, 3) arrays."""
    return planner.plan(**both(scene, scene.points))


# --- the same plans as the program -------------------------------------------------


def test_example_scene_as_the_program(program):
    """The example read with Open3D (float64 points of the float32 files) plans exactly as
    the program plans it: the float64 -> float32 conversion gives back the files' floats,
    so the report is the same to the last bit, not only within 1e-6."""
    o3d = pytest.importorskip("open3d")
    with open(os.path.join(EXAMPLE, "scene.json")) as f:
        manifest = json.load(f)
    sensors = {}
    for s in manifest["sensors"]:
        cloud = o3d.io.read_point_cloud(os.path.join(EXAMPLE, s["cloud"]), remove_nan_points=False)
        sensors[s["name"]] = (np.asarray(cloud.points), pose_of(s["pose"]))
    gripper = manifest["gripper"]
    r = forcegrasp.Planner(gripper=gripper).plan(**sensors)
    cli = program_report(program, os.path.join(EXAMPLE, "scene.json"))
    assert r["status"] == cli["status"] == "ok"
    g, cg = r["grasp"], cli["grasp"]
    for k in ("position", "approach", "closing", "pregrasp"):
        assert isinstance(g[k], np.ndarray) and g[k].shape == (3,) and g[k].dtype == np.float64
        np.testing.assert_allclose(g[k], cg[k], rtol=0, atol=1e-6)
    assert g["width"] == pytest.approx(cg["width"], abs=1e-6)
    assert plain(r) == plain(cli)  # and in fact bit for bit, every key
    assert set(r["timing_us"]) >= {"ingest", "plane", "cluster", "frame", "xoy", "xoz", "select", "total"}
    assert r["points"]["input"] == 2 * 640 * 480


def test_points_as_the_program(scene, reference, program, tmp_path):
    assert reference["status"] == "ok"
    assert reference["grasp"]["width"] == pytest.approx(0.05, abs=0.005)  # the box's 5 cm side
    assert plain(reference) == plain(program_report(program, write_scene(tmp_path, scene.points, scene.poses)))


def test_top_grasps_as_the_program(scene, program, tmp_path):
    """top=N gives the program's --top N list: the returned grasp first, numpy vectors."""
    r = forcegrasp.Planner().plan(**both(scene, scene.points), top=3)
    path = write_scene(tmp_path, scene.points, scene.poses)
    out = subprocess.run([program, "plan", path, "--json", "--top", "3"], capture_output=True, text=True, check=False)
    cli = json.loads(out.stdout)
    assert r["status"] == "ok" and 1 <= len(r["grasps"]) <= 3
    assert plain(r) == plain(cli)
    assert r["grasps"][0]["rank"] == 0 and isinstance(r["grasps"][0]["closing"], np.ndarray)
    assert "grasps" not in forcegrasp.Planner().plan(**both(scene, scene.points))
    for bad, error in ((0, ValueError), (99, ValueError), (1.5, TypeError), (True, TypeError)):
        with pytest.raises(error, match="top"):
            forcegrasp.Planner().plan(**both(scene, scene.points), top=bad)


def test_organized_as_the_program(scene, planner, program, tmp_path):
    r = planner.plan(**both(scene, scene.organized))
    assert plain(r) == plain(program_report(program, write_scene(tmp_path, scene.organized, scene.poses)))


def test_option_as_the_program(scene, program, tmp_path):
    r = forcegrasp.Planner(config={"voxel_leaf": 0.004, "extend_search": False}).plan(**both(scene, scene.points))
    scene_path = write_scene(tmp_path, scene.points, scene.poses)
    assert plain(r) == plain(program_report(program, scene_path, "voxel_leaf=0.004", "extend_search=false"))
    assert plain(r) != plain(program_report(program, scene_path))


def test_head_alone_as_the_program(scene, planner, program, tmp_path):
    r = planner.plan(head=(scene.points["head"], scene.poses["head"]))
    clouds = {"head": scene.points["head"]}
    assert plain(r) == plain(program_report(program, write_scene(tmp_path, clouds, scene.poses)))


# --- every layout plans alike ---------------------------------------------------------


def test_float64(scene, planner, reference):
    f64 = {k: v.astype(np.float64) for k, v in scene.points.items()}
    assert plain(planner.plan(**both(scene, f64))) == plain(reference)


def test_organized_float32_float64_and_flattened(scene, planner):
    organized = planner.plan(**both(scene, scene.organized))
    f64 = {k: v.astype(np.float64) for k, v in scene.organized.items()}
    flat = {k: v.reshape(-1, 3) for k, v in scene.organized.items()}
    assert plain(planner.plan(**both(scene, f64))) == plain(organized)
    assert plain(planner.plan(**both(scene, flat))) == plain(organized)


@pytest.mark.parametrize(
    "view",
    [
        "padded16",  # PCL's PointXYZ: x y z and a pad, 16 bytes apart (read in place)
        "every_other_row",  # a strided view (read in place, 24 bytes apart)
        "fortran",  # x, then y, then z columns: converted once
        "big_endian",  # not the host's byte order: converted once
        "list",  # a nested Python list
    ],
)
def test_views_and_layouts(scene, planner, reference, view):
    def make(pts):
        if view == "padded16":
            a = np.zeros((len(pts), 4), dtype=np.float32)
            a[:, :3] = pts
            return a[:, :3]
        if view == "every_other_row":
            a = np.zeros((2 * len(pts), 3), dtype=np.float32)
            a[::2] = pts
            return a[::2]
        if view == "fortran":
            return np.asfortranarray(pts)
        if view == "big_endian":
            return pts.astype(">f4")
        return pts.tolist()

    clouds = {k: make(v) for k, v in scene.points.items()}
    if view in ("padded16", "every_other_row", "fortran"):
        assert not clouds["head"].flags.c_contiguous
    assert plain(planner.plan(**both(scene, clouds))) == plain(reference)


def test_organized_view(scene, planner):
    """An organized cloud whose rows are not evenly spaced (a crop of a larger image)."""
    big = {k: np.pad(v, ((0, 0), (0, 7), (0, 0)), constant_values=np.nan) for k, v in scene.organized.items()}
    view = {k: v[:, :-7] for k, v in big.items()}
    assert plain(planner.plan(**both(scene, view))) == plain(planner.plan(**both(scene, scene.organized)))


def test_float32_is_read_in_place(scene, planner):
    """float32 points evenly spaced go to the planner without a copy; float64 ones are
    converted once (numpy's allocations are traced)."""
    import tracemalloc

    pts = np.tile(scene.points["head"], (8, 1))
    padded = np.zeros((len(pts), 4), dtype=np.float32)
    padded[:, :3] = pts
    f64 = pts.astype(np.float64)

    def peak(points):
        tracemalloc.start()
        try:
            planner.plan(head=(points, scene.poses["head"]))
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    assert peak(pts) < pts.nbytes / 10
    assert peak(padded[:, :3]) < pts.nbytes / 10
    assert peak(f64) >= pts.nbytes


def test_input_is_left_unchanged(scene, planner):
    before = scene.points["head"].copy()
    planner.plan(**both(scene, scene.points))
    np.testing.assert_array_equal(scene.points["head"], before)


def test_depth_images(scene, planner, reference):
    """Depth images plan as the points the planner makes of them; the report counts
    every pixel as input."""
    r = planner.plan(head=scene.depth_sensor("head"), hand=scene.depth_sensor("hand"))
    assert r["points"]["input"] == scene.depth["head"].size + scene.depth["hand"].size
    r["points"]["input"] = reference["points"]["input"]
    assert plain(r) == plain(reference)
    assert plain(planner.plan(**both(scene, scene.organized))) == plain(
        planner.plan(head=scene.depth_sensor("head"), hand=scene.depth_sensor("hand"))
    )


def test_depth_image_view(scene, planner):
    """A depth image that is a view (every other column of a wider one) is copied."""
    wide = {k: np.repeat(v, 2, axis=1) for k, v in scene.depth.items()}
    sensors = {k: {"depth": wide[k][:, ::2], "intrinsics": INTRINSICS, "pose": scene.poses[k]} for k in wide}
    assert plain(planner.plan(**sensors)) == plain(
        planner.plan(head=scene.depth_sensor("head"), hand=scene.depth_sensor("hand"))
    )


def test_dict_with_points(scene, planner, reference):
    sensors = {k: {"points": scene.points[k], "pose": scene.poses[k]} for k in ("head", "hand")}
    assert plain(planner.plan(**sensors)) == plain(reference)


def test_report_values(reference):
    g = reference["grasp"]
    for k in ("position", "approach", "closing", "pregrasp"):
        assert isinstance(g[k], np.ndarray) and g[k].shape == (3,) and g[k].dtype == np.float64
    assert reference["support_plane"]["normal"].shape == (3,)
    assert isinstance(reference["points"]["voxels"], int) and isinstance(g["width"], float)
    assert isinstance(g["family"], str) and isinstance(reference["search"]["rejected"], dict)
    assert abs(np.linalg.norm(g["approach"]) - 1) < 1e-5 and abs(g["approach"] @ g["closing"]) < 1e-5
    assert g["checks"]["support_plane"]["unit"] == "m"
    assert "robot_reach" not in g["checks"] and "joints" not in reference


def test_joints_check_the_reach(scene, planner):
    r = planner.plan(**both(scene, scene.points), joints=[0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0])
    assert r["status"] == "ok"
    assert "robot_reach" in r["grasp"]["checks"]
    assert [len(r["joints"][k]) for k in ("pregrasp", "grasp", "lift")] == [6, 6, 6]


def test_no_grasp(scene, planner):
    """Points that all lie beyond the range filter: a valid input with no grasp."""
    far = np.full((100, 3), 5.0, dtype=np.float32)
    r = planner.plan(head=(far, scene.poses["head"]))
    assert r["status"] == "no_grasp" and r["reason"] == "no_points" and r["message"]
    assert "grasp" not in r


# --- bad input is refused before the core sees it -------------------------------------


def bad_pose(kind):
    pose = np.eye(4)
    pose[:3, 3] = [0.1, 0.0, 0.8]
    if kind == "nan":
        pose[0, 3] = np.nan
    elif kind == "scaled":
        pose[:3, :3] *= 1.1
    elif kind == "reflection":
        pose[0, 0] = -1.0
    elif kind == "last_row":
        pose[3, 0] = 0.5
    elif kind == "far":
        pose[0, 3] = 150.0
    elif kind == "shape":
        pose = pose[:3]
    elif kind == "strings":
        pose = np.array([["1"] * 4] * 4)
    return pose


GOOD = np.array([[0.0, 0.0, 1.0]], dtype=np.float32)
DEPTH = np.full((4, 5), 1000, dtype=np.uint16)


@pytest.mark.parametrize(
    "head, error, words",
    [
        ((GOOD.astype(np.int32), np.eye(4)), TypeError, "head points must be float32 or float64, not int32"),
        ((GOOD.astype(np.float16), np.eye(4)), TypeError, "float32 or float64"),
        ((np.zeros((5, 2), np.float32), np.eye(4)), ValueError, "shape (N, 3) or (H, W, 3), not (5, 2)"),
        ((np.zeros(6, np.float32), np.eye(4)), ValueError, "not (6,)"),
        ((np.zeros((0, 3), np.float32), np.eye(4)), ValueError, "head points are empty"),
        ((np.zeros((2, 0, 3), np.float32), np.eye(4)), ValueError, "empty"),
        (("points", np.eye(4)), TypeError, "head points must be float32 or float64"),
        ((GOOD, bad_pose("nan")), ValueError, "non_finite: head pose has a NaN or Inf value"),
        ((GOOD, bad_pose("scaled")), ValueError, "invalid_pose: head pose rotation is not orthonormal"),
        ((GOOD, bad_pose("reflection")), ValueError, "invalid_pose: head pose rotation is a reflection"),
        ((GOOD, bad_pose("last_row")), ValueError, "invalid_pose: head pose's last row is not [0, 0, 0, 1]"),
        ((GOOD, bad_pose("far")), ValueError, "invalid_pose: head pose position is more than 100 m"),
        ((GOOD, bad_pose("shape")), ValueError, "head pose must have shape (4, 4), not (3, 4)"),
        ((GOOD, bad_pose("strings")), TypeError, "head pose must be a 4x4 array of numbers"),
        ((GOOD,), ValueError, "head must be (points, pose), not 1 items"),
        (GOOD, TypeError, "head must be a (points, pose) tuple or a dict"),
        ({"points": GOOD}, ValueError, 'head: no "pose"'),
        ({"points": GOOD, "pose": np.eye(4), "colour": 1}, ValueError, 'head: unknown key "colour"'),
        ({"points": GOOD, "depth": DEPTH, "pose": np.eye(4)}, ValueError, 'give "points" or "depth"'),
        ({"points": GOOD, "pose": np.eye(4), "intrinsics": INTRINSICS}, ValueError, "belong to a depth image"),
        ({"depth": DEPTH, "pose": np.eye(4)}, ValueError, 'invalid_argument: head depth needs "intrinsics"'),
        ({"depth": DEPTH.astype(np.float32), "pose": np.eye(4), "intrinsics": INTRINSICS}, TypeError, "uint16"),
        ({"depth": DEPTH[None], "pose": np.eye(4), "intrinsics": INTRINSICS}, ValueError, "shape (H, W)"),
        ({"depth": DEPTH[:0], "pose": np.eye(4), "intrinsics": INTRINSICS}, ValueError, "head depth is empty"),
        ({"depth": DEPTH, "pose": np.eye(4), "intrinsics": (1.0, 2.0, 3.0)}, TypeError, "four numbers"),
        ({"depth": DEPTH, "pose": np.eye(4), "intrinsics": (np.nan, 500, 2, 2)}, ValueError, "non_finite"),
        ({"depth": DEPTH, "pose": np.eye(4), "intrinsics": (0.5, 500, 2, 2)}, ValueError, "invalid_argument"),
    ],
)
def test_bad_sensor(planner, reference, scene, head, error, words):
    with pytest.raises(error) as e:
        planner.plan(head=head)
    assert words in str(e.value)
    # The planner is whole after it: the next plan is the same as before.
    assert plain(planner.plan(**both(scene, scene.points))) == plain(reference)


def test_hand_is_named(planner):
    with pytest.raises(ValueError, match="non_finite: hand pose"):
        planner.plan(hand=(GOOD, bad_pose("nan")))


def test_no_sensor(planner):
    with pytest.raises(ValueError, match="no_input"):
        planner.plan()
    with pytest.raises(TypeError):
        planner.plan(GOOD)  # the sensors are keywords


@pytest.mark.parametrize(
    "joints, error, words",
    [
        ([0.0] * 5, ValueError, "joints must be 6 angles"),
        ([0.0] * 5 + [np.inf], ValueError, "non_finite: joints"),
        (["a"] * 6, TypeError, "joints must be numbers"),
    ],
)
def test_bad_joints(planner, joints, error, words):
    with pytest.raises(error, match=words):
        planner.plan(head=(GOOD, np.eye(4)), joints=joints)


def test_core_status_error():
    """Too many points for the voxel grid at the smallest crop box: the core's
    capacity_exceeded, a ValueError with the status name and the planner's message."""
    rng = np.random.default_rng(1)
    pts = rng.uniform([-0.45, -0.45, 0.4], [0.45, 0.45, 1.4], size=(300_000, 3)).astype(np.float32)
    down = np.diag([1.0, -1.0, -1.0, 1.0])  # looking down from 1.5 m: the points fill the crop box
    down[:3, 3] = [0.5, 0.0, 1.5]
    planner = forcegrasp.Planner(config={"voxel_leaf": 0.002, "crop_shrink_min": 0.45})
    with pytest.raises(ValueError, match="^capacity_exceeded: head: "):
        planner.plan(head=(pts, down))


# --- options ---------------------------------------------------------------------------


def test_config_values(scene):
    p = forcegrasp.Planner(
        config={"voxel_leaf": 0.004, "ransac_iterations": 150, "extend_search": False, "target_rule": "largest"},
        gripper={"max_opening": 0.07},
    )
    c = p.config
    assert c["voxel_leaf"] == 0.004 and c["ransac_iterations"] == 150
    assert c["extend_search"] is False and c["target_rule"] == "largest"
    assert c["max_opening"] == pytest.approx(0.07) and c["finger_width"] == pytest.approx(0.022)
    # Values as --set takes them: text, numpy numbers.
    q = forcegrasp.Planner(config={"voxel_leaf": "0.004", "ransac_iterations": np.int64(150), "extend_search": "off"})
    assert q.config["voxel_leaf"] == 0.004 and q.config["ransac_iterations"] == 150 and not q.config["extend_search"]
    # The gripper first, then the options: an option overrides the gripper's value.
    assert forcegrasp.Planner(gripper={"max_opening": 0.07}, config={"max_opening": 0.06}).config["max_opening"] == (
        pytest.approx(0.06)
    )


@pytest.mark.parametrize(
    "config, words",
    [
        ({"voxel_size": 0.01}, 'unknown option "voxel_size"'),
        ({"delta": 0.002}, "(it is named scan_delta)"),
        ({"voxel_leaf": "small"}, 'option voxel_leaf: "small" is not a finite number'),
        ({"voxel_leaf": float("nan")}, "voxel_leaf"),
        ({"ransac_iterations": -1}, 'option ransac_iterations: "-1" is not a whole number'),
        ({"ransac_iterations": 1.5}, "ransac_iterations"),
        ({"extend_search": "maybe"}, "is not true or false"),
        ({"target_rule": "first"}, "is not nearest or largest"),
        ({"voxel_leaf": None}, "option voxel_leaf must be a number, boolean or string"),
        ({3: 1}, "option names"),
        ({"voxel_leaf": 0.0}, "invalid_config: configuration value out of range: voxel_leaf"),
    ],
)
def test_bad_config(config, words):
    with pytest.raises(ValueError) as e:
        forcegrasp.Planner(config=config)
    assert words in str(e.value)


@pytest.mark.parametrize(
    "gripper, words",
    [
        ({"max_opening": 0.9}, "gripper.max_opening = 0.900000 is outside 0.005000..0.500000 m"),
        ({"finger_width": "wide"}, "gripper.finger_width must be a finite number"),
        ({"palm": 0.1}, 'gripper: unknown key "palm"'),
    ],
)
def test_bad_gripper(gripper, words):
    with pytest.raises(ValueError) as e:
        forcegrasp.Planner(gripper=gripper)
    assert words in str(e.value)


def test_config_and_gripper_types():
    with pytest.raises(TypeError, match="config must be a dict"):
        forcegrasp.Planner(config=[("voxel_leaf", 0.005)])
    with pytest.raises(TypeError, match="gripper must be a dict"):
        forcegrasp.Planner(gripper=0.085)


def test_default_config_is_the_programs(program):
    defaults = forcegrasp.default_config()
    out = subprocess.run([program, "config"], capture_output=True, text=True, check=True)
    assert defaults == json.loads(out.stdout)
    assert len(defaults) > 40 and defaults["voxel_leaf"] == 0.005 and defaults["target_rule"] == "nearest"
    # A planner with no options holds the defaults but for the scene file's gripper.
    held = forcegrasp.Planner().config
    assert {k: v for k, v in held.items() if k not in ("max_opening", "finger_width", "finger_depth")} == {
        k: v for k, v in defaults.items() if k not in ("max_opening", "finger_width", "finger_depth")
    }
    assert held["finger_width"] == pytest.approx(0.022)


# --- threads ---------------------------------------------------------------------------


def test_two_planners_on_two_threads(scene):
    """Each planner owns its workspace and robot check: planned at once, they give what
    they give one after the other."""
    jobs = [
        both(scene, scene.points),
        {"head": scene.depth_sensor("head"), "hand": scene.depth_sensor("hand")},
        {"head": (scene.organized["head"], scene.poses["head"])},
    ]
    sequential = [plain(forcegrasp.Planner().plan(**j)) for j in jobs]
    results = [[], []]

    def work(slot, order):
        p = forcegrasp.Planner()
        for _ in range(3):
            for i in order:
                results[slot].append((i, plain(p.plan(**jobs[i]))))

    threads = [threading.Thread(target=work, args=(0, [0, 1, 2])), threading.Thread(target=work, args=(1, [2, 0, 1]))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results[0]) == len(results[1]) == 9
    for slot in results:
        for i, r in slot:
            assert r == sequential[i]


def test_one_planner_on_two_threads(scene, planner, reference):
    """Two threads that share one planner take turns: each gets the whole plan."""
    results = []

    def work():
        for _ in range(4):
            results.append(plain(planner.plan(**both(scene, scene.points))))

    threads = [threading.Thread(target=work) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 8 and all(r == plain(reference) for r in results)


def test_the_gil_is_released(scene):
    """While a thread plans, the others run Python: the main thread keeps counting.
    A planner that held the GIL would let it count at most once or twice per plan."""
    p = forcegrasp.Planner()
    jobs = both(scene, scene.points)
    state = {"in_plan": False, "done": False}

    def work():
        for _ in range(5):
            state["in_plan"] = True
            p.plan(**jobs)
            state["in_plan"] = False
        state["done"] = True

    t = threading.Thread(target=work)
    seen_in_plan = 0
    t.start()
    while not state["done"]:
        seen_in_plan += state["in_plan"]
    t.join()
    assert seen_in_plan > 1000
