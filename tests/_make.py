"""Test inputs the tests write themselves: meshes in every file format and robot files.

The "made" tier of ``tests/conftest.py``: a plain clone runs every mesh-file and robot-file
test on these, and again on the curated real files of ``../shared/data`` when they are beside
the checkout (the "real" tier).  Each made file stands in for one real file of the same name
and carries the trait the tests exercise (binary STL whose header starts with "solid", float
noise copies of vertices, UV-seam duplicates, an open surface, a triangle soup, balanced
non-manifold edges, ...).  The facts the tests assert come with each set: for the made files
from closed forms (volumes of prisms, annuli and boxes) or from a plain count done here,
for the real files from ``../shared/data/SOURCES.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


# ----------------------------------------------------------------------------- writers
def write_binary_stl(path: Path, corners, header: bytes = b"inertia test mesh") -> Path:
    """Binary STL of triangles ``corners`` (F, 3, 3), stored as float32 (zero normals)."""
    corners = np.asarray(corners)
    rec = np.zeros(len(corners), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = corners
    path.write_bytes(header[:80].ljust(80) + len(corners).to_bytes(4, "little") + rec.tobytes())
    return path


def write_ascii_stl(path: Path, corners) -> Path:
    lines = ["solid part"]
    for tri in np.asarray(corners, float):
        lines += ["  facet normal 0 0 0", "    outer loop"]
        lines += [f"      vertex {x!r} {y!r} {z!r}" for x, y, z in tri.tolist()]
        lines += ["    endloop", "  endfacet"]
    path.write_text("\n".join(lines + ["endsolid part"]) + "\n")
    return path


def write_obj(path: Path, vertices, faces) -> Path:
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, float).tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(faces).tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_off(path: Path, vertices, faces) -> Path:
    lines = ["OFF", f"{len(vertices)} {len(faces)} 0"]
    lines += [f"{x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, float).tolist()]
    lines += [f"3 {a} {b} {c}" for a, b, c in np.asarray(faces).tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ply(path: Path, vertices, faces) -> Path:
    head = ["ply", "format ascii 1.0", f"element vertex {len(vertices)}", "property double x",
            "property double y", "property double z", f"element face {len(faces)}",
            "property list uchar int vertex_indices", "end_header"]
    lines = [f"{x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, float).tolist()]
    lines += [f"3 {a} {b} {c}" for a, b, c in np.asarray(faces).tolist()]
    path.write_text("\n".join(head + lines) + "\n")
    return path


# ----------------------------------------------------------------------------- closed forms
def prism_volume(n: int, r: float, h: float) -> float:
    """Volume of a right prism over the regular n-gon inscribed in radius r."""
    return n / 2 * r * r * np.sin(2 * np.pi / n) * h


def box_inertia(extents, mass: float) -> np.ndarray:
    a, b, c = np.asarray(extents, float) ** 2
    return mass / 12 * np.diag([b + c, a + c, a + b])


def open_edge_count(corners) -> int:
    """Edges used by exactly one triangle, vertices identified by exactly equal coordinates."""
    pts = np.asarray(corners, float).reshape(-1, 3)
    _, ids = np.unique(pts, axis=0, return_inverse=True)
    tri = ids.reshape(-1, 3)
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts == 1).sum())


def _noisy(corners, every: int):
    """Float noise copies: in every ``every``-th triangle an exact 0 coordinate is written
    -2.7e-16, as CAD exporters leave them (closed again by the near merge only)."""
    c = np.asarray(corners, np.float32).copy()
    sel = c[::every]
    c[::every] = np.where(sel == 0, np.float32(-2.7e-16), sel)
    return c


# ----------------------------------------------------------------------------- meshes
@dataclass
class MeshSet:
    """A folder of test meshes and what the tests may assert about them."""

    dir: Path
    watertight: dict          # name -> (faces, volume in file units^3)
    broken: dict              # name -> (faces, defect code, count)
    noise_open_edges: int     # featuretype.stl: open edges left by exact welding alone
    soup_volume: float        # soup.stl as placed (trimesh)
    soup_volume_centred: float  # soup.stl moved to its bounding-box centre (trimesh)
    soup_message_volume: str  # regex of the signed volume our refusal names
    tier: str = "made"
    extra: dict = field(default_factory=dict)

    def path(self, name: str) -> Path:
        return self.dir / name


def real_mesh_set(root: Path) -> MeshSet:
    """``../shared/data/meshes`` with the figures of ``../shared/data/SOURCES.md``."""
    return MeshSet(
        dir=root, tier="real",
        watertight={"wingnut.obj": (6090, 22.0966), "ballA.off": (3796, 1401.11),
                    "featuretype.stl": (3476, 11.6277), "idler_riser_binary_solid_header.stl": (1572, 1.4878),
                    "tray_bottom_ascii.stl": (4520, 347866.0), "spot.obj": (23062, 0.687986)},
        # cycloidal: not open: 242 edges where closed parts touch (4 faces each, 2 per direction)
        broken={"teapot_open.stl": (894, "open_edges", 64), "soup.stl": (100, "open_edges", 300),
                "cycloidal.ply": (43368, "non_manifold_edges", 242)},
        noise_open_edges=576, soup_volume=0.168215, soup_volume_centred=-0.0653581,
        soup_message_volume=r"-0\.11\d+")


def _cylinder(n, r, h, centre):
    import trimesh

    m = trimesh.creation.cylinder(radius=r, height=h, sections=n)
    return m.vertices + centre, np.asarray(m.faces)


def _soup(rng, n=100):
    """n loose triangles facing +x, most at low x, one far out: the signed volume is positive
    as placed and negative about the bounding-box centre.  Flat triangles facing +x make the
    figures plain sums: trimesh's volume integrates x n_x over the surface, sum(A x_mean)."""
    yz = rng.uniform(0, 1, size=(n, 2))
    x = np.concatenate([rng.uniform(1.0, 1.2, size=n - 1), [3.0]])
    s = np.concatenate([rng.uniform(0.05, 0.1, size=n - 1), [0.01]])
    a = np.column_stack([x, yz])
    zero = 0 * s
    corners = np.stack([a, a + np.column_stack([zero, s, zero]), a + np.column_stack([zero, zero, s])], axis=1)
    corners = corners.astype(np.float32).astype(float)
    area = 0.5 * np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])[:, 0]
    xc = 0.5 * (corners[..., 0].min() + corners[..., 0].max())
    return corners, float((corners[:, 0, 0] * area).sum()), float(((corners[:, 0, 0] - xc) * area).sum())


