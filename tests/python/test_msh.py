"""ctest python.msh: gmsh MSH files written by meshio (an independent writer) read by adamss.

The idealised LV (tet6m and hex) goes to ASCII MSH 2.2 and 4.1 through meshio, with the labels as
gmsh physical groups and the endocardial nodes as the physical group of points "endocardium";
adamss.read_mesh of each .msh has every element at the same coordinates, the same labels and the tag, and
`adamss info` reads it."""
import json
import os
import subprocess
import sys
import tempfile

import meshio
import numpy as np

import adamss

exe = sys.argv[2]
work = tempfile.mkdtemp(prefix="adamss-python-msh-")
img = os.path.join(work, "lv.nii.gz")
subprocess.run([exe, "phantom", "lv", "--voxel-size", "2.5mm", "-o", img], check=True, stdout=subprocess.DEVNULL)
for topology, cell_type in (("tet6m", "tetra"), ("hex", "hexahedron")):
    h5 = os.path.join(work, topology + ".h5")
    subprocess.run([exe, "mesh", img, "--solid", "1", "--topology", topology, "-o", h5], check=True,
                   stdout=subprocess.DEVNULL)
    ref = adamss.read_mesh(h5)
    base = np.asarray(ref["node_tags"]["surface:1-2"], dtype=np.int64)  # the endocardium
    labels = np.asarray(ref["labels"])
    conn = np.asarray(ref["connectivity"])
    for fmt in ("gmsh22", "gmsh"):  # meshio: "gmsh22" is MSH 2.2, "gmsh" is 4.1
        m = meshio.Mesh(
            np.asarray(ref["nodes"]),
            [(cell_type, conn), ("vertex", base.reshape(-1, 1))],
            cell_data={"gmsh:physical": [labels, np.full(len(base), 9)],
                       "gmsh:geometrical": [labels, np.full(len(base), 9)]},
            field_data={"myocardium": np.array([1, 3]), "endocardium": np.array([9, 0])},
        )
        if fmt == "gmsh":  # 4.1 with two cell types: meshio needs each node's entity
            m.point_data["gmsh:dim_tags"] = np.tile([3, 1], (len(m.points), 1))
        msh = os.path.join(work, "%s-%s.msh" % (topology, fmt))
        meshio.write(msh, m, file_format=fmt, binary=False)
        got = adamss.read_mesh(msh)
        assert got["element_type"] == ref["element_type"], (topology, fmt)
        gnodes, gconn = np.asarray(got["nodes"]), np.asarray(got["connectivity"])
        assert gconn.shape == conn.shape, (topology, fmt, gconn.shape)
        assert np.allclose(gnodes[gconn], np.asarray(ref["nodes"])[conn], rtol=0, atol=1e-12), (topology, fmt)
        assert np.array_equal(np.asarray(got["labels"]), labels), (topology, fmt)
        tagged = np.sort(gnodes[np.asarray(got["node_tags"]["endocardium"])], axis=0)
        assert np.allclose(tagged, np.sort(np.asarray(ref["nodes"])[base], axis=0), atol=1e-12), (topology, fmt)
        info = json.loads(subprocess.run([exe, "info", msh, "--json"], check=True, capture_output=True,
                                         text=True).stdout)
        assert info["elements"] == len(conn), info
        print("%s via meshio %s: %d nodes, %d cells, %d endocardial nodes" % (topology, fmt, len(gnodes), len(gconn),
                                                                       len(base)))
