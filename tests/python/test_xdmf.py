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

# adamss reads XDMF too: its own sidecar gives the mesh.h5's arrays exactly, and meshio's XDMF
# (HDF5 and inline XML data, labels as gmsh:physical) gives the same elements and labels.
for topology, cell_type in (("tet6m", "tetra"), ("hex", "hexahedron")):
    m = adamss.read_mesh(os.path.join(work, topology + ".h5"))
    x = adamss.read_mesh(os.path.join(work, topology + ".xdmf"))
    for key in ("nodes", "connectivity", "labels", "fiber", "sheet", "normal"):
        assert np.array_equal(np.asarray(x[key]), np.asarray(m[key])), (topology, key)
    assert np.array_equal(x["cell_fields"]["scar"], m["cell_fields"]["scar"]), topology
    for fmt in ("HDF", "XML"):
        mesh = meshio.Mesh(np.asarray(m["nodes"]), [(cell_type, np.asarray(m["connectivity"]))],
                           cell_data={"gmsh:physical": [np.asarray(m["labels"])],
                                      "scar": [np.asarray(m["cell_fields"]["scar"])]})
        path = os.path.join(work, "%s-meshio-%s.xdmf" % (topology, fmt))
        meshio.xdmf.write(path, mesh, data_format=fmt)
        y = adamss.read_mesh(path)
        assert np.array_equal(np.asarray(y["connectivity"]), np.asarray(m["connectivity"])), (topology, fmt)
        assert np.allclose(np.asarray(y["nodes"]), np.asarray(m["nodes"]), rtol=0, atol=1e-15), (topology, fmt)
        assert np.array_equal(np.asarray(y["labels"]), np.asarray(m["labels"])), (topology, fmt)
        assert np.array_equal(y["cell_fields"]["scar"], m["cell_fields"]["scar"]), (topology, fmt)
    print("%s: adamss reads its sidecar and meshio's XDMF (HDF and XML) back" % topology)
