"""MJCF bodies whose inertia MuJoCo infers from geoms: every mesh-inertia mode, fitted
primitives and shell primitives give MuJoCo's compiled numbers (MuJoCo as the oracle), and
the modes keep their own closed-form meaning (second methods, no MuJoCo needed)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from inertia.massprops import primitives
from inertia.massprops.mesh import mesh_properties
from inertia.robots.geometry import link_geometry_properties
from inertia.robots.io import read_robot
from inertia.robots.mujoco_inertia import MESH_INERTIA_MODES, mesh_inertia, principal_descending
from tests._make import write_binary_stl
from tests.robots._report import sev


def tube_mesh(r_in: float, r_out: float, h: float, n: int = 24):
    """A closed, outward-wound, non-convex tube (annulus prism) along z."""
    a = 2 * np.pi * np.arange(n) / n
    ring = np.stack([np.cos(a), np.sin(a)], axis=1)
    v = np.concatenate([np.c_[r_out * ring, np.zeros(n)], np.c_[r_out * ring, np.full(n, h)],
                        np.c_[r_in * ring, np.zeros(n)], np.c_[r_in * ring, np.full(n, h)]])
    ob, ot, ib, it = 0, n, 2 * n, 3 * n
    f = []
    for i in range(n):
        j = (i + 1) % n
        f += [(ob + i, ob + j, ot + j), (ob + i, ot + j, ot + i)]      # outer wall, normal out
        f += [(ib + i, it + j, ib + j), (ib + i, it + i, it + j)]      # inner wall, normal in
        f += [(ot + i, ot + j, it + j), (ot + i, it + j, it + i)]      # top, normal +z
        f += [(ob + i, ib + j, ob + j), (ob + i, ib + i, ib + j)]      # bottom, normal -z
    return v, np.array(f)


def corners_of(v, f):
    return np.asarray(v, float)[np.asarray(f)]


def _rot(angle, axis):
    from inertia._core.rotations import quat_from_rotvec, quat_to_matrix

    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return quat_to_matrix(quat_from_rotvec(axis * angle))


@pytest.fixture
def tube_stl(tmp_path):
    v, f = tube_mesh(0.03, 0.08, 0.05)
    v = v @ _rot(0.4, (1, 2, 3)).T + (0.01, 0.02, 0.03)
    return write_binary_stl(tmp_path / "tube.stl", corners_of(v, f)), v, f


def _ours(path, body: str):
    link = read_robot(path).link(body)
    props, _, problems = link_geometry_properties(link, role="collision", simulator=True)
    assert props is not None, problems
    return props


def _mujocos(path, body: str):
    mujoco = pytest.importorskip("mujoco")
    m = mujoco.MjModel.from_xml_path(str(path))
    i = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, body)
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, m.body_iquat[i])
    R = R.reshape(3, 3)
    return m.body_mass[i], m.body_ipos[i], R @ np.diag(m.body_inertia[i]) @ R.T


#: MuJoCo diagonalises each inertia with a Jacobi iteration that stops at rotations of ~1.4e-6
#: rad (its kEigEPS = 1e-12 on the cosine), so its compiled body inertia carries relative
#: errors of that order times the moments' spread; our numbers are compared at 1e-7
MUJOCO_EIG_RTOL = 1e-7


def _rel(ours, theirs) -> float:
    mass, com, inertia = theirs
    return max(abs(ours.mass - mass) / mass, float(np.abs(ours.com - com).max()) / max(1e-3, np.abs(com).max()),
               float(np.abs(ours.inertia_com - inertia).max() / np.abs(inertia).max()))


@pytest.mark.parametrize("mode", MESH_INERTIA_MODES)
@pytest.mark.parametrize("scale", ["1 1 1", "1 1.2 0.9", "-1 1 1"])
def test_every_mesh_inertia_mode_equals_mujocos_compiler(tmp_path, tube_stl, mode, scale):
    path = tmp_path / "m.xml"
    path.write_text(f"""<mujoco><asset><mesh name="t" file="{tube_stl[0].name}" inertia="{mode}" scale="{scale}"/>
