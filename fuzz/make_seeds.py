#!/usr/bin/env python3
"""Writes the small crafted seed corpora of fuzz/corpus/<target>/ (python3, no modules
beyond the standard library). Deterministic: rerunning rewrites the same bytes.

  python3 fuzz/make_seeds.py            # from the repository root

pcd/   ascii, binary and binary_compressed (LZF) PCD files: extra fields of every TYPE
       and SIZE, COUNT > 1, padding fields, labels, organized clouds with NaN, POINTS
       without WIDTH, COLUMNS, doubles, an empty cloud; each under 4 KiB.
ply/   ascii and binary_little_endian PLY files: faces and other elements, list
       properties, every scalar type, comments; each under 4 KiB.
scene/ manifests: poses, joints + hand_eye, gripper, minimal.
plan/  inputs in the layout of fuzz/plan_fuzz.cpp: a table and a box seen as a point
       cloud and as a depth image, both sensors, configuration presets and overrides,
       and the invalid cases (NaN / Inf / denormal poses, reflections, bad roles, a
       role twice, null data, small strides, bad intrinsics, empty images); points
       also in pieces through add_point_source; targets by a point or a box (on the
       box, around it, outside the workspace, empty, NaN, Inf, inverted, a raw kind)
       and plan_object / more_grasps on two boxes, out of range and out of sequence.
api/   call sequences in the layout of fuzz/api_fuzz.cpp: captures, plans, bad memory
       and configurations, the grasp task, bogus workspaces; targets, the object list
       and each object's plan, ranked, with null pointers and indices out of range.
The real clouds of ../shared/data/clouds are added at run time by scripts/fuzz.sh.
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
NAN = float("nan")
INF = float("inf")
DENORM = struct.unpack("<f", struct.pack("<I", 1))[0]  # smallest float denormal


def out(target, name, data):
    d = os.path.join(HERE, "corpus", target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)
    if target in ("pcd", "ply"):
        assert len(data) < 4096, (name, len(data))


# ---- LZF (liblzf format, as PCL writes binary_compressed) ----------------------------

def lzf_compress(data):
    """Greedy LZF: literal runs (ctrl 0..31) and back-references (len-2 in 3 bits, 7 ->
    an extra length byte; 13-bit offset)."""
    outb = bytearray()
    lit = bytearray()

    def flush():
        i = 0
        while i < len(lit):
            chunk = lit[i:i + 32]
            outb.append(len(chunk) - 1)
            outb.extend(chunk)
            i += 32
        lit.clear()

    i, n = 0, len(data)
    table = {}
    while i < n:
        best_len, best_off = 0, 0
        if i + 2 < n:
            key = bytes(data[i:i + 3])
            ref = table.get(key)
            table[key] = i
            if ref is not None and 1 <= i - ref <= 8192:
                length = 0
                while i + length < n and length < 264 and data[ref + length] == data[i + length]:
                    length += 1
                if length >= 3:
                    best_len, best_off = length, i - ref - 1
        if best_len:
            flush()
            l = best_len - 2
            if l < 7:
                outb.append((l << 5) | (best_off >> 8))
            else:
                outb.append((7 << 5) | (best_off >> 8))
                outb.append(l - 7)
            outb.append(best_off & 0xFF)
            i += best_len
        else:
            lit.append(data[i])
            i += 1
    flush()
    return bytes(outb)


def lzf_decompress(src, size):
    o = bytearray()
    i = 0
    while i < len(src):
        c = src[i]
        i += 1
        if c < 32:
            o.extend(src[i:i + c + 1])
            i += c + 1
        else:
            l = c >> 5
            if l == 7:
                l += src[i]
                i += 1
            ref = len(o) - ((c & 0x1F) << 8) - src[i] - 1
            i += 1
            for k in range(l + 2):
                o.append(o[ref + k])
    assert len(o) == size
    return bytes(o)


# ---- PCD ----------------------------------------------------------------------------

def pcd_header(fields, sizes, types, counts, width, height, data, viewpoint=True, points=True,
               version=True, comment=True, fields_key="FIELDS"):
    h = ""
    if comment:
        h += "# .PCD v0.7 - Point Cloud Data file format\n"
    if version:
        h += "VERSION 0.7\n"
    h += fields_key + " " + " ".join(fields) + "\n"
    h += "SIZE " + " ".join(str(s) for s in sizes) + "\n"
    h += "TYPE " + " ".join(types) + "\n"
    if counts is not None:
        h += "COUNT " + " ".join(str(c) for c in counts) + "\n"
    if width is not None:
        h += "WIDTH %d\nHEIGHT %d\n" % (width, height)
    if viewpoint:
        h += "VIEWPOINT 0.1 -0.2 0.5 0.9238795 0 0.3826834 0\n"
    if points:
        h += "POINTS %d\n" % ((width or 0) * height if points is True else points)
    h += "DATA " + data + "\n"
    return h.encode()


def pack_value(t, s, v):
    fmt = {("F", 4): "<f", ("F", 8): "<d", ("U", 1): "<B", ("U", 2): "<H", ("U", 4): "<I",
           ("U", 8): "<Q", ("I", 1): "<b", ("I", 2): "<h", ("I", 4): "<i", ("I", 8): "<q"}[(t, s)]
    if t != "F":
        v = int(v)
    return struct.pack(fmt, v)


def scene_points(n):
    """A few points of a table (z = 0) and a box, in metres, NaN for missing pixels."""
    pts = []
    for i in range(n):
        if i % 7 == 3:
            pts.append((NAN, NAN, NAN))
        elif i % 3 == 0:
            pts.append((0.465 + 0.01 * (i % 8), -0.025 + 0.005 * (i % 11), 0.12))
        else:
            pts.append((0.3 + 0.013 * (i % 31), -0.2 + 0.017 * (i % 23), 0.0))
    return pts


def make_pcd():
    xyz = ("x", "y", "z")
    # 1. ascii, the canonical header, special values
    body = "1 2 3\nnan nan nan\n-1 0.5 2e-3\n1e-45 -0 +4.5\ninf -inf 1e39\n"
    out("pcd", "ascii_xyz.pcd", pcd_header(xyz, (4, 4, 4), "FFF", (1, 1, 1), 5, 1, "ascii") + body.encode())
    # 2. ascii, extra fields: rgb, a 3-count normal, a padding field, a label, doubles
    fields = ("x", "y", "z", "rgb", "normal", "_", "label", "curvature")
    sizes = (4, 4, 8, 4, 4, 1, 2, 8)
    types = ("F", "F", "F", "F", "F", "U", "U", "F")
    counts = (1, 1, 1, 1, 3, 2, 1, 1)
    rows = []
    for i, (x, y, z) in enumerate(scene_points(12)):
        rows.append("%r %r %r 4.2108e+06 0 0 1 7 9 %d 0.25" % (x, y, z, i % 4))
    out("pcd", "ascii_extra_fields.pcd",
        pcd_header(fields, sizes, types, counts, 12, 1, "ascii") + ("\n".join(rows) + "\n").encode())
    # 3. binary, organized 4 x 3 with NaN holes
    pts = scene_points(12)
    data = b"".join(struct.pack("<fff", *p) for p in pts)
    out("pcd", "binary_organized.pcd", pcd_header(xyz, (4, 4, 4), "FFF", (1, 1, 1), 4, 3, "binary") + data)
    # 4. binary, mixed fields: label U2, x F4, y F8, z F4, intensity U1, padding I1 x3, rgba U4
    fields = ("label", "x", "y", "z", "intensity", "_", "rgba")
    sizes = (2, 4, 8, 4, 1, 1, 4)
    types = ("U", "F", "F", "F", "U", "I", "U")
    counts = (1, 1, 1, 1, 1, 3, 1)
    data = b""
    for i, (x, y, z) in enumerate(scene_points(10)):
        data += pack_value("U", 2, i % 3) + pack_value("F", 4, x) + pack_value("F", 8, y)
        data += pack_value("F", 4, z) + pack_value("U", 1, 200) + b"\x01\xff\x7f" + pack_value("U", 4, 0xFF8040)
    out("pcd", "binary_mixed_fields.pcd", pcd_header(fields, sizes, types, counts, 10, 1, "binary") + data)
    # 5. binary_compressed x y z (structure of arrays, LZF with back-references)
    pts = scene_points(48)
    soa = b"".join(struct.pack("<%df" % len(pts), *[p[k] for p in pts]) for k in range(3))
    packed = lzf_compress(soa)
    assert lzf_decompress(packed, len(soa)) == soa
    out("pcd", "compressed_xyz.pcd", pcd_header(xyz, (4, 4, 4), "FFF", (1, 1, 1), 8, 6, "binary_compressed")
        + struct.pack("<II", len(packed), len(soa)) + packed)
    # 6. binary_compressed like the mOSD captures: label x y z rgba (U F F F U)
    pts = scene_points(40)
    cols = [[i % 5 for i in range(40)], [p[0] for p in pts], [p[1] for p in pts], [p[2] for p in pts],
            [0x00808080] * 40]
    soa = struct.pack("<40I", *cols[0]) + b"".join(struct.pack("<40f", *c) for c in cols[1:4])
    soa += struct.pack("<40I", *cols[4])
    packed = lzf_compress(soa)
    assert lzf_decompress(packed, len(soa)) == soa
    out("pcd", "compressed_label_rgba.pcd",
        pcd_header(("label", "x", "y", "z", "rgba"), (4, 4, 4, 4, 4), "UFFFU", (1, 1, 1, 1, 1), 8, 5,
                   "binary_compressed") + struct.pack("<II", len(packed), len(soa)) + packed)
    # 7. POINTS without WIDTH, COLUMNS, no COUNT, no VERSION, no VIEWPOINT
    out("pcd", "points_only.pcd",
        pcd_header(xyz, (4, 4, 4), "FFF", None, None, 1, "ascii", viewpoint=False, points=3, version=False,
                   comment=False, fields_key="COLUMNS") + b"0.5 0 0.1\n0.51 0.01 0.1\n0.52 0 0.11\n")
    # 8. doubles, binary, lower-case types
    data = b"".join(struct.pack("<ddd", *p) for p in scene_points(9))
    out("pcd", "binary_double.pcd", pcd_header(xyz, (8, 8, 8), "fff", (1, 1, 1), 9, 1, "binary") + data)
    # 9. an empty cloud, and an empty compressed one
    out("pcd", "empty_binary.pcd", pcd_header(xyz, (4, 4, 4), "FFF", (1, 1, 1), 0, 1, "binary"))
    out("pcd", "empty_compressed.pcd",
        pcd_header(xyz, (4, 4, 4), "FFF", (1, 1, 1), 0, 1, "binary_compressed") + struct.pack("<II", 0, 0))
    # 10. CRLF line ends, tabs, .7 version
    hdr = ("# CRLF\r\nVERSION .7\r\nFIELDS\tx y\tz\r\nSIZE 4 4 4\r\nTYPE F F F\r\nWIDTH 2\r\nHEIGHT 1\r\n"
           "POINTS 2\r\nDATA ascii\r\n0 0 0\r\n1 1 1\r\n")
    out("pcd", "ascii_crlf.pcd", hdr)


# ---- PLY ----------------------------------------------------------------------------

PLY_FMT = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
           "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
           "float": "f", "float32": "f", "double": "d", "float64": "d"}


def make_ply():
    pts = [p for p in scene_points(20) if not math.isnan(p[0])]
    # 1. ascii vertices only
    h = "ply\nformat ascii 1.0\ncomment made by fuzz/make_seeds.py\nelement vertex %d\n" % len(pts)
    h += "property float x\nproperty float y\nproperty float z\nend_header\n"
    out("ply", "ascii_vertices.ply", h + "".join("%r %r %r\n" % p for p in pts))
    # 2. ascii with faces (list uchar int) and an edge element after them
    h = ("ply\nformat ascii 1.0\nobj_info fuzz seed\nelement vertex 4\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\n"
         "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n")
    body = "0 0 0 255\n1 0 0 128\n0 1 0 0\n0 0 1 7\n3 0 1 2\n4 0 1 2 3\n0 3\n"
    out("ply", "ascii_faces.ply", h + body)
    # 3. binary little endian, float xyz + uchar rgb
    h = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n" % len(pts))
    out("ply", "binary_float_rgb.ply", h.encode() + b"".join(struct.pack("<fffBBB", *p, 10, 20, 30) for p in pts))
    # 4. binary, double xyz in another order, faces (uchar count, int32 indices), then a camera element
    h = ("ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty double z\nproperty double x\n"
         "property double y\nelement face 2\nproperty list uchar int vertex_indices\nelement camera 1\n"
         "property float view_px\nend_header\n")
    body = b"".join(struct.pack("<ddd", p[2], p[0], p[1]) for p in pts[:5])
    body += struct.pack("<B3i", 3, 0, 1, 2) + struct.pack("<B4i", 4, 1, 2, 3, 4) + struct.pack("<f", 0.5)
    out("ply", "binary_double_faces.ply", h.encode() + body)
    # 5. every scalar type, ascii, integer coordinates
    types = ["char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8", "int16",
             "uint16", "int32", "uint32", "float32", "float64"]
    h = "ply\nformat ascii 1.0\nelement vertex 3\n"
    for i, t in enumerate(types):
        h += "property %s p%d\n" % (t, i)
    h += "property int16 x\nproperty uint8 y\nproperty float64 z\nend_header\n"
    rows = ["-1 2 -3 4 -5 6 7.5 -8.25 -9 10 -11 12 -13 14 1.5 2.5 %d %d %d" % (i - 1, i, 2 * i) for i in range(3)]
    out("ply", "ascii_all_types.ply", h + "\n".join(rows) + "\n")
    # 6. binary: an element before the vertices, and a list property inside the vertex element
    h = ("ply\nformat binary_little_endian 1.0\nelement material 2\nproperty uchar id\nproperty float shine\n"
         "element vertex 3\nproperty float x\nproperty list ushort short tags\nproperty float y\n"
         "property float z\nend_header\n")
    body = struct.pack("<Bf", 1, 0.5) + struct.pack("<Bf", 2, 0.25)
    body += struct.pack("<fH2hff", 0.1, 2, 5, -5, 0.2, 0.3)
    body += struct.pack("<fHff", 0.4, 0, 0.5, 0.6)
    body += struct.pack("<fH3hff", 0.7, 3, 1, 2, 3, 0.8, NAN)
    out("ply", "binary_list_in_vertex.ply", h.encode() + body)
    # 7. ascii with a list in the vertex element and nan / inf values, version "1"
    h = ("ply\nformat ascii 1\nelement vertex 2\nproperty list uint8 float weights\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n")
    out("ply", "ascii_list_nan.ply", h + "2 0.5 0.5 nan 1 2\n0 +inf -inf 1e-40\n")
    # 8. an empty vertex element, binary
    out("ply", "binary_empty.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 0\n"
        "property float x\nproperty float y\nproperty float z\nend_header\n")


# ---- scene manifests ----------------------------------------------------------------

def make_scene():
    out("scene", "two_sensors.json", """{
 "sensors": [
  {"name": "head", "cloud": "head.pcd",
   "pose": {"position": [0.0268, 0.0852, 0.7659],
            "rotation": [[0.08250259022878527, -0.826693434762604, 0.5565710085208802],
                         [-0.9965908501514257, -0.06843766394472008, 0.04607562857138704],
                         [0.0, -0.5584749332550193, -0.8295213975093121]]}},
  {"name": "hand", "cloud": "/abs/hand.ply",
   "pose": {"position": [0.4384, 0.4115, 0.4672],
            "rotation": [[1, 0, 0], [0, -1, 0], [0, 0, -1]]}}
 ],
 "gripper": {"max_opening": 0.085, "finger_width": 0.022, "finger_depth": 0.04}
}
""")
    out("scene", "joints_hand_eye.json", """{"sensors": [{"name": "hand", "cloud": "../clouds/hand.pcd",
 "joints": [0.0, -1.5707963, 1.5707963, -1.5707963, -1.5707963, 0.0],
 "hand_eye": {"position": [0.0, 0.08, 0.03], "rotation": [[1e0, 0, 0], [0, 1.0, 0], [0, 0, 1]]}}],
 "gripper": {"max_opening": 0.14}}
