"""Robot description files: read, check, repair and write the inertials of URDF, MJCF and SDF.

:func:`read_robot` picks the reader from the file (extension, then root element; ``.xacro``
files are expanded first); :func:`robot_mass_properties` gives the whole robot's (and each
link's) mass properties at a joint configuration;
:func:`check_model` lists each link's problems; :mod:`.fix` writes corrected copies;
:mod:`.writers` prints ready-to-paste inertial blocks.  XML is parsed safely
(:mod:`.xmlsafe`): no entities, no network.  Standard library + NumPy only.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_EXPORTS = {
    "read_robot": "io", "detect_format": "io", "read_urdf": "urdf_sdf", "read_sdf": "urdf_sdf",
    "read_mjcf": "mjcf", "check_model": "check", "CheckReport": "check", "RobotFileError": "xmlsafe",
    "RobotModel": "model", "Link": "model", "Inertial": "model", "Geometry": "model",
    "link_geometry_properties": "geometry", "inertial_block": "writers", "fix_file": "fix",
    "nearest_physical_inertia": "fix", "robot_mass_properties": "whole", "RobotMassProperties": "whole",
    "LinkMass": "whole", "link_poses": "kinematics", "expand_xacro": "io", "Joint": "model",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, ())