</asset><worldbody><body name="b"><freejoint/>
<geom type="mesh" mesh="t" density="800" pos="0.1 0 0" euler="10 20 30"/>
<geom type="mesh" mesh="t" mass="0.7" quat="0.9 0.1 0.3 0.2"/></body></worldbody></mujoco>""")
    assert _rel(_ours(path, "b"), _mujocos(path, "b")) < MUJOCO_EIG_RTOL


@pytest.mark.parametrize("kind", ["box", "capsule", "cylinder", "sphere", "ellipsoid"])
@pytest.mark.parametrize("fitaabb", ["false", "true"])
@pytest.mark.parametrize("mode", ["legacy", "convex"])
def test_a_primitive_fitted_to_a_mesh_is_mujocos_fit(tmp_path, tube_stl, kind, fitaabb, mode):
    """``<geom type="capsule" mesh="...">`` without a size: MuJoCo fits the primitive (to the
    inertia box, or the principal-frame AABB with fitaabb), scaled by fitscale."""
    path = tmp_path / "fit.xml"
    path.write_text(f"""<mujoco><compiler fitaabb="{fitaabb}"/>
<asset><mesh name="t" file="{tube_stl[0].name}" inertia="{mode}"/></asset>
<worldbody><body name="b"><freejoint/>
<geom type="{kind}" mesh="t" fitscale="1.1" pos="0.1 0 0" euler="10 20 30" density="500"/></body></worldbody></mujoco>""")
    # MuJoCo's own principal axes are good to ~1e-6 rad (its Jacobi stops there); the AABB fit
    # in those axes inherits it
    assert _rel(_ours(path, "b"), _mujocos(path, "b")) < (1e-6 if fitaabb == "true" else MUJOCO_EIG_RTOL)


@pytest.mark.parametrize("geom", ['type="sphere" size="0.05"', 'type="box" size="0.05 0.06 0.07"',
                                  'type="cylinder" size="0.05 0.07"', 'type="capsule" size="0.05 0.07"',
                                  'type="ellipsoid" size="0.05 0.06 0.07"'])
def test_shell_primitives_equal_mujocos(tmp_path, geom):
    path = tmp_path / "shell.xml"
    path.write_text(f"""<mujoco><worldbody><body name="b"><freejoint/>
<geom {geom} shellinertia="true" density="3" pos="0.01 0.02 0.03" euler="10 20 30"/>
</body></worldbody></mujoco>""")
    assert _rel(_ours(path, "b"), _mujocos(path, "b")) < MUJOCO_EIG_RTOL


def test_a_mesh_given_by_vertices_alone_is_its_convex_hull(tmp_path):
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(30, 3)) * (0.05, 0.03, 0.02)
    path = tmp_path / "v.xml"
    text = " ".join(repr(float(x)) for x in pts.ravel())
    path.write_text(f"""<mujoco><asset><mesh name="cloud" vertex="{text}"/></asset>