""")
    out("scene", "joints_only.json",
        '{"sensors":[{"name":"hand","cloud":"c.pcd","joints":[1,2,3,-1,-2,-3]},'
        '{"name":"head","cloud":"h.pcd","pose":{"position":[0,0,1],"rotation":[[1,0,0],[0,1,0],[0,0,1]]}}]}')
    out("scene", "minimal.json", '{"sensors":[{"name":"head","cloud":"x.pcd","pose":{"position":[0,0,0],'
        '"rotation":[[1,0,0],[0,1,0],[0,0,1]]}}],"extra":{"ignored":[null,true,false,"\\u00e9\\n",-0.0,1e-320]}}')


# ---- plan inputs (layout: fuzz/plan_fuzz.cpp) ----------------------------------------

def f32(*vals):
    return struct.pack("<%df" % len(vals), *vals)


def norm(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def look_at(eye, target):
    """The rotation of plan_fuzz.cpp's look-at encoding: columns x, y, z of world_R_sensor."""
    z = norm(tuple(t - e for t, e in zip(target, eye)))
    x = cross(z, (0, 0, 1))
    x = norm(x) if math.sqrt(sum(c * c for c in x)) >= 1e-6 else (1, 0, 0)
    y = cross(z, x)
    return x, y, z


def to_sensor(p, eye, axes):
    d = tuple(a - b for a, b in zip(p, eye))
    return tuple(sum(ax[k] * d[k] for k in range(3)) for ax in axes)  # R^T (p - eye)


