"""`inertia fix` edits the source text in place: the output is the input byte for byte except
the numbers it changes, whatever the file's formatting; the repaired files load in MuJoCo (and
Pinocchio), and a tensor that is zero or rounding noise is never "fixed" into another
meaningless number (MuJoCo refuses a moving body whose moments are below mjMINVAL = 1e-15)."""

from __future__ import annotations

import numpy as np
import pytest

from inertia._core.tolerances import SIMULATOR_MIN_VALUE
from inertia.cli.main import main
from inertia.massprops.validity import is_physical
from inertia.robots import nearest_physical_inertia, read_robot
from inertia.robots.fix import fix_file

BAD = np.diag([1.01, 1.11, 100.11])        # fails the triangle inequality
BAD_NEAREST = nearest_physical_inertia(BAD)

# Each file holds one invalid inertial (BAD) between lines marked >>> and <<< (comments), and
# formatting a re-serialising writer would change: quoting, attribute order and line breaks
# inside tags, tabs, CRLF, comments, empty elements without a space, integers written as "0".
URDF = ("<?xml version='1.0' encoding='utf-8'?>\n<!-- header -->\n<robot\n  name='r'  >\n"
        "\t<link name=\"base\"/>\n"
        "  <link  name='arm'>\n"
        "    <!-- >>> -->\n"
        "    <inertial>\n      <origin rpy='0 0 0'   xyz='0 0 0.1'/>\n      <mass value='2'/>\n"
        "      <inertia ixx='1.01' ixy='0' ixz='0'\n               iyy='1.11' iyz='0' izz='100.11'/>\n"
        "    </inertial>\n"
        "    <!-- <<< -->\n"
        "    <visual><geometry><box size='.1 .2 .3'/></geometry></visual>\n"
        "  </link>\n"
        "  <joint name='j' type='revolute'><parent link='base'/><child link='arm'/><axis xyz='0 0 1'/>"
        "<limit lower='-1' upper='1' effort='1' velocity='1'/></joint>\n"
        "</robot>\n")
MJCF = ('<mujoco model="m">\n  <compiler angle="radian"/>\n  <worldbody>\n'
        '    <geom type="plane" size="1 1 .1"/>\n'
        '    <body name="arm" pos="0 0 1">\n      <joint type="hinge" axis="0 0 1"/>\n'
        '      <geom type="box" size=".1 .1 .1"/>\n'
        '      <!-- >>> -->\n'
        "      <inertial pos='0 0 0'  mass=\"2\" diaginertia='1.01 1.11 100.11'/>\n"
        '      <!-- <<< -->\n'
        '    </body>\n  </worldbody>\n</mujoco>\n')
SDF = ('<?xml version="1.0"?>\n<sdf version="1.6">\n  <model name="m">\n    <link name="arm">\n'
       '      <!-- >>> -->\n'
       '      <inertial>\n        <pose>0 0 0 0 0 0</pose>\n        <mass>2</mass>\n        <inertia>\n'
       '          <ixx>1.01</ixx><ixy>0</ixy><ixz>0</ixz>\n          <iyy>1.11</iyy>\n          <iyz>0</iyz>\n'
       '          <izz>100.11</izz>\n        </inertia>\n      </inertial>\n'
       '      <!-- <<< -->\n'
       '      <visual name="v"><geometry><box><size>.1 .2 .3</size></box></geometry></visual>\n'
       '    </link>\n  </model>\n</sdf>\n')
FILES = {"urdf": URDF, "xml": MJCF, "sdf": SDF}


def _variants(text: str) -> dict:
    """The same file with LF, with CRLF, and in Latin-1 with a non-ASCII comment."""
    latin = text.replace("<!-- >>> -->", "<!-- >>> Größe -->", 1)
    if latin.startswith("<?xml"):
        latin = latin.replace("utf-8", "iso-8859-1", 1) if "utf-8" in latin.split("\n", 1)[0] else \
            latin.replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="iso-8859-1"?>', 1)
    else:
        latin = '<?xml version="1.0" encoding="iso-8859-1"?>\n' + latin
    return {"lf": text.encode(), "crlf": text.replace("\n", "\r\n").encode(), "latin1": latin.encode("latin-1")}


def _outside_marks(data: bytes) -> tuple[bytes, bytes]:
    a, b = data.index(b">>>"), data.index(b"<<<")
    return data[:a], data[b:]