def make_mesh_set(d: Path) -> MeshSet:
    """Write the made meshes into folder ``d`` (same names as the real ones)."""
    import trimesh

    rng = np.random.default_rng(20261124)
    watertight, broken = {}, {}

    # wingnut.obj: an annulus (genus 1), OBJ
    n, r0, r1, h = 24, 0.8, 2.0, 1.5
    m = trimesh.creation.annulus(r_min=r0, r_max=r1, height=h, sections=n)
    write_obj(d / "wingnut.obj", m.vertices + [0.3, -0.2, 1.0], m.faces)
    watertight["wingnut.obj"] = (len(m.faces), prism_volume(n, r1, h) - prism_volume(n, r0, h))

    # ballA.off: a 40-gon prism, OFF, far from the origin
    v, f = _cylinder(40, 7.0, 9.0, [20.0, 10.0, -5.0])
    write_off(d / "ballA.off", v, f)
    watertight["ballA.off"] = (len(f), prism_volume(40, 7.0, 9.0))

    # featuretype.stl: binary STL with float noise copies of vertices (open unless merged)
    v, f = _cylinder(64, 1.25, 2.5, [0.0, 0.0, 1.25])   # vertices with exact zeros
    corners = _noisy(v[f], every=5)
    write_binary_stl(d / "featuretype.stl", corners)
    watertight["featuretype.stl"] = (len(f), prism_volume(64, 1.25, 2.5))
    noise_open = open_edge_count(corners)

    # idler_riser_binary_solid_header.stl: binary STL whose header begins with "solid", noisy too
    v, f = _cylinder(30, 0.5, 1.75, [0.0, 0.0, 0.875])
    write_binary_stl(d / "idler_riser_binary_solid_header.stl", _noisy(v[f], every=4),
                     header=b"solid idler_riser exported as binary")
    watertight["idler_riser_binary_solid_header.stl"] = (len(f), prism_volume(30, 0.5, 1.75))

    # tray_bottom_ascii.stl: ASCII STL of a large box (mm-like coordinates)
    m = trimesh.creation.box(extents=(120.0, 80.0, 25.0))
    write_ascii_stl(d / "tray_bottom_ascii.stl", (m.vertices + [60.0, 40.0, 12.5])[m.faces])
    watertight["tray_bottom_ascii.stl"] = (12, 120.0 * 80.0 * 25.0)

    # spot.obj: 5120 faces, split at a "UV seam": the top cap has its own copies of its vertices
    n = 1280
    v, f = _cylinder(n, 0.5, 0.8, [0.1, 0.2, 0.3])
    top = np.all(np.isclose(v[f][..., 2], v[:, 2].max()), axis=1)
    seam = np.unique(f[top])
    copy = np.full(len(v), -1)
    copy[seam] = len(v) + np.arange(len(seam))
    g = f.copy()
    g[top] = copy[f[top]]
    write_obj(d / "spot.obj", np.concatenate([v, v[seam]]), g)
    watertight["spot.obj"] = (len(f), prism_volume(n, 0.5, 0.8))

    # teapot_open.stl: a cup (a prism without its top cap), binary STL
    n = 48
    v, f = _cylinder(n, 3.0, 4.0, [1.0, 2.0, 2.0])
    top = np.all(np.isclose(v[f][..., 2], v[:, 2].max()), axis=1)
    write_binary_stl(d / "teapot_open.stl", v[f[~top]])
    broken["teapot_open.stl"] = (int((~top).sum()), "open_edges", n)

    # soup.stl: 100 loose triangles, binary STL
    corners, vol, vol_c = _soup(rng)
    write_binary_stl(d / "soup.stl", corners)
    broken["soup.stl"] = (100, "open_edges", 300)

    # cycloidal.ply: three closed cubes in a chain, each touching the next along one edge
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    parts = [box.vertices + [k, k, 0.5] for k in range(3)]
    vv = np.concatenate(parts)
    ff = np.concatenate([np.asarray(box.faces) + 8 * k for k in range(3)])
    write_ply(d / "cycloidal.ply", vv, ff)
    broken["cycloidal.ply"] = (len(ff), "non_manifold_edges", 2)

    return MeshSet(dir=d, watertight=watertight, broken=broken, noise_open_edges=noise_open,
                   soup_volume=vol, soup_volume_centred=vol_c, soup_message_volume=r"-\d+\.\d+")


