"""Seeds and mutators for fuzzing inertia's readers (tests/test_fuzz.py, bench/fuzz.py)."""

from __future__ import annotations

import random
import re as _re
import struct

CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_F = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
          (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]


def seed_obj() -> bytes:
    s = "".join(f"v {x} {y} {z}\n" for x, y, z in CUBE_V)
    s += "".join(f"f {a+1} {b+1} {c+1}\n" for a, b, c in CUBE_F)
    return s.encode()


def seed_off() -> bytes:
    s = f"OFF\n{len(CUBE_V)} {len(CUBE_F)} 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in CUBE_V)
    s += "".join(f"3 {a} {b} {c}\n" for a, b, c in CUBE_F)
    return s.encode()


def seed_ply() -> bytes:
    head = ("ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 12\nproperty list uchar int vertex_indices\nend_header\n")
    s = head + "".join(f"{x} {y} {z}\n" for x, y, z in CUBE_V) + "".join(f"3 {a} {b} {c}\n" for a, b, c in CUBE_F)
    return s.encode()


def seed_ply_binary() -> bytes:
    """The cube as a little-endian binary PLY, its sides as quads but the first (two triangles):
    list lengths that vary row by row."""
    faces = [CUBE_F[0], CUBE_F[1]] + [(a, b, c, d) for (a, b, c), (_, _, d) in zip(CUBE_F[2::2], CUBE_F[3::2])]
    head = (f"ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
            f"property float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    out = bytearray(head.encode()) + b"".join(struct.pack("<3f", *p) for p in CUBE_V)
    for face in faces:
        out += struct.pack(f"<B{len(face)}i", len(face), *face)
    return bytes(out)


def _tris():
    return [[CUBE_V[i] for i in f] for f in CUBE_F]


def seed_stl_ascii() -> bytes:
    s = "solid cube\n"
    for t in _tris():
        s += " facet normal 0 0 0\n  outer loop\n" + "".join(f"   vertex {x} {y} {z}\n" for x, y, z in t)
        s += "  endloop\n endfacet\n"
    return (s + "endsolid cube\n").encode()


def seed_stl_binary() -> bytes:
    tris = _tris()
    out = bytearray(b"binary cube".ljust(80, b" ")) + struct.pack("<I", len(tris))
    for t in tris:
        out += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *p) for p in t) + b"\0\0"
    return bytes(out)


URDF = b"""<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <inertial><origin xyz="0 0 0.1" rpy="0 0 0"/><mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial>
    <visual><geometry><box size="0.1 0.2 0.3"/></geometry></visual>
    <collision><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="arm">
    <inertial><mass value="1.0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial>
    <collision><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
</robot>
"""

MJCF = b"""<mujoco model="m">
  <compiler angle="radian" inertiafromgeom="auto"/>
  <default><geom density="1000"/></default>
  <worldbody>
    <body name="a" pos="0 0 1" quat="1 0 0 0">
      <joint type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.1 0.2 0.3"/>
      <body name="b" pos="0 0 0.5" euler="0 0.5 0">
        <joint type="hinge"/>
        <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.001"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.4" size="0.05"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

SDF = b"""<?xml version="1.0"?>
<sdf version="1.7">
  <model name="m">
    <link name="l">
      <inertial><pose>0 0 0.1 0 0 0</pose><mass>2</mass>
        <inertia><ixx>0.02</ixx><ixy>0</ixy><ixz>0</ixz><iyy>0.02</iyy><iyz>0</iyz><izz>0.01</izz></inertia>
      </inertial>
      <collision name="c"><geometry><box><size>0.1 0.2 0.3</size></box></geometry></collision>
    </link>
  </model>
</sdf>
"""

MESH_SEEDS = {".obj": seed_obj, ".off": seed_off, ".ply": seed_ply, ".stl": seed_stl_ascii}
ROBOT_SEEDS = {".urdf": URDF, ".xml": MJCF, ".sdf": SDF}

_TOKENS = [b"0", b"-1", b"1e308", b"-1e308", b"nan", b"inf", b"1e-320", b"", b" ", b"\r", b"\n", b"/", b"//",
           b"999999999999", b"-0", b"0x10", b"\x00", b"\xff\xfe", b"<", b">", b"\"", b"=", b"&amp;", b"<!--", b"-->",
           b"<include file=\"x.xml\"/>", b"<worldbody/>", b"<body>", b"</body>", b"<frame>", b"quat=\"0 0 0 0\"",
           b"3", b"4", b"f", b"v", b"vn", b"facet", b"endsolid", b"1 2", b"1 2 3 4 5"]


def mutate(data: bytes, rng: random.Random, n_ops: int | None = None) -> bytes:
    """Random structure-blind mutations: flip, insert a token, delete a span, duplicate a span, truncate."""
    b = bytearray(data)
    for _ in range(n_ops or rng.randint(1, 4)):
        op = rng.randrange(6)
        i = rng.randrange(len(b) + 1) if b else 0
        if op == 0 and b:
            b[min(i, len(b) - 1)] = rng.randrange(256)
        elif op == 1:
            b[i:i] = rng.choice(_TOKENS)
        elif op == 2 and b:
            j = min(len(b), i + rng.randint(1, 16))
            del b[i:j]
        elif op == 3 and b:
            j = min(len(b), i + rng.randint(1, 64))
            b[i:i] = b[i:j]
        elif op == 4:
            del b[i:]
        else:  # replace a number-looking token
            j = min(len(b), i + rng.randint(1, 8))
            b[i:j] = rng.choice(_TOKENS)
    return bytes(b)


_NUMS = [b"0", b"-0", b"-1", b"1e308", b"-1e308", b"1e-200", b"nan", b"inf", b"-inf", b"1e20", b"3.0e-45", b"",
         b"1 2", b"abc", b"2147483648", b"-2147483649", b"9", b"100", b"1e7", b"0.000001"]
_NUM_RE = _re.compile(rb"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")


def mutate_structured(data: bytes, rng: random.Random) -> bytes:
    """Mutations that keep the file mostly well formed: numbers swapped for edge values, lines
    deleted, duplicated or swapped, an XML attribute or element dropped or repeated."""
    lines = data.split(b"\n")
    for _ in range(rng.randint(1, 3)):
        op = rng.randrange(5)
        k = rng.randrange(len(lines)) if lines else 0
        if op == 0 and lines:          # a number -> an edge value
            nums = list(_NUM_RE.finditer(lines[k]))
            if nums:
                m = rng.choice(nums)
                lines[k] = lines[k][:m.start()] + rng.choice(_NUMS) + lines[k][m.end():]
        elif op == 1 and lines:
            del lines[k]
        elif op == 2 and lines:
            lines.insert(k, lines[rng.randrange(len(lines))])
        elif op == 3 and len(lines) > 1:
            j = rng.randrange(len(lines))
            lines[k], lines[j] = lines[j], lines[k]
        elif lines:                    # drop an attribute
            attrs = list(_re.finditer(rb'\s\w+="[^"]*"', lines[k]))
            if attrs:
                m = rng.choice(attrs)
                lines[k] = lines[k][:m.start()] + lines[k][m.end():]
    return b"\n".join(lines)


def mutate_any(data: bytes, rng: random.Random) -> bytes:
    return mutate_structured(data, rng) if rng.random() < 0.75 else mutate(data, rng)
