"""adamss from Python: run a cardiac-mechanics scene and get its results as numpy arrays.

    import adamss
    r = adamss.run("cases/benchmarks/land-p2.yaml", "out/land-p2")
    r["probes"]["endo_apex"]["final_position"]   # m
    r["globals"]["lv_pressure"], r["globals"]["lv_volume"]   # Pa, m^3 per logged step

A scene is a file path, YAML text, or a dict with the keys of docs/scene-reference.md (values
with units as strings: {"dt": "10 us"}). Errors in the scene raise adamss.InputError (a
ValueError) with the same one-line message as `adamss run`.
"""
import json
import os

from ._core import InputError, IoError, NumericalError  # noqa: F401 (re-exported)
from . import _core

__all__ = ["run", "read_mesh", "InputError", "NumericalError", "IoError"]


def _scene_text(scene):
    """(YAML text, origin path) of a scene given as a dict, a path or YAML text."""
    if isinstance(scene, dict):
        # JSON is YAML: the dict goes through the same parser and checks as a scene file.
        return json.dumps(scene), os.path.join(os.getcwd(), "<dict>.yaml")
    scene = os.fspath(scene)
    if "\n" not in scene and os.path.exists(scene):
        with open(scene, encoding="utf-8") as f:
            return f.read(), os.path.abspath(scene)
    if "\n" not in scene and scene.endswith((".yaml", ".yml")):
        raise InputError("cannot open scene '%s': no such file" % scene)
    return scene, os.path.join(os.getcwd(), "<text>.yaml")


def run(scene, output, cache=None, progress=False):
    """Run `scene` (a dict, a file path or YAML text) with its results in the folder `output`.

    Returns a dict: status ("completed", "unstable", ...), reason, steps, t (s), wall_seconds,
    newton_iterations, linear_iterations, reformations, rejected_steps, time_split {loop,
    forces, jacobians, factorisations, solves: {seconds, calls}, other} (s), frames, warnings,
    output (the folder: frames, series.pvd, globals.csv, run.log), reference_positions /
    positions / velocities / displacement (n x 3 arrays, m and m/s, final state), probes {name:
    {node, reference, final_position, displacement, twist_about_z_deg}}, cavities {name:
    {volume_initial_m3, ... as summary.json}}, volume_relative_change, and globals {column of
    globals.csv: array} (t, kinetic_energy,
    NAME_volume, NAME_pressure, ... one value per logged step, SI).
    `cache` is the mesh-recipe cache folder (default as `adamss run`); `progress` prints the
    progress line on stderr.
    """
    text, origin = _scene_text(scene)
    return _core.run(text, origin, os.fspath(output), "" if cache is None else os.fspath(cache), bool(progress))


def read_mesh(path):
    """Read a mesh file: a mesh.h5 written by `adamss mesh`, a VTK .vtu grid or a gmsh .msh file
    (ASCII 2.2 or 4.1) of tetrahedra or hexahedra, as a dict of numpy arrays.

    element_type ("tet4" or "hex8"), nodes (n x 3, m), connectivity (elements x 4 or 8, VTK
    order), labels, fiber / sheet / normal (elements x 3, when the mesh has fibres), cell_fields
    {name: array}, node_tags {name: node indices}, cavities {name: {volume_m3, closed}}.
    """
    return _core.read_mesh(os.fspath(path))