def _without_numbers(data: bytes) -> bytes:
    return bytes(c for c in data if chr(c) not in "0123456789.e+-")


@pytest.mark.parametrize("variant", ["lf", "crlf", "latin1"])
@pytest.mark.parametrize("ext", sorted(FILES))
def test_fix_changes_only_the_numbers(tmp_path, ext, variant, capsys):
    src = tmp_path / f"model.{ext}"
    data = _variants(FILES[ext])[variant]
    src.write_bytes(data)
    out = tmp_path / f"fixed.{ext}"
    assert main(["fix", str(src), "-o", str(out)]) == 0
    fixed = out.read_bytes()
    assert src.read_bytes() == data                                 # the input is untouched
    assert _outside_marks(fixed) == _outside_marks(data)           # every byte outside the inertial
    # inside it, only digits changed: the same bytes once the numbers are taken out
    assert _without_numbers(fixed) == _without_numbers(data)
    np.testing.assert_allclose(read_robot(out).links[-1].inertial.inertia_com_inertial, BAD_NEAREST, rtol=1e-15)
    assert main(["check", str(out)]) == 0
    # a second fix has nothing to do: byte-identical, and it says so
    again = tmp_path / f"again.{ext}"
    assert main(["fix", str(out), "-o", str(again)]) == 0
    assert again.read_bytes() == fixed
    assert "byte-identical" in capsys.readouterr().err


@pytest.mark.parametrize("ext", sorted(FILES))
def test_fix_from_geometry_changes_only_the_inertial(tmp_path, ext):
    src = tmp_path / f"model.{ext}"
    data = _variants(FILES[ext])["crlf"]
    src.write_bytes(data)
    out = tmp_path / f"fixed.{ext}"
    report = fix_file(src, out, mode="geometry")
    assert list(report.changed) == ["arm"] and report.remaining == {}
    fixed = out.read_bytes()
    assert _outside_marks(fixed) == _outside_marks(data)
    inside = fixed[fixed.index(b">>>"):fixed.index(b"<<<")]
    assert b"\r\n" in inside and b"\n" not in inside.replace(b"\r\n", b"")   # CRLF kept inside too
    inertial = read_robot(out).links[-1].inertial
    half = np.array([0.05, 0.1, 0.15]) if ext != "xml" else np.array([0.1, 0.1, 0.1])   # the box
    box = inertial.mass / 3 * np.diag([half[1] ** 2 + half[2] ** 2, half[0] ** 2 + half[2] ** 2,
                                       half[0] ** 2 + half[1] ** 2])
    np.testing.assert_allclose(inertial.inertia_com, box, rtol=1e-12, atol=1e-17)