<worldbody><body name="b"><freejoint/><geom type="mesh" mesh="cloud"/></body></worldbody></mujoco>""")
    ours = _ours(path, "b")
    assert _rel(ours, _mujocos(path, "b")) < MUJOCO_EIG_RTOL


# ---- the modes' own meaning, without MuJoCo -------------------------------------------------


def test_modes_on_a_closed_non_convex_mesh_against_second_methods():
    r_in, r_out, h, n = 0.03, 0.08, 0.05, 24
    v, f = tube_mesh(r_in, r_out, h, n)
    v32 = np.asarray(v, np.float32).astype(float)
    exact = mesh_properties(v32, f, density=1.0)
    # the exact mode is the exact solid: polygon annulus area times height
    polygon = 0.5 * n * math.sin(2 * math.pi / n) * (r_out ** 2 - r_in ** 2)
    vol, com, inertia = mesh_inertia(v32, f, "exact")
    assert vol == pytest.approx(polygon * h, rel=1e-6)
    np.testing.assert_allclose(inertia, exact.inertia_com, rtol=0, atol=1e-12 * np.abs(exact.inertia_com).max())
    # convex: the solid n-gon prism of the outer ring
    vol_c, _, inertia_c = mesh_inertia(v32, f, "convex")
    assert vol_c == pytest.approx(0.5 * n * math.sin(2 * math.pi / n) * r_out ** 2 * h, rel=1e-6)
    # legacy: pyramids from the axis (the apex, by symmetry) are 1/3 area x distance: the
    # outer wall 2/3 A_out h, top and bottom (A_out - A_in) h / 3, and the inner wall's
    # 2/3 A_in h counted positive instead of negative: A_out h + A_in h / 3
    vol_l, _, _ = mesh_inertia(v32, f, "legacy")
    ngon = 0.5 * n * math.sin(2 * math.pi / n) * h
    assert vol_l == pytest.approx(ngon * (r_out ** 2 + r_in ** 2 / 3), rel=1e-6)
    # shell: the surface area of the tube
    area, _, _ = mesh_inertia(v32, f, "shell")
    side = n * 2 * math.sin(math.pi / n) * (r_out + r_in) * h
    assert area == pytest.approx(side + 2 * polygon, rel=1e-6)


def test_legacy_is_exact_on_a_convex_mesh_and_shell_is_the_box_shell():
    from inertia.geometry.shapes import cylinder_mesh

    v, f = cylinder_mesh(0.05, 0.2, sides=16)
    a = mesh_inertia(v, f, "legacy")
    b = mesh_inertia(v, f, "exact")
    assert a[0] == pytest.approx(b[0], rel=1e-12)
    np.testing.assert_allclose(a[2], b[2], rtol=1e-10, atol=1e-18)
    box = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * (0.1, 0.2, 0.3)
    from scipy.spatial import ConvexHull

    hull = ConvexHull(box)
    faces = hull.simplices.copy()
    D, E, F = box[faces[:, 0]], box[faces[:, 1]], box[faces[:, 2]]
    flip = np.einsum("ij,ij->i", np.cross(E - D, F - D), hull.equations[:, :3]) < 0
    faces[flip] = faces[flip][:, ::-1]
    area, com, inertia = mesh_inertia(box, faces, "shell")
    shell = primitives.box((0.2, 0.4, 0.6), density=1.0, kind="shell")
    assert area == pytest.approx(shell.mass, rel=1e-12)
    np.testing.assert_allclose(inertia, shell.inertia_com, rtol=1e-12, atol=1e-18)


def test_principal_descending_is_a_proper_eigenframe():
    rng = np.random.default_rng(0)
    for _ in range(50):
        A = rng.normal(size=(3, 3))
        I = A @ A.T + np.eye(3) * 0.1
        w, R = principal_descending(I)
        assert np.all(np.diff(w) <= 1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)
        np.testing.assert_allclose(R @ np.diag(w) @ R.T, I, atol=1e-5 * np.abs(I).max())


def test_check_warns_when_legacy_inertia_is_far_from_the_solid(tmp_path, tube_stl, capsys):
    import json

    from inertia.cli.main import main

    path = tmp_path / "legacy.xml"
    path.write_text(f"""<mujoco><asset><mesh name="t" file="{tube_stl[0].name}"/>
<mesh name="e" file="{tube_stl[0].name}" inertia="exact"/></asset>
<worldbody><body name="legacy"><freejoint/><geom type="mesh" mesh="t"/></body>
<body name="exact"><freejoint/><geom type="mesh" mesh="e"/></body></worldbody></mujoco>""")
    main(["check", str(path), "--format", "json"])
    links = {lk["name"]: lk for lk in json.loads(capsys.readouterr().out)["links"]}
    assert [w["code"] for w in sev(links["legacy"], "warning")] == ["legacy_mesh_inertia"]
    assert sev(links["exact"], "warning") == [] and sev(links["exact"], "error") == []
    # the numbers in the message are the two computations
    v, f = tube_stl[1], tube_stl[2]
    v32 = np.asarray(v, np.float32).astype(float)
    assert f"{1000 * mesh_inertia(v32, f, 'legacy')[0]:.6g} kg" in sev(links["legacy"], "warning")[0]["message"]
    assert f"{1000 * mesh_inertia(v32, f, 'exact')[0]:.6g} kg" in sev(links["legacy"], "warning")[0]["message"]
