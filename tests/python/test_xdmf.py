"""ctest python.xdmf: the XDMF sidecar that `adamss mesh` writes beside mesh.h5, read by meshio
(Debian python3-meshio, the reader fenicsx and many cardiac pipelines use): the same nodes,
cells, labels, fibre frame and cell fields as adamss.read_mesh, for a tetrahedral and a
hexahedral mesh."""
import os
import subprocess
import sys
import tempfile

import meshio
import numpy as np

import adamss

exe = sys.argv[2]
work = tempfile.mkdtemp(prefix="adamss-python-xdmf-")
img = os.path.join(work, "lv.nii.gz")
f, s, scar = (os.path.join(work, n) for n in ("f.nii.gz", "s.nii.gz", "scar.nii.gz"))
subprocess.run([exe, "phantom", "lv", "--voxel-size", "2.5mm", "-o", img, "--fiber-out", f, "--sheet-out", s,
                "--scar-out", scar], check=True, stdout=subprocess.DEVNULL)
for topology, cell_type in (("tet6m", "tetra"), ("hex", "hexahedron")):
    mesh = os.path.join(work, topology + ".h5")
    subprocess.run([exe, "mesh", img, "--solid", "1", "--topology", topology, "--fiber", f, "--sheet", s,
                    "--cell-field", "scar=" + scar, "-o", mesh], check=True, stdout=subprocess.DEVNULL)
    x = meshio.read(os.path.join(work, topology + ".xdmf"))
    m = adamss.read_mesh(mesh)
    assert np.array_equal(x.points, m["nodes"]), topology
    assert len(x.cells) == 1 and x.cells[0].type == cell_type, x.cells
    assert np.array_equal(x.cells[0].data, m["connectivity"]), topology
    assert np.array_equal(x.cell_data["label"][0].ravel(), m["labels"]), topology
    for v in ("fiber", "sheet", "normal"):
        assert np.array_equal(x.cell_data[v][0], m[v]), (topology, v)
    assert np.array_equal(x.cell_data["scar"][0].ravel(), m["cell_fields"]["scar"]), topology
    assert m["cell_fields"]["scar"].max() == 1.0
    print("%s: %d nodes, %d cells read back through the XDMF sidecar" % (topology, len(x.points), len(x.cells[0].data)))
