"""Shared pieces of the Python module's tests: the module, the program to compare
with, a box on a table seen by two depth cameras (ray-cast, noise-free), and the
files that give the same scene to `forcegrasp plan`.

ctest sets PYTHONPATH to the module's folder and FG_PROGRAM to the program; run by
hand, the host-release build's are used."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(ROOT, "build", "host-release")
try:
    import forcegrasp  # noqa: F401
except ImportError:
    sys.path.insert(0, os.path.join(BUILD, "python"))

# A 320x240 camera: focal length and principal point in pixels.
WIDTH, HEIGHT = 320, 240
INTRINSICS = (262.5, 262.5, 159.5, 119.5)
# The table top (z = 0, x 0.1..0.9, y -0.4..0.4) and a box standing on it.
BOX_MIN = np.array([0.475, -0.04, 0.0])
BOX_MAX = np.array([0.525, 0.04, 0.12])


def look_at(eye, target):
    """world_T_sensor of a camera at eye looking at target: optical frame, z along the
    view, x right, y down."""
    eye = np.asarray(eye, dtype=np.float64)
    z = np.asarray(target, dtype=np.float64) - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = x, y, z, eye
    return pose


def render_depth(pose, boxes=((BOX_MIN, BOX_MAX),)):
    """The depth image (uint16 mm, 0 = no return) of the table and the boxes (min, max)
    standing on it."""
    fx, fy, cx, cy = INTRINSICS
    u, v = np.meshgrid(np.arange(WIDTH), np.arange(HEIGHT))
    ray = np.stack([(u - cx) / fx, (v - cy) / fy, np.ones(u.shape)], axis=-1)  # z = 1: t is the depth
    d = ray @ pose[:3, :3].T
    o = pose[:3, 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        t_table = -o[2] / d[..., 2]
        hit = o + t_table[..., None] * d
        on_table = (t_table > 0) & (np.abs(hit[..., 0] - 0.5) <= 0.4) & (np.abs(hit[..., 1]) <= 0.4)
        t = np.where(on_table, t_table, np.inf)
        for box_min, box_max in boxes:
            t1, t2 = (box_min - o) / d, (box_max - o) / d
            t_in = np.nanmax(np.minimum(t1, t2), axis=-1)
            t_out = np.nanmin(np.maximum(t1, t2), axis=-1)
            on_box = (t_in <= t_out) & (t_in > 0) & (t_in < t)
            t = np.where(on_box, t_in, t)
    return np.where(np.isfinite(t), np.round(t * 1000.0), 0).astype(np.uint16)


def depth_to_points(depth):
    """The organized cloud (H, W, 3) float32 the planner makes of a depth image, with
    its arithmetic in its order (Planner::add_depth_image); NaN where depth is 0."""
    fx, fy, cx, cy = (np.float32(k) for k in INTRINSICS)
    u, v = np.meshgrid(np.arange(depth.shape[1], dtype=np.float32), np.arange(depth.shape[0], dtype=np.float32))
    z = depth.astype(np.float32) * np.float32(0.001)
    x = (u - cx) * (np.float32(1) / fx) * z
    y = ((v - cy) * (np.float32(1) / fy)) * z
    pts = np.stack([x, y, z], axis=-1)
    pts[depth == 0] = np.nan
    return pts


class Scene:
    """The box scene (or boxes) from a head camera and a wrist camera."""

    def __init__(self, boxes=((BOX_MIN, BOX_MAX),)):
        self.boxes = boxes
        self.poses = {
            "head": look_at([0.0, -0.15, 0.75], [0.5, 0.0, 0.05]),
            "hand": look_at([0.5, 0.42, 0.42], [0.5, 0.0, 0.05]),
        }
        self.depth = {name: render_depth(pose, boxes) for name, pose in self.poses.items()}
        self.organized = {name: depth_to_points(d) for name, d in self.depth.items()}
        # The returns alone, in image order: the points a depth image gives the planner.
        self.points = {name: o[self.depth[name] > 0] for name, o in self.organized.items()}

    def depth_sensor(self, name):
        return {"depth": self.depth[name], "intrinsics": INTRINSICS, "pose": self.poses[name]}


@pytest.fixture(scope="session")
def scene():
    return Scene()


# Three boxes apart on the table: the centre one of the box scene, one to its left
# (y > 0) and one nearer the head camera and to its right.
THREE_BOXES = (
    (BOX_MIN, BOX_MAX),
    (np.array([0.47, 0.17, 0.0]), np.array([0.53, 0.23, 0.10])),
    (np.array([0.33, -0.24, 0.0]), np.array([0.37, -0.16, 0.08])),
)


@pytest.fixture(scope="session")
def three_boxes():
    return Scene(THREE_BOXES)


@pytest.fixture(scope="session")
def program():
    path = os.environ.get("FG_PROGRAM", os.path.join(BUILD, "platform", "host", "cli", "forcegrasp"))
    if not os.access(path, os.X_OK):
        pytest.skip("the forcegrasp program is not built: " + path)
    return path


def write_pcd(path, points):
    """A DATA binary PCD of float32 x y z: organized when points is (H, W, 3)."""
    pts = np.ascontiguousarray(points, dtype=np.float32)
    height, width = (pts.shape[0], pts.shape[1]) if pts.ndim == 3 else (1, pts.shape[0])
    header = (
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        "WIDTH %d\nHEIGHT %d\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA binary\n" % (width, height, width * height)
    )
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(pts.astype("<f4").tobytes())


def write_scene(folder, clouds, poses):
    """scene.json naming one PCD per sensor (head first); its path."""
    sensors = []
    for name in ("head", "hand"):
        if name not in clouds:
            continue
        write_pcd(os.path.join(folder, name + ".pcd"), clouds[name])
        pose = poses[name]
        sensors.append(
            {
                "name": name,
                "cloud": name + ".pcd",
                "pose": {"position": pose[:3, 3].tolist(), "rotation": pose[:3, :3].tolist()},
            }
        )
    path = os.path.join(str(folder), "scene.json")
    with open(path, "w") as f:
        json.dump({"sensors": sensors}, f)
    return path


def program_report(program, scene_path, *options):
    """`forcegrasp plan SCENE --json [--set ...]`'s report."""
    sets = [a for o in options for a in ("--set", o)]
    out = subprocess.run([program, "plan", scene_path, "--json"] + sets, capture_output=True, text=True, check=False)
    return json.loads(out.stdout)


def plain(report):
    """A report as JSON gives it, without its times: numpy arrays as lists."""
    if isinstance(report, dict):
        return {k: plain(v) for k, v in report.items() if k != "timing_us"}
    if isinstance(report, list):
        return [plain(v) for v in report]
    if isinstance(report, np.ndarray):
        return report.tolist()
    return report