BOX_LO, BOX_HI = (0.465, -0.025, 0.0), (0.535, 0.025, 0.12)


def cast(eye, d):
    """Depth along the ray eye + t d of the table top (z = 0, [0.25, 0.75] x [-0.25, 0.25]) and the box."""
    t0, t1, hit = 0.0, 1e9, True
    for a in range(3):
        if abs(d[a]) < 1e-12:
            hit = hit and BOX_LO[a] <= eye[a] <= BOX_HI[a]
            continue
        ta, tb = (BOX_LO[a] - eye[a]) / d[a], (BOX_HI[a] - eye[a]) / d[a]
        ta, tb = min(ta, tb), max(ta, tb)
        t0, t1 = max(t0, ta), min(t1, tb)
        hit = hit and t0 <= t1
    best = t0 if hit else -1.0
    if d[2] < 0:
        tp = -eye[2] / d[2]
        x, y = eye[0] + d[0] * tp, eye[1] + d[1] * tp
        if (best < 0 or tp < best) and 0.25 < x < 0.75 and abs(y) < 0.25:
            best = tp
    return best


ONE_BOX = ((0.0, 0.12),)


def points_block(role, eye, target, stride=12, kind_extra=0, pose=None, step=1, boxes=ONE_BOX, scale=1.0):
    """A head-like view of the scene as sensor-frame points (pose encoding 2: look-at):
    the table and a box of each (y offset, height) of `boxes` (more than one: objects
    standing apart); coordinates times `scale` (1000: millimetres)."""
    axes = look_at(eye, target)
    world = []
    for i in range(11):          # table around the boxes
        for j in range(11):
            x, y = 0.35 + 0.03 * i, -0.15 + 0.03 * j
            if not any(0.455 < x < 0.545 and -0.035 < y - b < 0.035 for b, _ in boxes):
                world.append((x, y, 0.0))
    for b, h in boxes:
        for i in range(9):       # box side facing the sensor (x = 0.465) and its top
            for k in range(int(round(h / 0.008))):
                world.append((0.465, b - 0.024 + 0.006 * i, 0.004 + 0.008 * k))
        for i in range(9):
            for j in range(7):
                world.append((0.468 + 0.008 * i, b - 0.022 + 0.0073 * j, h))
    world = world[::step]
    payload = b""
    for p in world:
        payload += f32(*(c * scale for c in to_sensor(p, eye, axes))) + b"\0" * (stride - 12)
    kind = 0 | (2 << 1) | kind_extra
    pose_bytes = f32(*eye, *target) if pose is None else pose
    if pose is not None:
        kind = 0 | kind_extra
    return bytes([role, kind]) + pose_bytes + bytes([stride]) + struct.pack("<H", len(payload)) + payload


