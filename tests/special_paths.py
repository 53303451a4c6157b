"""Paths that are not regular files, given to every reader (tests/test_input_paths.py, bench/fuzz.py).

``make_special(kind, path)`` puts a path of one kind at ``path``; ``FAMILIES`` maps each reader
family to ``(name of the special path, setup(folder), read(folder) -> the message it gave)``:
the read returns the text of the refusal (the error, the check's finding, the batch row), or
raises AssertionError when the reader answered without a word.
"""

from __future__ import annotations

import os
import shutil
import socket

#: what a refusal of each kind says (a regular expression)
KINDS = {"fifo": "FIFO", "device": "character device", "socket": "socket", "folder": "folder",
         "loop": "symlink loop", "dangling": "symlink to a path that does not exist",
         "unreadable": "Permission denied", "vanished": "(?i)not found|no such file",
         "growing": "changed while it was read"}

URDF = ('<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" '
        'iyz="0"/></inertial>{geometry}</link></robot>\n')
XACRO = '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">{body}<link name="a"/></robot>\n'
MJCF = '<mujoco>{body}<worldbody><body name="b"><geom size="0.1" mass="1"/></body></worldbody></mujoco>\n'
SDF = '<sdf version="1.7"><world name="w">{body}</world></sdf>\n'
USDA = '#usda 1.0\n(\n    subLayers = [@./sub.usda@]\n)\n'


def make_special(kind: str, path) -> object:
    """Put a ``kind`` path at ``path``; returns what must stay open while it is used (a socket)."""
    path = os.fspath(path)
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "device":
        os.symlink("/dev/zero", path)
    elif kind == "socket":
        sock = socket.socket(socket.AF_UNIX)
        sock.bind(path)
        return sock
    elif kind == "folder":
        os.mkdir(path)
    elif kind == "loop":
        os.symlink(path + ".other", path)
        os.symlink(path, path + ".other")
    elif kind == "dangling":
        os.symlink(path + ".gone", path)
    elif kind == "unreadable":
        with open(path, "w") as fh:
            fh.write("solid x\nendsolid x\n")
        os.chmod(path, 0)
    elif kind == "growing":   # a regular file of size 0 whose reads return text: its size changes as read
        os.symlink("/proc/self/status", path)
    elif kind != "vanished":  # vanished: named (listed, referenced), then gone
        raise ValueError(kind)
    return None


def _error_text(call):
    from inertia.errors import InertiaError

    try:
        call()
    except InertiaError as exc:
        return str(exc)
    raise AssertionError("no refusal")


def _mesh(ext):
    def read(d):
        from inertia.geometry.mesh_io import load_mesh
        return _error_text(lambda: load_mesh(d / f"m{ext}"))
    return f"m{ext}", None, read


def _gltf_setup(d):
    import trimesh

    files = trimesh.exchange.gltf.export_gltf(trimesh.Scene(trimesh.creation.box()))
    for name, data in files.items():
        if name != "gltf_buffer_0.bin":
            (d / name).write_bytes(data)


def _robot(name):
    def read(d):
        from inertia.robots import read_robot
        return _error_text(lambda: read_robot(d / name))
    return read


def _checked(main):
    def read(d):
        from inertia.robots import check_model, read_robot
        rep = check_model(read_robot(d / main))
        text = "\n".join(f.message for link in rep.links for f in [*link.errors, *link.warnings, *link.notes])
        assert text, "no finding"
        return text
    return read


def _write(name, text):
    def setup(d):
        (d / name).write_text(text)
    return setup


def _sdf_model_setup(d):
    (d / "mdl").mkdir()
    (d / "mdl" / "model.sdf").write_text('<sdf version="1.7"><model name="m"><link name="l"/></model></sdf>\n')
    (d / "main.sdf").write_text(SDF.format(body="<include><uri>model://mdl</uri></include>"))


def _usd(name):
    def read(d):
        from inertia.robots.usd.stage import read_stage
        return _error_text(lambda: read_stage(d / name))
    return read


def _row(d, path):
    from inertia.batch.record import process_file
    from inertia.batch.sources import Job

    row = process_file(Job(str(path), density=1000.0))
    assert row["status"] == "error", row
    return row["message"]


def _listed(d):
    from inertia.batch.sources import collect_jobs

    vanished = not os.path.lexists(d / "data" / "m.stl")
    if vanished:
        shutil.copy(d / "a.stl", d / "data" / "m.stl")
    path = next(j.path for j in collect_jobs([d / "data"], density=1000.0) if j.path.endswith("m.stl"))
    if vanished:
        os.remove(path)   # between the listing and the reading
    return _row(d, path)


