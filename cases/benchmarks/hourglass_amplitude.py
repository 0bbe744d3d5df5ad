#!/usr/bin/env python3
"""Hourglass amplitude of a hexahedral adamss frame (standard library only).

    cases/benchmarks/hourglass_amplitude.py OUT/frames/frame_NNNNN.vtu

Reads the raw-appended VTU that `adamss run` writes (Points = current positions,
displacement = x - X) and prints, over all hexahedra, the largest one-point strain
|F_c - I|_max (F_c the centre gradient, what the virtual hexahedron sees) and the largest
hourglass "strain" max_alpha |q_alpha| / (8 L), q_alpha = sum_a gamma_alpha,a x_a with the
Flanagan-Belytschko base vectors of the reference element (solver/terms/adamss/hourglass.hpp;
L = V0^(1/3)). For an element without hourglassing the second number is ~0; comparable
numbers mean the hourglass patterns carry as much deformation as the physical strain.
"""
import re
import struct
import sys
import zlib

XI = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
H = [[x * y, y * z, z * x, x * y * z] for (x, y, z) in XI]


def appended_block(raw, at):
    """The bytes of one appended array: zlib blocks (header [blocks, block size, last size,
    compressed sizes...], UInt64) as adamss writes them, or one raw block [size] (older frames)."""
    if b'compressor="vtkZLibDataCompressor"' not in raw[:4096]:
        size = struct.unpack_from("<Q", raw, at)[0]
        return raw[at + 8:at + 8 + size]
    blocks = struct.unpack_from("<Q", raw, at)[0]
    sizes = struct.unpack_from("<%dQ" % blocks, raw, at + 24)
    out, pos = [], at + 24 + 8 * blocks
    for size in sizes:
        out.append(zlib.decompress(raw[pos:pos + size]))
        pos += size
    return b"".join(out)


def read_vtu(path):
    raw = open(path, "rb").read()
    start = raw.index(b'<AppendedData encoding="raw">')
    base = raw.index(b"_", start) + 1
    head = raw[:start].decode()
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="([^"]+)" NumberOfComponents="(\d+)" format="appended" '
                         r'offset="(\d+)"/>', head):
        typ, name, _, off = m.group(1), m.group(2), int(m.group(3)), int(m.group(4))
        fmt = {"Float64": "d", "Int64": "q", "Int32": "i", "UInt8": "B"}[typ]
        block = appended_block(raw, base + off)
        arrays[name] = struct.unpack("<%d%s" % (len(block) // struct.calcsize(fmt), fmt), block)
    return arrays


def inv3(m):
    a, b, c = m[0]
    d, e, f = m[1]
    g, h, i = m[2]
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return det, [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
                 [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
                 [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]


def main(path):
    a = read_vtu(path)
    pts, disp, conn = a["Points"], a["displacement"], a["connectivity"]
    ne = len(conn) // 8
    worst_f = worst_h = 0.0
    for e in range(ne):
        nodes = conn[8 * e:8 * e + 8]
        X = [[pts[3 * n + c] for c in range(3)] for n in nodes]  # frames hold the reference points
        x = [[pts[3 * n + c] + disp[3 * n + c] for c in range(3)] for n in nodes]
        dn = [[XI[k][d] / 8.0 for d in range(3)] for k in range(8)]
        jac = [[sum(X[k][i] * dn[k][j] for k in range(8)) for j in range(3)] for i in range(3)]
        det, ji = inv3(jac)
        b = [[sum(dn[k][m] * ji[m][j] for m in range(3)) for j in range(3)] for k in range(8)]  # dN/dX
        length = (8.0 * det) ** (1.0 / 3.0)
        fc = [[sum(x[k][i] * b[k][j] for k in range(8)) for j in range(3)] for i in range(3)]
        worst_f = max(worst_f, max(abs(fc[i][j] - (i == j)) for i in range(3) for j in range(3)))
        for al in range(4):
            hx = [sum(H[k][al] * X[k][i] for k in range(8)) for i in range(3)]
            gam = [H[k][al] - sum(hx[i] * b[k][i] for i in range(3)) for k in range(8)]
            q = [sum(gam[k] * x[k][i] for k in range(8)) for i in range(3)]
            worst_h = max(worst_h, (q[0] ** 2 + q[1] ** 2 + q[2] ** 2) ** 0.5 / (8.0 * length))
    print("%s: elements %d, max |F_c - I| %.4g, max hourglass strain %.4g, ratio %.3g" %
          (path, ne, worst_f, worst_h, worst_h / worst_f if worst_f > 0 else 0.0))


if __name__ == "__main__":
    for p in sys.argv[1:]:
        main(p)