def depth_block(role, eye, target, w=64, h=48, f=120.0, kind_extra=0, intr=None):
    axes = look_at(eye, target)
    cx, cy = (w - 1) / 2.0, (h - 1) / 2.0
    px = b""
    for v in range(h):
        for u in range(w):
            ray = ((u - cx) / f, (v - cy) / f, 1.0)
            d = tuple(sum(axes[c][r] * ray[c] for c in range(3)) for r in range(3))  # R ray
            t = cast(eye, d)
            px += struct.pack("<H", int(round(t * 1000)) if t > 0 else 0)
    kind = 1 | (2 << 1) | kind_extra
    intr = f32(f, f, cx, cy) if intr is None else intr
    return bytes([role, kind]) + f32(*eye, *target) + bytes([w, h]) + intr + struct.pack("<H", len(px)) + px


def plan_input(blocks, config=0, overrides=b"", flags_extra=0, view=0, target=b"", objects=b"", units=b""):
    """target: a target block (flags bit 4); objects: the object calls after the plan (bit 5);
    units: a units block (bit 7: u8 role, float metres per unit)."""
    n_over = len(overrides) // 5
    assert len(overrides) == 5 * n_over and n_over < 8
    flags = len(blocks) | flags_extra | (16 if target else 0) | (32 if objects else 0) | (128 if units else 0)
    return (bytes([config | (n_over << 3)]) + overrides + bytes([flags, view]) + target + units + b"".join(blocks) +
            objects)