def _listed_setup(d):
    (d / "data").mkdir()
    (d / "a.stl").write_bytes(b"solid a\nendsolid a\n")
    (d / "data" / "b.stl").write_bytes(b"solid b\nendsolid b\n")


def _manifest_rows(d):
    from inertia.batch.sources import collect_jobs

    jobs = collect_jobs([d / "list.csv"])
    return _row(d, jobs[0].path)


def _manifest(d):
    from inertia.batch.sources import collect_jobs
    return _error_text(lambda: collect_jobs([d / "list.csv"]))


def _gltf(d):
    from inertia.geometry.mesh_io import load_mesh
    return _error_text(lambda: load_mesh(d / "model.gltf"))


def _dask_config(d):
    from inertia.cli.batch import _scheduler_from_config
    return _error_text(lambda: _scheduler_from_config(d / "dask.yaml"))


#: family -> (the special path's name (relative to the folder), setup(folder) or None, read(folder))
FAMILIES = {
    **{f"mesh file {ext}": _mesh(ext) for ext in (".stl", ".obj", ".ply", ".off", ".glb", ".gltf", ".dae")},
    "glTF buffer": ("gltf_buffer_0.bin", _gltf_setup, _gltf),
    "URDF": ("r.urdf", None, _robot("r.urdf")),
    "SDF": ("r.sdf", None, _robot("r.sdf")),
    "MJCF": ("r.xml", None, _robot("r.xml")),
    "xacro": ("r.urdf.xacro", None, _robot("r.urdf.xacro")),
    "xacro include": ("inc.xacro", _write("main.urdf.xacro", XACRO.format(
        body='<xacro:include filename="inc.xacro"/>')), _robot("main.urdf.xacro")),
    "xacro load_yaml": ("p.yaml", _write("main.urdf.xacro", XACRO.format(
        body="<xacro:property name=\"p\" value=\"${xacro.load_yaml('p.yaml')}\"/><link name=\"l${p}\"/>")),
        _robot("main.urdf.xacro")),
    "MJCF include": ("inc.xml", _write("main.xml", MJCF.format(body='<include file="inc.xml"/>')),
                     _robot("main.xml")),
    "SDF include": ("inc.sdf", _write("main.sdf", SDF.format(body="<include><uri>inc.sdf</uri></include>")),
                    _robot("main.sdf")),
    "SDF model.config": ("mdl/model.config", _sdf_model_setup, _robot("main.sdf")),
    "robot mesh reference": ("m.stl", _write("r.urdf", URDF.format(
        geometry='<collision><geometry><mesh filename="m.stl"/></geometry></collision>')), _checked("r.urdf")),
    "USD stage": ("r.usda", None, _usd("r.usda")),
    "USD sublayer": ("sub.usda", _write("main.usda", USDA), _usd("main.usda")),
    "batch source": ("m.stl", None, lambda d: _row(d, d / "m.stl")),
    "batch folder listing": ("data/m.stl", _listed_setup, _listed),
    "batch manifest": ("list.csv", None, _manifest),
    "batch manifest row": ("m.stl", _write("list.csv", "path\nm.stl\n"), _manifest_rows),
    "Dask configuration": ("dask.yaml", None, _dask_config),
}

#: what a family says instead of the kind's words, where its format gives the path another meaning
EXPECTED = {("SDF include", "folder"): "model folder",            # an included folder is a model folder
            ("SDF model.config", "vanished"): None,                # a model folder without one: its model.sdf
            ("batch folder listing", "folder"): None,              # a folder named m.stl is searched, not read
            ("USD sublayer", "vanished"): None,                    # usd-core composes without it, with a warning
            ("USD stage", "growing"): "cannot open the stage",     # checked by kind, then read by usd-core
            ("USD sublayer", "growing"): "cannot open the stage"}


def dependencies(family: str) -> tuple:
    """Modules a family needs (the test skips it without them)."""
    if family in ("mesh file .off", "mesh file .glb", "mesh file .gltf", "glTF buffer"):
        return ("trimesh",)
    if family == "mesh file .dae":
        return ("trimesh", "collada")
    if family.startswith("xacro"):
        return ("xacro",)
    if family.startswith("USD"):
        return ("pxr",)
    if family.startswith("batch") or family == "Dask configuration":
        return ("pandas", "dask", "yaml")
    return ()