def test_fixed_files_load_in_mujoco_and_pinocchio(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    for ext in ("xml", "urdf"):
        src = tmp_path / f"model.{ext}"
        src.write_text(FILES[ext])
        with pytest.raises(ValueError, match="A \\+ B >= C"):    # MuJoCo refuses the input ...
            mujoco.MjModel.from_xml_path(str(src))
        out = tmp_path / f"fixed.{ext}"
        fix_file(src, out)
        model = mujoco.MjModel.from_xml_path(str(out))             # ... and loads the fix
        np.testing.assert_allclose(np.sort(model.body_inertia[-1]), np.linalg.eigvalsh(BAD_NEAREST), rtol=1e-12)
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(str(tmp_path / "fixed.urdf"))
    np.testing.assert_allclose(model.inertias[-1].inertia, BAD_NEAREST, rtol=1e-12)


def test_valid_files_come_back_identical(tmp_path, capsys, robots):
    for key, (path, _) in robots.good.items():
        out = tmp_path / f"{key}{path.suffix}"
        argv = ["fix", str(path), "-o", str(out)]
        if path.suffix == ".sdf":
            argv += ["--package-path", str(path.parent.parent)]
        assert main(argv) == 0, key
        assert out.read_bytes() == path.read_bytes(), key
        assert "nothing to fix; it is byte-identical" in capsys.readouterr().err


@pytest.mark.parametrize("tensor", ["0 0 0 0 0 0", "2.4e-35 0 0 0 0 0", "1e-41 1e-41 1e-41 0 0 0"])
def test_noise_tensors_are_not_fixed_into_other_noise(tmp_path, capsys, tensor):
    """A 1.34 kg moving link whose tensor is zero or rounding noise: MuJoCo refuses it, and no
    nearest tensor means anything; fix keeps it, says why and exits 1 (it was 'fixed' to 1e-41)."""
    mujoco = pytest.importorskip("mujoco")
    src = tmp_path / "noise.xml"
    src.write_text('<mujoco><worldbody><body name="link"><joint type="hinge"/>'
                   f'<inertial pos="0 0 0" mass="1.34" fullinertia="{tensor}"/></body></worldbody></mujoco>')
    out = tmp_path / "out.xml"
    assert main(["fix", str(src), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "zero or rounding noise" in err and "still fails the check" in err and "--from-geometry" in err
    assert out.read_bytes() == src.read_bytes()
    with pytest.raises(ValueError, match="mjMINVAL|positive eigenvalues"):
        mujoco.MjModel.from_xml_path(str(src))


def test_nearest_never_goes_below_what_mujoco_accepts(tmp_path):
    """A rod-like tensor (one moment zero) of a small link: the relative floor alone (1e-6 of the
    trace) would give 4e-21 kg m^2; the result keeps MuJoCo's absolute floor and loads."""
    mujoco = pytest.importorskip("mujoco")
    I = np.diag([0.0, 2e-15, 2e-15])
    fixed = nearest_physical_inertia(I)
    assert np.linalg.eigvalsh(fixed)[0] >= SIMULATOR_MIN_VALUE and is_physical(fixed)
    src = tmp_path / "rod.xml"
    src.write_text('<mujoco><worldbody><body name="rod"><joint type="hinge"/>'
                   '<inertial pos="0 0 0" mass="1e-3" diaginertia="0 2e-15 2e-15"/></body></worldbody></mujoco>')
    out = tmp_path / "out.xml"
    assert fix_file(src, out).remaining == {}
    mujoco.MjModel.from_xml_path(str(out))


def test_projection_is_the_nearest_point_of_the_physical_set():
    """The active-set projection against a brute-force search over the constraint set."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        w = np.sort(rng.uniform(-1, 3, size=3))
        fixed = np.linalg.eigvalsh(nearest_physical_inertia(np.diag(w)))
        assert is_physical(np.diag(fixed))
        d_fixed = np.sum((fixed - w) ** 2)
        # random physical moments are never nearer (up to rounding)
        floor = max(1e-6 * max(abs(w.sum()), np.abs(w).max()), SIMULATOR_MIN_VALUE)
        # inside the cone by the stated margin, not on its boundary
        assert fixed[0] >= floor * (1 - 1e-9) and fixed[0] + fixed[1] - fixed[2] >= floor * (1 - 1e-6)
        cand = rng.uniform(0, 3, size=(4000, 3))
        cand.sort(axis=1)
        ok = (cand[:, 0] >= floor) & (cand[:, 0] + cand[:, 1] - cand[:, 2] >= floor)
        assert np.min(np.sum((cand[ok] - w) ** 2, axis=1)) >= d_fixed - 1e-12


def test_flip_products_that_finds_nothing_says_so_and_fails(tmp_path, capsys):
    src = tmp_path / "m.sdf"
    src.write_text(SDF)
    out = tmp_path / "o.sdf"
    assert main(["fix", str(src), "-o", str(out), "--flip-products"]) == 1
    err = capsys.readouterr().err
    assert "nothing changed" in err and "still fails the check (1 link)" in err and "triangle inequality" in err
    assert "0 inertials changed" not in err


def test_a_replicated_inertial_is_fixed_once_for_every_copy(tmp_path):
    """MJCF <replicate> makes three bodies of one <inertial> element: one edit fixes all three,
    and MuJoCo loads the result (it refused the input)."""
    mujoco = pytest.importorskip("mujoco")
    src = tmp_path / "rep.xml"
    src.write_text('<mujoco>\n  <worldbody>\n    <replicate count="3" offset="1 0 0">\n      <body name="b">\n'
                   '        <joint type="hinge"/>\n        <inertial pos="0 0 0" mass="1" diaginertia="1.01 1.11 100.11"/>\n'
                   '      </body>\n    </replicate>\n  </worldbody>\n</mujoco>\n')
    out = tmp_path / "out.xml"
    report = fix_file(src, out)
    assert len(report.changed) == 1 and report.remaining == {}
    model = mujoco.MjModel.from_xml_path(str(out))
    for k in (1, 2, 3):
        np.testing.assert_allclose(np.sort(model.body_inertia[k]), np.linalg.eigvalsh(BAD_NEAREST), rtol=1e-12)