def target_block(kind, point=(0, 0, 0), box_min=(0, 0, 0), box_max=(0, 0, 0), raw_kind=None):
    """plan_fuzz.cpp's target: kind 0 by rule, 1 point, 2 box, 3 the raw kind byte."""
    head = bytes([kind]) if raw_kind is None else bytes([3, raw_kind])
    return head + f32(*point, *box_min, *box_max)


def object_calls(*calls):
    """plan_object calls after the plan: (index byte, more byte) each, 1 to 4 of them."""
    assert 1 <= len(calls) <= 4
    return bytes([len(calls) - 1]) + b"".join(bytes([i, m]) for i, m in calls)


def override(index, value, is_int=False):
    return bytes([index]) + (struct.pack("<I", value) if is_int else f32(value))


TWO_BOXES = ((0.0, 0.12), (-0.1, 0.08))
HEAD_EYE, HAND_EYE, TARGET = (0.15, 0.0, 0.55), (0.5, -0.42, 0.42), (0.5, 0.0, 0.05)


def make_plan():
    head = points_block(0, HEAD_EYE, TARGET)
    out("plan", "head_points.bin", plan_input([head], flags_extra=8))
    out("plan", "hand_depth.bin", plan_input([depth_block(1, HAND_EYE, TARGET)], flags_extra=8, view=3))
    out("plan", "two_sensors.bin",
        plan_input([points_block(0, HEAD_EYE, TARGET, step=2), depth_block(1, HAND_EYE, TARGET, 40, 30, 75.0)],
                   flags_extra=4 | 8, view=1))
    out("plan", "head_depth_small.bin", plan_input([depth_block(0, HEAD_EYE, TARGET, 32, 24, 60.0)], config=4))
    out("plan", "stride16.bin", plan_input([points_block(1, HAND_EYE, TARGET, stride=16)], config=3))
    # points through add_point_source: pieces of 1 and of 8 points, and null pieces
    out("plan", "pieces1.bin", plan_input([points_block(0, HEAD_EYE, TARGET, step=3, kind_extra=16)]))
    out("plan", "pieces8_stride16.bin",
        plan_input([points_block(1, HAND_EYE, TARGET, stride=16, kind_extra=16 | (7 << 5))], flags_extra=8))
    out("plan", "pieces_null.bin", plan_input([points_block(0, HEAD_EYE, TARGET, step=8, kind_extra=8 | 16)]))
    for preset in (1, 2, 5, 6, 7):
        out("plan", "preset%d.bin" % preset, plan_input([points_block(0, HEAD_EYE, TARGET)], config=preset))
    # configuration overrides (indices of plan_fuzz.cpp's apply_override tables)
    # float fields 0..37, uint32 fields 38..43, bools 44..46, target_rule 47
    over = override(13, 0.02) + override(9, 0.3) + override(19, 0.0087) + override(41, 5, True)
    out("plan", "config_overrides.bin", plan_input([points_block(0, HEAD_EYE, TARGET, step=3)], overrides=over))
    out("plan", "config_invalid.bin", plan_input([points_block(0, HEAD_EYE, TARGET, step=4)],
                                                  overrides=override(13, NAN) + override(0, -1.0)))
    out("plan", "config_target_rule.bin", plan_input([points_block(0, HEAD_EYE, TARGET, step=4)],
                                                      overrides=override(47, 9, True)))
    # no sensor at all; the same role twice; invalid roles
    out("plan", "no_input.bin", plan_input([]))
    small = points_block(0, HEAD_EYE, TARGET, step=8)
    out("plan", "role_twice.bin", plan_input([small, small]))
    out("plan", "role_invalid.bin", plan_input([points_block(3, HEAD_EYE, TARGET, step=8)]))
    # poses: NaN, Inf, denormals, a reflection, far away, a quaternion, identity
    def raw_pose(r, t):
        return f32(*r, *t)
    ident = (1, 0, 0, 0, 1, 0, 0, 0, 1)
    for name, pose in (("pose_nan", raw_pose((NAN,) + ident[1:], (0, 0, 0))),
                       ("pose_inf", raw_pose(ident, (0, INF, 0))),
                       ("pose_denormal", raw_pose((1, DENORM, 0, -DENORM, 1, 0, 0, 0, 1), (DENORM, 0, 0.5))),
                       ("pose_reflection", raw_pose((-1, 0, 0, 0, -1, 0, 0, 0, -1), (0.5, 0, 0.6))),
                       ("pose_far", raw_pose(ident, (0, 0, 1e30)))):
        out("plan", name + ".bin", plan_input([points_block(0, HEAD_EYE, TARGET, step=6, pose=pose)]))
    q = norm((0.2, 0.9, -0.3, 0.1))
    out("plan", "pose_quaternion.bin",
        plan_input([points_block(0, HEAD_EYE, TARGET, step=6, pose=f32(*q, 0.5, 0.0, 0.7), kind_extra=1 << 1)]))
    out("plan", "pose_quaternion_zero.bin",
        plan_input([points_block(0, HEAD_EYE, TARGET, step=6, pose=f32(0, 0, 0, 0, 0.5, 0, 0.7), kind_extra=1 << 1)]))
    out("plan", "pose_identity.bin",
        plan_input([points_block(1, HEAD_EYE, TARGET, step=6, pose=f32(0.5, 0, -0.6), kind_extra=3 << 1)]))
    # bad arguments: small strides, a null pointer, bad intrinsics, an empty image
    stride0 = bytes([0, 2 << 1]) + f32(*HEAD_EYE, *TARGET) + bytes([0]) + struct.pack("<H", 24) + f32(0, 0, 1, 0, 0, 1)
    out("plan", "stride0.bin", plan_input([stride0]))
    out("plan", "null_points.bin", plan_input([points_block(0, HEAD_EYE, TARGET, step=8, kind_extra=8)]))
    out("plan", "null_depth.bin", plan_input([depth_block(1, HAND_EYE, TARGET, 16, 12, 30.0, kind_extra=8)]))
    out("plan", "depth_intrinsics_nan.bin",
        plan_input([depth_block(1, HAND_EYE, TARGET, 16, 12, 30.0, intr=f32(NAN, 30, 7.5, 5.5))]))
    out("plan", "depth_intrinsics_tiny.bin",
        plan_input([depth_block(1, HAND_EYE, TARGET, 16, 12, 30.0, intr=f32(1.0001, DENORM, -1e5, 1e5))]))
    out("plan", "depth_empty.bin", plan_input([depth_block(1, HAND_EYE, TARGET, 0, 12, 30.0)]))
    # targets and the objects: two boxes apart (y = 0 and -0.1; the second lower, so no
    # plane through both tops outweighs the table; preset 5 joins cells two apart, so
    # each box is one object), each planned for itself with the other as an obstacle,
    # ranked; indices out of range (1 past, 2^32 - 1)
    two = points_block(0, HEAD_EYE, TARGET, boxes=TWO_BOXES)
    every = object_calls((0, 3), (1, 0x80 | 2), (2, 31), (0xFF, 1))
    out("plan", "objects_two_boxes.bin", plan_input([two], config=5, objects=every))
    # units: a cloud in millimetres (refused, naming them), declared (planned), bad units
    mm = points_block(0, HEAD_EYE, TARGET, step=2, scale=1000.0)
    out("plan", "units_mm_refused.bin", plan_input([mm]))
    out("plan", "units_mm_declared.bin", plan_input([mm], units=bytes([0]) + f32(0.001)))
    out("plan", "units_nan.bin", plan_input([mm], units=bytes([1]) + f32(NAN)))
    out("plan", "units_role_invalid.bin", plan_input([mm], units=bytes([3]) + f32(0.001)))
    # registration (A.4b): the hand after the head, its pose (look-at) 8 mm off, a
    # rewindable point source (pieces of 2), 30 cm off, and the hand before the head
    head_pts = points_block(0, HEAD_EYE, TARGET, step=2)
    def hand_off(d, kind_extra=0):
        eye = tuple(e + d for e in HAND_EYE)
        tgt = tuple(t + d for t in TARGET)
        return points_block(1, HAND_EYE, TARGET, pose=f32(*eye, *tgt), kind_extra=(2 << 1) | kind_extra)
    out("plan", "registration_off_8mm.bin", plan_input([head_pts, hand_off(0.008)], flags_extra=8))
    out("plan", "registration_pieces.bin", plan_input([head_pts, hand_off(0.008, 16 | (1 << 5))]))
    out("plan", "registration_far.bin", plan_input([head_pts, hand_off(0.3)]))
    out("plan", "registration_hand_first.bin", plan_input([hand_off(0.008), head_pts]))
    out("plan", "target_point_far_box.bin",
        plan_input([two], config=5, target=target_block(1, point=(0.45, -0.1, 0.05)), objects=every))
    out("plan", "target_box_around.bin",
        plan_input([two], config=5, target=target_block(2, box_min=(0.45, -0.14, -0.01), box_max=(0.55, -0.06, 0.09)),
                   flags_extra=8, objects=object_calls((1, 4))))
    out("plan", "target_box_empty.bin",
        plan_input([two], config=5, target=target_block(2, box_min=(0.3, -0.1, 0.4), box_max=(0.4, 0.0, 0.5)),
                   objects=every))
    out("plan", "target_outside.bin",
        plan_input([two], config=5, target=target_block(1, point=(5.0, 0.0, 0.05)), objects=object_calls((0, 2))))
    out("plan", "target_box_outside.bin",
        plan_input([small], target=target_block(2, box_min=(3.0, 3.0, 0.0), box_max=(1e30, 1e30, 1e30))))
    out("plan", "target_nan.bin", plan_input([small], target=target_block(1, point=(0.5, NAN, 0.05))))
    out("plan", "target_inf_box.bin", plan_input([small], target=target_block(2, box_min=(-INF, 0, 0), box_max=(INF, 1, 1))))
    out("plan", "target_inverted_box.bin",
        plan_input([small], target=target_block(2, box_min=(0.6, 0.1, 0.2), box_max=(0.4, -0.1, 0.0))))
    out("plan", "target_raw_kind.bin", plan_input([small], target=target_block(0, raw_kind=7)))
    out("plan", "objects_before_plan.bin", plan_input([small], flags_extra=64, objects=object_calls((0, 1))))
    out("plan", "objects_no_input.bin", plan_input([], flags_extra=64, objects=object_calls((0, 1), (0xFF, 0))))