# ----------------------------------------------------------------------------- robots
@dataclass
class RobotSet:
    """A folder of robot files laid out as ``../shared/data/robots`` and what tests may assert.

    ``good`` maps each folder to ``(file, least number of links)``: files whose inertials are
    all valid and agree with their geometry.
    """

    root: Path
    tier: str = "made"

    @property
    def simple_arm(self) -> Path:
        return self.root / "simple_arm_sdf_INVALID" / "simple_arm" / "model.sdf"

    @property
    def pendulum(self) -> Path:
        return self.root / "double_pendulum_urdf" / "urdf" / "double_pendulum.urdf"

    @property
    def barkour_dir(self) -> Path:
        return self.root / "barkour_v0_mjcf"

    @property
    def good(self) -> dict:
        n = {"real": (3, 13, 1), "made": (3, 4, 1)}[self.tier]
        return {"double_pendulum_urdf": (self.pendulum, n[0]),
                "barkour_v0_mjcf": (self.barkour_dir / "barkour_v0_mjx.xml", n[1]),
                "cordless_drill_sdf": (self.root / "cordless_drill_sdf" / "cordless_drill" / "model.sdf", n[2])}


def real_robot_set(root: Path) -> RobotSet:
    return RobotSet(root=root, tier="real")


def _box_corners(extents, centre):
    import trimesh

    m = trimesh.creation.box(extents=extents)
    return (m.vertices + centre)[m.faces]


def _f(x) -> str:
    """A float as XML text (repr of a Python float: shortest round-trip digits)."""
    return repr(float(x))


def _sdf_inertia(I, indent):
    tags = {"ixx": (0, 0), "ixy": (0, 1), "ixz": (0, 2), "iyy": (1, 1), "iyz": (1, 2), "izz": (2, 2)}
    return "\n".join(f"{indent}<{t}>{_f(float(I[i, j]))}</{t}>" for t, (i, j) in tags.items())


