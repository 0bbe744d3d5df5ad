"""ctest python.api: the adamss package on small inputs. A scene as a dict (JSON through the
scene parser) runs and returns globals as arrays, one per logged step; a mistyped key raises
adamss.InputError with the CLI's message; read_mesh returns the arrays of a mesh.h5 that the
`adamss` executable wrote, consistent with its `info --json`."""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

import adamss

source, exe = sys.argv[1], sys.argv[2]
work = tempfile.mkdtemp(prefix="adamss-python-api-")
scene = {
    "name": "slab",
    "mesh": {"phantom": "slab", "slab_size": [2, 2, 4], "voxel_size": "1 mm", "topology": "tet6m",
             "fibre": [0, 0, 1], "sheet": [1, 0, 0]},
    "materials": [{"name": "m", "labels": [1], "density": "1000 kg/m^3",
                   "terms": [{"virtual_hexahedron": {"law": "neo_hookean", "parameters": {"E": "20 kPa", "nu": 0.3}}}]}],
    "boundary": [{"select": {"region": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}}, "fix": "xyz"},
                 {"select": {"region": {"plane": {"point": [0, 0, "4 mm"], "normal": [0, 0, 1],
                                                  "tolerance": "0.001 mm"}}},
                  "control": {"axis": "z", "displacement": {"ramp": {"to": "0.4 mm", "duration": "1 s"}}}}],
    "integrator": {"type": "static", "dt": "0.25 s"},
    "run": {"t_end": "1 s"},
}
r = adamss.run(scene, os.path.join(work, "out"), cache=os.path.join(work, "cache"))
assert r["status"] == "completed", r
g = r["globals"]
assert len(g["t"]) == r["steps"] + 1 and g["t"][0] == 0 and abs(g["t"][-1] - 1.0) < 1e-12, g["t"]
assert np.all(np.diff(g["t"]) > 0) and np.all(g["step"] == np.arange(r["steps"] + 1)), g["step"]
top = r["reference_positions"][:, 2] > 4e-3 - 1e-9
assert np.allclose(r["displacement"][top, 2], 0.4e-3, atol=1e-12), r["displacement"][top, 2]
assert os.path.exists(os.path.join(r["output"], "run.log"))
# The time split (summary.json time_split_s): one assembly and one factorisation per reformation.
ts = r["time_split"]
assert r["rejected_steps"] == 0, r  # the split counts rejected attempts, reformations does not
assert ts["jacobians"]["calls"] == ts["factorisations"]["calls"] == r["reformations"] > 0, (ts, r["reformations"])
assert ts["solves"]["calls"] >= r["reformations"] and ts["forces"]["calls"] > 0, ts
parts = sum(ts[k]["seconds"] for k in ("forces", "jacobians", "factorisations", "solves"))
assert 0 < parts <= ts["loop"] and abs(ts["other"] - (ts["loop"] - parts)) < 1e-9, ts

bad = json.loads(json.dumps(scene))
bad["run"]["tend"] = 1
try:
    adamss.run(bad, os.path.join(work, "bad"))
    raise AssertionError("a mistyped key was accepted")
except adamss.InputError as e:
    assert "run.tend: unknown key; did you mean 't_end'?" in str(e), str(e)

img, mesh = os.path.join(work, "lv.nii.gz"), os.path.join(work, "lv.h5")
subprocess.run([exe, "phantom", "lv", "--voxel-size", "2.5mm", "-o", img,
                "--fiber-out", os.path.join(work, "f.nii.gz"), "--sheet-out", os.path.join(work, "s.nii.gz")],
               check=True, stdout=subprocess.DEVNULL)
subprocess.run([exe, "mesh", img, "--solid", "1", "--topology", "tet6m", "--fiber", os.path.join(work, "f.nii.gz"),
                "--sheet", os.path.join(work, "s.nii.gz"), "--cavity", "lv=2", "-o", mesh],
               check=True, stdout=subprocess.DEVNULL)
info = json.loads(subprocess.run([exe, "info", mesh, "--json"], check=True, capture_output=True, text=True).stdout)
m = adamss.read_mesh(mesh)
assert m["element_type"] == "tet4"
assert m["nodes"].shape == (info["nodes"], 3)
assert m["connectivity"].shape == (info["elements"], 4)
assert m["connectivity"].min() == 0 and m["connectivity"].max() == info["nodes"] - 1
assert np.allclose(np.linalg.norm(m["fiber"], axis=1), 1.0)
assert abs(m["cavities"]["lv"]["volume_m3"] - info["cavities"]["lv"]["volume_m3"]) < 1e-15
try:
    adamss.read_mesh(os.path.join(work, "missing.h5"))
    raise AssertionError("a missing mesh was read")
except adamss.InputError as e:
    assert "missing.h5" in str(e), str(e)
print("python api: ok")