# ---- firmware C API call sequences (layout: fuzz/api_fuzz.cpp) ------------------------

def api_pose_raw(eye, target):
    """Pose encoding 1: the 9 row-major entries of world_R_sensor, then t."""
    x, y, z = look_at(eye, target)
    return f32(*[(x, y, z)[j][i] for i in range(3) for j in range(3)], *eye)


def api_init(slot, mem=0, cfg=0, extra=b""):
    return bytes([0, slot, mem, cfg]) + extra


def api_points(slot, role, eye, target, step=2, flags=1 << 2, stride=12, boxes=ONE_BOX):
    block = points_block(0, eye, target, stride=stride, step=step, boxes=boxes)
    # Reuse the world points of points_block: its payload follows role, kind, pose, stride, u16.
    payload = block[2 + 24 + 1 + 2:]
    return bytes([2, slot, role & 0xFF, flags]) + api_pose_raw(eye, target) + bytes([stride]) + \
        struct.pack("<H", len(payload)) + payload


def api_depth(slot, role, eye, target, w=40, h=30, f=75.0, flags=1 << 2):
    block = depth_block(0, eye, target, w, h, f)
    rest = block[2 + 24:]  # w, h, intrinsics, u16, payload: the same layout
    return bytes([3, slot, role & 0xFF, flags]) + api_pose_raw(eye, target) + rest