# simple_arm: arm_base breaks the triangle inequality (1.01 + 1.11 < 100.11), as the real
# gazebo_models file does; the link sits on line 4, its <inertial> on line 5
SIMPLE_ARM_SDF = """<?xml version="1.0" ?>
<sdf version="1.5">
  <model name="simple_arm">
    <link name="arm_base">
      <inertial>
        <pose>0 0 0.00099 0 0 0</pose>
        <inertia>
          <ixx>1.11</ixx>
          <ixy>0</ixy>
          <ixz>0</ixz>
          <iyy>100.11</iyy>
          <iyz>0</iyz>
          <izz>1.01</izz>
        </inertia>
        <mass>101.0</mass>
      </inertial>
    </link>
    <!-- a valid second link -->
    <link name="arm_shoulder_pan">
      <pose>0 0 1.1 0 0 0</pose>
      <inertial>
        <pose>0.045455 0 0 0 0 0</pose>
        <inertia>
          <ixx>0.011</ixx>
          <ixy>0</ixy>
          <ixz>0</ixz>
          <iyy>0.0225</iyy>
          <iyz>0</iyz>
          <izz>0.0135</izz>
        </inertia>
        <mass>1.1</mass>
      </inertial>
    </link>
    <joint name="arm_shoulder_pan_joint" type="revolute">
      <parent>arm_base</parent>
      <child>arm_shoulder_pan</child>
      <axis><xyz>0 0 1</xyz></axis>
    </joint>
  </model>
</sdf>
"""


def _pendulum(d: Path):
    """A URDF of three links, each a box mesh (../meshes/NAME.stl) with its exact inertial."""
    (d / "urdf").mkdir(parents=True)
    (d / "meshes").mkdir()
    links = {"base_link": ((0.0625, 0.0625, 0.125), (0.0, 0.0, 0.0625), 0.5),
             "link1": ((0.03125, 0.015625, 0.25), (0.0, 0.0078125, 0.125), 0.25),
             "link2": ((0.015625, 0.03125, 0.1875), (0.0, -0.0078125, 0.09375), 0.125)}
    parts = ['<?xml version="1.0" encoding="utf-8"?>', "<!-- a made stand-in for example-robot-data's double pendulum -->",
             '<robot name="2dof_planar">']
    for name, (ext, c, m) in links.items():
        write_binary_stl(d / "meshes" / f"{name}.stl", _box_corners(ext, c))
        I = box_inertia(ext, m)
        geo = f'<geometry><mesh filename="../meshes/{name}.stl"/></geometry>'
        parts += [f'  <link name="{name}">',
                  f'    <inertial><origin xyz="{_f(c[0])} {_f(c[1])} {_f(c[2])}" rpy="0 0 0"/><mass value="{_f(m)}"/>',
                  f'      <inertia ixx="{_f(I[0, 0])}" ixy="0" ixz="0" iyy="{_f(I[1, 1])}" iyz="0" izz="{_f(I[2, 2])}"/></inertial>',
                  f'    <visual><origin xyz="0 0 0" rpy="0 0 0"/>{geo}</visual>',
                  f'    <collision><origin xyz="0 0 0" rpy="0 0 0"/>{geo}</collision>',
                  "  </link>"]
    for parent, child, z in (("base_link", "link1", 0.125), ("link1", "link2", 0.25)):
        parts += [f'  <joint name="{child}_joint" type="continuous"><parent link="{parent}"/><child link="{child}"/>',
                  f'    <origin xyz="0 0 {_f(z)}" rpy="0 0 0"/><axis xyz="1 0 0"/></joint>']
    (d / "urdf" / "double_pendulum.urdf").write_text("\n".join(parts + ["</robot>"]) + "\n")