def api_plan(slot, null_out=0):
    return bytes([4, slot, null_out])


def api_target(slot, variant, point=(0, 0, 0), box_min=(0, 0, 0), box_max=(0, 0, 0)):
    """Op 10: variant 0 clear, 1 point, 2 box, 3 a null pointer (bits 2-3: which)."""
    return bytes([10, slot, variant]) + f32(*point, *box_min, *box_max)


def api_objects(slot, flags=0, capacity=16):
    return bytes([11, slot, flags, capacity])


def api_plan_object(slot, index, flags=0):
    """Op 12: flags bit 0 null output, bit 1 ranked, bits 2-5 the ranked capacity."""
    return bytes([12, slot, index, flags])


def make_api():
    capture = api_points(0, 0, HEAD_EYE, TARGET) + api_depth(0, 1, HAND_EYE, TARGET)
    out("api", "one_capture.bin", api_init(0) + capture + api_plan(0) + api_plan(0) +
        api_points(0, 1, HAND_EYE, TARGET, step=8) + bytes([5, 0]) + bytes([1, 0]) + api_plan(0) + capture + api_plan(0))
    out("api", "two_workspaces.bin",
        api_init(0) + api_init(1) + api_points(1, 0, HEAD_EYE, TARGET) + api_points(0, 0, HEAD_EYE, TARGET, step=3) +
        api_depth(1, 1, HAND_EYE, TARGET) + api_plan(1) + api_plan(0) + bytes([1, 1]) + api_plan(1))
    out("api", "bad_memory.bin",
        api_init(0, mem=1) + api_init(0, mem=8) + api_init(0, mem=2 << 4) + api_init(0, mem=3 << 4, extra=struct.pack("<H", 7)) +
        api_init(0, mem=64) + api_init(0, mem=128) + api_init(0, mem=1 << 4) + api_plan(0))
    out("api", "bad_config.bin",
        api_init(0, cfg=1, extra=struct.pack("<I", 12)) + api_init(0, cfg=2, extra=struct.pack("<I", 99)) +
        api_init(0, cfg=3) + api_init(0, cfg=5, extra=bytes([6]) + f32(NAN) + bytes([3]) + f32(-1.0)) +
        api_init(1, cfg=4, extra=bytes([11]) + f32(0.3)) + api_points(1, 0, HEAD_EYE, TARGET, step=4) + api_plan(1))
    out("api", "wrong_order.bin",
        api_plan(0) + bytes([1, 0]) + api_init(0) + api_plan(0, 1) + api_plan(0) + api_points(0, 7, HEAD_EYE, TARGET, step=8) +
        api_points(0, 0xFF, HEAD_EYE, TARGET, step=8) + api_points(0, 0, HEAD_EYE, TARGET, step=8, flags=1) +
        api_points(0, 0, HEAD_EYE, TARGET, step=8, flags=2) + api_points(0, 0, HEAD_EYE, TARGET, step=8, stride=4) +
        api_depth(0, 1, HAND_EYE, TARGET, 8, 6, 15.0, flags=16) + api_points(2, 0, HEAD_EYE, TARGET, step=8) + api_plan(3))
    # the grasp task: head image then the task (use_head), a failing one, an aborted one
    head_img = api_depth(0, 0, (0.5, 0.05, 0.45), TARGET, 64, 48, 80.0)
    # config field 19 -> cluster_cells = 2: the 64 x 48 image's pixels are a leaf apart
    out("api", "task.bin", api_init(0, cfg=4, extra=bytes([19]) + struct.pack("<I", 2)) + head_img + bytes([9, 0, 1, 200, 0]) +
        bytes([9, 0, 1 | 128, 200, 0]) + bytes([9, 0, 3 | 16, 50, 0]) + bytes([9, 0, 1, 200, 1]) +
        bytes([9, 0, 1 | 4, 5, 0]) + bytes([9, 0, 1 | 8, 5, 3]) + bytes([9, 2, 1, 5, 0]))
    # targets and the objects: plan/'s two boxes; every object planned, plain and ranked;
    # a target by a point and by a box; out of range, out of sequence, null pointers
    two = api_points(0, 0, HEAD_EYE, TARGET, step=1, boxes=TWO_BOXES)
    cells2 = bytes([19]) + struct.pack("<I", 2)  # config field 19: cluster_cells = 2, each box one object
    objects = (api_objects(0) + api_plan_object(0, 0) + api_plan_object(0, 1, 2 | (4 << 2)) +
               api_plan_object(0, 2) + api_plan_object(0, 0xFF) + api_objects(0, capacity=1))
    out("api", "objects.bin",
        api_init(0, cfg=4, extra=cells2) + api_plan_object(0, 0) + api_objects(0) + two + api_plan(0) + objects +
        api_target(0, 1, point=(0.45, -0.1, 0.05)) + api_plan(0) + api_objects(0) +
        api_target(0, 2, box_min=(0.45, -0.04, -0.01), box_max=(0.55, 0.04, 0.13)) + api_plan(0) + objects +
        api_target(0, 0) + bytes([1, 0]) + api_plan_object(0, 0, 2 | (2 << 2)) + two + api_plan(0) + objects)
    out("api", "targets_bad.bin",
        api_init(0) + api_target(0, 1, point=(NAN, 0.0, 0.05)) + api_target(0, 2, box_min=(0, 0, 0), box_max=(INF, 1, 1)) +
        api_target(0, 2, box_min=(0.6, 0.1, 0.2), box_max=(0.4, -0.1, 0.0)) + api_target(0, 3) +
        api_target(0, 3 | (1 << 2)) + api_target(0, 3 | (2 << 2)) + api_target(2, 1, point=(0.5, 0, 0)) +
        api_objects(0, flags=1) + api_objects(0, flags=2) + api_objects(0, flags=4) + api_objects(0, capacity=0) +
        api_objects(3) + api_plan_object(0, 0, 1) + api_plan_object(0, 0, 2) + api_plan_object(2, 0) +
        api_target(0, 1, point=(0.5, 0.0, 9.0)) + api_points(0, 0, HEAD_EYE, TARGET, step=4) + api_plan(0) +
        api_plan_object(0, 0) + api_target(0, 2, box_min=(0.3, -0.1, 0.4), box_max=(0.4, 0.0, 0.5)) + api_plan(0) +
        api_objects(0) + api_plan_object(0, 0, 2 | (15 << 2)))
    out("api", "bogus_and_strings.bin",
        api_init(0) + bytes([7, 0, 7, 1, 7, 2, 7, 3]) + bytes([6]) + struct.pack("<ii", -112, 10) +
        bytes([6]) + struct.pack("<ii", 12345, -3) + bytes([8, 3, 13]) + f32(NAN) + bytes([40]) + f32(-1.0) +
        bytes([2]) + struct.pack("<I", 0xFFFFFFFF))


if __name__ == "__main__":
    make_pcd()
    make_ply()
    make_scene()
    make_plan()
    make_api()
    for t in ("pcd", "ply", "scene", "plan", "api"):
        d = os.path.join(HERE, "corpus", t)
        files = sorted(os.listdir(d))
        print("%-6s %2d files, largest %d bytes" % (t, len(files), max(os.path.getsize(os.path.join(d, f)) for f in files)))