def _barkour(d: Path):
    """MJCF bodies with mesh geoms: closed (foot, handle), open (head) and non-manifold (body)."""
    import trimesh

    d.mkdir(parents=True)
    foot_ext, foot_c = (0.03125, 0.0625, 0.015625), (0.0078125, 0.0, -0.015625)
    write_binary_stl(d / "foot.stl", _box_corners(foot_ext, foot_c))
    v, f = _cylinder(24, 0.015, 0.1, [0.004, -0.003, 0.02])
    write_binary_stl(d / "handle.stl", v[f])
    v, f = _cylinder(16, 0.05, 0.04, [0.0, 0.0, 0.02])
    top = np.all(np.isclose(v[f][..., 2], v[:, 2].max()), axis=1)
    write_binary_stl(d / "head.stl", v[f[~top]])   # open: no top cap
    box = trimesh.creation.box(extents=(0.05, 0.05, 0.05))
    write_binary_stl(d / "body.stl", np.concatenate([(box.vertices + [0.05 * k, 0.05 * k, 0])[box.faces]
                                                     for k in range(2)]))  # two cubes sharing an edge
    m = 0.25
    I = box_inertia(foot_ext, m)
    legs = "".join(f"""
      <body name="leg_{k}" pos="{x} 0 -0.1">
        <joint name="knee_{k}" axis="0 1 0"/>
        <inertial pos="{_f(foot_c[0])} {_f(foot_c[1])} {_f(foot_c[2])}" mass="{_f(m)}" diaginertia="{_f(I[0, 0])} {_f(I[1, 1])} {_f(I[2, 2])}"/>
        <geom class="visual" mesh="foot"/>
        <geom type="sphere" size="0.01" pos="0 0 -0.03"/>
      </body>""" for k, x in ((1, 0.1), (2, -0.1)))
    (d / "barkour_v0_mjx.xml").write_text(f"""<mujoco model="made_quadruped">
  <compiler angle="radian" meshdir="." autolimits="true"/>
  <default>
    <geom contype="0" conaffinity="0" type="mesh"/>
    <default class="visual">
      <geom contype="0" conaffinity="0" density="0" group="1"/>
    </default>
  </default>
  <asset>
    <mesh file="head.stl"/>
    <mesh file="handle.stl"/>
    <mesh file="foot.stl"/>
  </asset>
  <worldbody>
    <body name="chassis" pos="0 0 0.3">
      <freejoint/>
      <inertial pos="0 0 0.02" quat="1 0 0 0" mass="3.5" diaginertia="0.03 0.02 0.015"/>
      <geom class="visual" mesh="head"/>
      <geom class="visual" mesh="handle"/>
      <geom type="box" size="0.1 0.05 0.03"/>{legs}
      <body name="tail" pos="-0.12 0 0">
        <inertial pos="0 0 0" mass="0.1" diaginertia="2e-5 3e-5 4e-5"/>
      </body>
    </body>
  </worldbody>
</mujoco>
""")


def _drill(d: Path):
    """An SDF model with model:// URIs: a .dae visual (not usable for inertia) and a closed
    STL collision mesh its declared inertial matches."""
    (d / "meshes").mkdir(parents=True)
    ext, c, m = (0.0625, 0.125, 0.25), np.array([0.0, 0.0, 0.125]), 1.5
    write_binary_stl(d / "meshes" / "cordless_drill.stl", _box_corners(ext, c))
    (d / "meshes" / "cordless_drill.dae").write_text(
        '<?xml version="1.0"?>\n<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">\n'
        "  <asset/>\n</COLLADA>\n")
    (d / "model.config").write_text('<?xml version="1.0"?>\n<model><name>Cordless Drill</name>'
                                    "<sdf version=\"1.5\">model.sdf</sdf></model>\n")
    pose = c + [0.0, 0.0, -0.09]
    (d / "model.sdf").write_text(f"""<?xml version="1.0" ?>
<sdf version="1.5">
  <model name="drill">
    <link name="link">
      <inertial>
        <pose>{_f(pose[0])} {_f(pose[1])} {_f(pose[2])} 0 0 0</pose>
        <inertia>
{_sdf_inertia(box_inertia(ext, m), "          ")}
        </inertia>
        <mass>{_f(m)}</mass>
      </inertial>
      <collision name="collision">
        <pose>0 0 -0.09 0 0 0</pose>
        <geometry><mesh><uri>model://cordless_drill/meshes/cordless_drill.stl</uri></mesh></geometry>
      </collision>
      <visual name="visual">
        <pose>0 0 -0.09 0 0 0</pose>
        <geometry><mesh><uri>model://cordless_drill/meshes/cordless_drill.dae</uri></mesh></geometry>
      </visual>
    </link>
  </model>
</sdf>
""")


def make_robot_set(root: Path) -> RobotSet:
    """Write the made robot files into ``root`` (the layout of ``../shared/data/robots``)."""
    arm = root / "simple_arm_sdf_INVALID" / "simple_arm"
    arm.mkdir(parents=True)
    (arm / "model.sdf").write_text(SIMPLE_ARM_SDF)
    _pendulum(root / "double_pendulum_urdf")
    _barkour(root / "barkour_v0_mjcf")
    _drill(root / "cordless_drill_sdf" / "cordless_drill")
    return RobotSet(root=root)
